// The plain HTTP session: reads a request, screens its headers (docs/deployment.md), answers the
// built-in routes on the I/O thread and hands the router's to the handler, probe or control pool.
#include <boost/asio/dispatch.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/websocket.hpp>

#include <array>
#include <deque>

#include "server/session_internal.hpp"
#include "uavcover/error.hpp"

namespace uavcover::server::detail {

namespace {

class HttpSession : public Session, public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket&& socket, Core& core) : stream_(std::move(socket)), core_(core) {}
  ~HttpSession() override { core_.remove_session(reg_); }

  void start() {
    reg_ = core_.add_session(weak_from_this());
    if (reg_ == 0) return;
    net::dispatch(stream_.get_executor(),
                  beast::bind_front_handler(&HttpSession::do_read, shared_from_this()));
  }

  void shutdown() override {
    net::post(stream_.get_executor(), [self = shared_from_this()] {
      self->closed_ = true;
      beast::error_code ec;
      self->stream_.socket().shutdown(tcp::socket::shutdown_both, ec);
      self->stream_.close();
    });
  }

 private:
  void do_read() {
    if (closed_) return;
    parser_.emplace();
    parser_->body_limit(core_.cfg.max_body);
    parser_->header_limit(kHeaderLimit);
    stream_.expires_after(first_ ? core_.cfg.header_timeout : core_.cfg.idle_timeout);
    http::async_read_header(stream_, buffer_, *parser_,
                            beast::bind_front_handler(&HttpSession::on_header, shared_from_this()));
  }

  /// A request that cannot be read any further: answer and close.
  bool read_failed(beast::error_code ec) {
    if (ec == http::error::end_of_stream || ec == beast::error::timeout ||
        ec == net::error::operation_aborted || ec == net::error::connection_reset || ec == net::error::eof ||
        closed_) {
      close_quietly();
      return true;
    }
    if (ec == http::error::body_limit) {
      reply_and_close(413, "body",
                      fmt::format("the request body is larger than {} bytes", core_.cfg.max_body));
    } else if (ec == http::error::header_limit) {
      reply_and_close(431, "headers",
                      fmt::format("the request headers are larger than {} bytes", kHeaderLimit));
    } else if (ec == http::error::partial_message) {
      close_quietly();
    } else if (ec.category() == http::make_error_code(http::error::bad_target).category()) {
      reply_and_close(400, "", "malformed HTTP request: " + ec.message());
    } else {
      close_quietly();
    }
    return true;
  }

  void on_header(beast::error_code ec, std::size_t) {
    if (ec) {
      read_failed(ec);
      return;
    }
    start_ = std::chrono::steady_clock::now();
    stream_.expires_after(core_.cfg.idle_timeout);
    const auto& req = parser_->get();
    // refused on the headers alone, before any of the body is read; the connection then closes
    if (auto refusal = screen(req)) {
      reply_and_close(refusal->status, refusal->field, refusal->what(), std::move(refusal->headers));
      return;
    }
    if (beast::iequals(req[http::field::expect], "100-continue") && !parser_->is_done()) {
      auto cont = std::make_shared<http::response<http::empty_body>>(http::status::continue_, req.version());
      http::async_write(stream_, *cont,
                        [self = shared_from_this(), cont](beast::error_code ec2, std::size_t) {
                          if (ec2) return self->close_quietly();
                          self->read_body();
                        });
      return;
    }
    read_body();
  }

  /// The checks a request's headers must pass (docs/deployment.md): one Host naming this server (400,
  /// 421), an Origin of this server or --cors-origin (403), no transfer coding but chunked (501) and
  /// no content coding (415), the token (401), and a JSON body on the API (415).
  std::optional<HttpError> screen(const http::request_parser<http::string_body>::value_type& req) const {
    const auto& cfg = core_.cfg;
    const std::string_view target = sv(req.target());
    std::size_t hosts = 0;
    std::string host;
    for (const auto& f : req)
      if (f.name() == http::field::host) {
        ++hosts;
        host = std::string(sv(f.value()));
      }
    if (hosts > 1) return HttpError(400, "host", "the request has more than one Host header");
    if (hosts == 0 && req.version() >= 11)
      return HttpError(400, "host", "an HTTP/1.1 request needs a Host header");
    // the absolute form's authority takes the place of Host (RFC 9112 3.2.2)
    const std::string authority = target_authority(target).value_or(host);
    if ((hosts > 0 || !authority.empty()) && !host_allowed(authority, core_.host_policy))
      return HttpError(421, "host",
                       "this server does not answer for host \"" + authority.substr(0, 100) +
                           "\" (uavcover serve --allowed-host NAME adds a name)");
    std::size_t origins = 0;
    std::string origin;
    for (const auto& f : req)
      if (f.name() == http::field::origin) {
        ++origins;
        origin = std::string(sv(f.value()));
      }
    if (origins > 1 || (origins == 1 && !origin_allowed(origin, authority, cfg.cors_origin)))
      return HttpError(403, "origin",
                       "requests from origin \"" + origin.substr(0, 100) +
                           "\" are not allowed (uavcover serve --cors-origin ORIGIN allows one)");
    std::string codings;
    std::size_t te_fields = 0;
    for (const auto& f : req)
      if (f.name() == http::field::transfer_encoding) {
        ++te_fields;
        codings += (codings.empty() ? "" : ",") + std::string(sv(f.value()));
      }
    if (te_fields > 0) {
      if (te_fields > 1 || lower(trim(codings)) != "chunked")
        return HttpError(
            501, "transfer-encoding",
            "only Transfer-Encoding: chunked is supported, got \"" + codings.substr(0, 100) + "\"");
      if (req.count(http::field::content_length) > 0)
        return HttpError(400, "transfer-encoding",
                         "a request must not have both Transfer-Encoding and Content-Length");
    }
    if (req.count(http::field::content_encoding) > 0) {
      std::string encodings;
      for (const auto& f : req)
        if (f.name() == http::field::content_encoding)
          encodings += (encodings.empty() ? "" : ",") + std::string(sv(f.value()));
      if (lower(trim(encodings)) != "identity")
        return HttpError(
            415, "content-encoding",
            "request bodies must not be compressed (Content-Encoding: \"" + encodings.substr(0, 100) + "\")");
    }
    Request probe;
    bool decoded = true;
    try {
      decode_target(target, probe);
    } catch (const HttpError&) {
      decoded = false;  // answered 400 once read
    }
    const std::string method(sv(req.method_string()));
    const bool open_route = decoded && (method == "GET" || method == "HEAD") &&
                            (probe.path == "/healthz" || probe.path == "/readyz");
    const bool preflight = cfg.cors_origin && method == "OPTIONS";
    const bool has_body = te_fields > 0 || (parser_->content_length() && *parser_->content_length() > 0);
    // with a body: 401 before reading it (and the connection closes); without, the answer keeps it open
    if (cfg.token && has_body && !open_route && !preflight) {
      const auto auth = req[http::field::authorization];
      probe.headers["authorization"] = std::string(sv(auth));
      if (auth.empty()) probe.headers.clear();
      if (!core_.authorized(probe)) {
        HttpError e(401, "authorization", "missing or wrong bearer token (Authorization: Bearer <token>)");
        e.headers.emplace_back("WWW-Authenticate", "Bearer");
        return e;
      }
    }
    // the uploads (multipart_route: the importer's file, the photos' heads) take multipart/form-data (they
    // store nothing and answer JSON; a foreign page is refused by the Origin check above, 403)
    const std::string media = media_type(sv(req[http::field::content_type]));
    const bool upload = multipart_route(method, probe.path) && media == "multipart/form-data";
    if (has_body && decoded && probe.path.rfind("/api/", 0) == 0 && media != "application/json" && !upload)
      return HttpError(415, "body",
                       req.count(http::field::content_type) > 0
                           ? "expected Content-Type application/json, got \"" +
                                 std::string(sv(req[http::field::content_type])).substr(0, 100) + "\""
                           : std::string("a request body needs Content-Type: application/json"));
    return std::nullopt;
  }

  void read_body() {
    http::async_read(stream_, buffer_, *parser_,
                     beast::bind_front_handler(&HttpSession::on_body, shared_from_this()));
  }

  void on_body(beast::error_code ec, std::size_t) {
    if (ec) {
      read_failed(ec);
      return;
    }
    process();
  }

  enum class Dispatched { Answered, Deferred, Stream };

  void process() {
    auto& breq = parser_->get();
    Request req;
    req.method = std::string(breq.method_string());
    const auto client_id = breq["x-request-id"];
    req.request_id = valid_request_id(sv(client_id)) ? std::string(sv(client_id)) : core_.next_request_id();
    for (const auto& f : breq) {
      const std::string name = lower(sv(f.name_string()));
      auto [it, fresh] = req.headers.emplace(name, std::string(f.value()));
      if (!fresh) it->second += ", " + std::string(f.value());
    }
    const bool keep = breq.keep_alive();
    const unsigned version = breq.version();
    const std::string method = req.method;
    head_ = method == "HEAD";
    std::string route = "unmatched";
    Response res;
    try {
      decode_target(sv(breq.target()), req);
      req.body = std::move(breq.body());
      if (dispatch(req, breq, route, res) != Dispatched::Answered) return;  // a stream, or the pool answers
    } catch (const HttpError& e) {
      res = Response::error(e.status, e.field, e.what());
      res.headers.insert(res.headers.end(), e.headers.begin(), e.headers.end());
    } catch (const InputError& e) {
      res = Response::error(422, e.field(), e.what());
    } catch (const std::exception& e) {
      spdlog::error("request {} {} {}: {}", req.request_id, req.method, route, e.what());
      res = Response::error(500, "", "internal error");
    }
    answer(req.request_id, method, route, req.path, std::move(res), version, keep);
  }

  void answer(const std::string& id, const std::string& method, const std::string& route,
              const std::string& path, Response res, unsigned version, bool keep) {
    if (res.status == 401) res.headers.emplace_back("WWW-Authenticate", "Bearer");
    const int status = res.status;
    auto out = to_beast(std::move(res), version, keep, id, core_, head_);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    core_.log_request(id, method, route, path, status, seconds, out.body().size());
    send(std::move(out), keep);
  }

  /// `fn(req)` with every error as its JSON answer (handlers off the I/O threads must not throw).
  static Response run_guarded(const std::function<Response(const Request&)>& fn, const Request& req,
                              const std::string& route) {
    try {
      return fn(req);
    } catch (const HttpError& e) {
      Response r = Response::error(e.status, e.field, e.what());
      r.headers.insert(r.headers.end(), e.headers.begin(), e.headers.end());
      return r;
    } catch (const InputError& e) {
      return Response::error(422, e.field(), e.what());
    } catch (const std::exception& e) {
      spdlog::error("request {} {} {}: {}", req.request_id, req.method, route, e.what());
      return Response::error(500, "", "internal error");
    } catch (...) {
      spdlog::error("request {} {} {}: unknown exception", req.request_id, req.method, route);
      return Response::error(500, "", "internal error");
    }
  }

  /// Runs `fn(req)` on `pool` and answers on this session's strand. Deferred; Answered with 503 (and
  /// `req` untouched) when the pool has `max` requests already or the server stops.
  Dispatched defer(net::thread_pool& pool, std::atomic<std::size_t>& load, std::size_t max, Request& req,
                   const std::string& route, unsigned version, bool keep,
                   std::function<Response(const Request&)> fn, Response& res) {
    auto shared = std::make_shared<Request>(std::move(req));
    const std::string method = std::string(parser_->get().method_string());
    auto self = shared_from_this();
    const bool posted = core_.post_bounded(
        pool, load, max, [self, shared, fn, route, method, version, keep](Core::PoolSlot& slot) {
          Response out = run_guarded(fn, *shared, route);
          slot.release();  // before the answer: a client that has it may ask again at once
          net::post(self->stream_.get_executor(), [self, shared, out = std::move(out), route, method, version,
                                                   keep]() mutable {
            self->answer(shared->request_id, method, route, shared->path, std::move(out), version, keep);
          });
        });
    if (posted) return Dispatched::Deferred;
    req = std::move(*shared);
    res = Response::error(503, "", "the server is busy; try again later");
    res.headers.emplace_back("Retry-After", "1");
    return Dispatched::Answered;
  }

  /// Answers `req` into `res` (Answered), hands it to the handler pool (Deferred) or the connection to
  /// an event stream (Stream). Only cheap answers are made here, on the I/O thread.
  Dispatched dispatch(Request& req, const http::request<http::string_body>& breq, std::string& route,
                      Response& res) {
    const auto& cfg = core_.cfg;
    const unsigned version = breq.version();
    const bool keep = breq.keep_alive();
    if (cfg.cors_origin && req.method == "OPTIONS") {
      route = "preflight";
      res.status = 204;
      res.headers = {{"Access-Control-Allow-Methods", "GET, HEAD, POST, PUT, DELETE, OPTIONS"},
                     {"Access-Control-Allow-Headers", "Authorization, Content-Type, X-Request-Id"},
                     {"Access-Control-Max-Age", "600"}};
      return Dispatched::Answered;
    }
    if (head_) req.method = "GET";  // HEAD: the GET's answer without its body (to_beast)
    if (req.method == "GET" && req.path == "/healthz") {
      route = "/healthz";
      res = Response::json(200, {{"status", "ok"}});
      return Dispatched::Answered;
    }
    if (req.method == "GET" && req.path == "/readyz") {
      route = "/readyz";
      auto check = cfg.ready_check;
      return defer(
          core_.probes, core_.probe_load, kMaxPendingProbes, req, route, version, keep,
          [check](const Request& r) {
            bool ready = true;
            try {
              ready = !check || check();
            } catch (const std::exception& e) {
              spdlog::warn("request {}: readiness check failed: {}", r.request_id, e.what());
              ready = false;
            }
            Response out = ready ? Response::json(200, {{"status", "ready"}})
                                 : Response::json(503, {{"status", "unavailable"}});
            if (!ready) out.headers.emplace_back("Retry-After", "5");
            return out;
          },
          res);
    }
    if (!core_.authorized(req)) {
      res = Response::error(401, "authorization",
                            "missing or wrong bearer token (Authorization: Bearer <token>)");
      return Dispatched::Answered;
    }
    if (req.method == "GET" && req.path == "/metrics") {
      route = "/metrics";
      return defer(
          core_.probes, core_.probe_load, kMaxPendingProbes, req, route, version, keep,
          [](const Request&) {
            Response out;
            out.content_type = kMetricsContentType;
            out.body = metrics().render();  // the job counts come from the database
            return out;
          },
          res);
    }
    if (req.method == "GET" && req.path == kEventsPath) {
      route = kEventsPath;
      if (head_) {
        res = Response::error(405, "", "method HEAD is not allowed on the event stream; allowed: GET");
        res.headers.emplace_back("Allow", "GET");
        return Dispatched::Answered;
      }
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
      if (websocket::is_upgrade(breq)) {
        core_.log_request(req.request_id, req.method, route, req.path, 101, seconds, 0);
        stream_.expires_never();
        start_websocket(stream_.release_socket(), core_, parser_->release(), req.request_id);
        return Dispatched::Stream;
      }
      const auto ids = parse_jobs_param(req, static_cast<std::size_t>(std::max(0, cfg.max_subscriptions)));
      core_.log_request(req.request_id, req.method, route, req.path, 200, seconds, 0);
      stream_.expires_never();
      start_sse(stream_.release_socket(), core_, breq.version(), ids, req.request_id);
      return Dispatched::Stream;
    }
    const bool api = req.path.rfind("/api/", 0) == 0;
    if (req.method == "GET" && !api) {
      const std::string key = req.path == "/" ? "/index.html" : req.path;
      if (const auto it = cfg.static_files.find(key); it != cfg.static_files.end()) {
        route = "static";
        res.status = 200;
        res.content_type = it->second.media_type;
        res.body = it->second.bytes;
        return Dispatched::Answered;
      }
    }
    auto match = core_.router.match(req.method, req.path);
    if (match.handler != nullptr) {
      route = match.route;
      req.params = std::move(match.params);
      const Handler* handler = match.handler;  // the router outlives the server
      if (is_flight_control(req.method, route))
        return defer(
            core_.control, core_.control_load, kMaxPendingControls, req, route, version, keep,
            [handler](const Request& r) { return (*handler)(r); }, res);
      return defer(
          core_.handlers, core_.handler_load, std::max<std::size_t>(1, cfg.max_pending), req, route, version,
          keep, [handler](const Request& r) { return (*handler)(r); }, res);
    }
    if (!match.allowed.empty()) {
      std::vector<std::string> allowed = match.allowed;
      if (std::find(allowed.begin(), allowed.end(), "GET") != allowed.end()) allowed.emplace_back("HEAD");
      std::sort(allowed.begin(), allowed.end());
      allowed.erase(std::unique(allowed.begin(), allowed.end()), allowed.end());
      std::string list;
      for (const auto& m : allowed) list += (list.empty() ? "" : ", ") + m;
      const std::string shown = head_ ? std::string("HEAD") : req.method.substr(0, 20);
      res = Response::error(405, "", "method " + shown + " is not allowed here; allowed: " + list);
      res.headers.emplace_back("Allow", list);
      return Dispatched::Answered;
    }
    if (req.method == "GET" && req.path == "/") {
      route = "index";
      res.status = 200;
      res.content_type = "text/html; charset=utf-8";
      res.body = kIndexPage;
      return Dispatched::Answered;
    }
    res = Response::error(404, "", "no such resource: " + req.path.substr(0, 200));
    return Dispatched::Answered;
  }

  void send(StringResponse&& res, bool keep) {
    auto sp = std::make_shared<StringResponse>(std::move(res));
    stream_.expires_after(core_.cfg.idle_timeout);
    http::async_write(stream_, *sp, [self = shared_from_this(), sp, keep](beast::error_code ec, std::size_t) {
      if (ec) return self->close_quietly();
      if (!keep || self->closed_) return self->linger_close();
      self->first_ = false;
      self->do_read();
    });
  }

  /// An error answer outside the handlers (413, 431, 400), then the connection closes.
  void reply_and_close(int status, const std::string& field, const std::string& message,
                       std::vector<std::pair<std::string, std::string>> headers = {}) {
    const auto id = core_.next_request_id();
    const unsigned version = parser_ && parser_->is_header_done() ? parser_->get().version() : 11;
    const std::string method =
        parser_ && parser_->is_header_done() ? std::string(parser_->get().method_string()) : "";
    Response r = Response::error(status, field, message);
    r.headers = std::move(headers);
    auto out = to_beast(std::move(r), version, false, id, core_, method == "HEAD");
    core_.log_request(id, method, "unmatched", "", status, 0.0, out.body().size());
    send(std::move(out), false);
  }

  /// Half-closes, then reads what the client still sends (bounded) so it gets the answer, not a reset.
  void linger_close() {
    beast::error_code ec;
    stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
    if (ec) return close_quietly();
    stream_.expires_after(std::chrono::seconds(2));
    drain();
  }

  void drain() {
    stream_.async_read_some(net::buffer(scratch_),
                            [self = shared_from_this()](beast::error_code ec, std::size_t n) {
                              self->drained_ += n;
                              if (ec || self->drained_ > kDrainBytes) return self->close_quietly();
                              self->drain();
                            });
  }

  void close_quietly() {
    beast::error_code ec;
    stream_.socket().shutdown(tcp::socket::shutdown_both, ec);
    stream_.close();
  }

  beast::tcp_stream stream_;
  Core& core_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::array<char, 4096> scratch_{};
  std::size_t drained_ = 0;
  bool first_ = true;
  bool closed_ = false;
  bool head_ = false;  ///< the request being answered is a HEAD
  std::uint64_t reg_ = 0;
};
}  // namespace

void start_http(tcp::socket&& socket, Core& core) {
  std::make_shared<HttpSession>(std::move(socket), core)->start();
}

}  // namespace uavcover::server::detail
