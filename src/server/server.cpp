// Boost.Beast sessions behind HttpServer: one strand per connection, handlers run on the I/O threads.
#include "server/server.hpp"

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <boost/asio/dispatch.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/thread_pool.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <condition_variable>
#include <deque>
#include <random>
#include <set>
#include <thread>

#include "server/metrics.hpp"
#include "uavcover/error.hpp"

namespace uavcover::server {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

namespace {

constexpr std::size_t kHeaderLimit = 16 * 1024;
constexpr std::size_t kWsMessageMax = 64 * 1024;
constexpr std::size_t kMaxPendingMessages = 1000;
constexpr std::size_t kMaxConnections = 10000;
constexpr std::size_t kMaxPendingProbes = 16;    // /readyz and /metrics waiting for the probe thread
constexpr std::size_t kMaxPendingControls = 32;  // flight controls waiting for the control thread

/// A live flight's controls: `POST /api/v1/flights/{id}/commands`, `GET` and `DELETE
/// /api/v1/flights/{id}` (the router's route pattern).
bool is_flight_control(const std::string& method, const std::string& route) {
  static const std::string flight = "/api/v1/flights/{id}";
  return (route == flight && (method == "GET" || method == "DELETE")) ||
         (route == flight + "/commands" && method == "POST");
}
constexpr std::size_t kDrainBytes = std::size_t{64} << 20;  // bounded by the 2 s linger too
constexpr const char* kEventsPath = "/api/v1/events";

const char* const kIndexPage =
    "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>uavcover</title></head>\n"
    "<body><h1>uavcover</h1><p>The multi-UAV coverage planner's HTTP API.</p>\n"
    "<ul><li><a href=\"/api/v1/openapi.json\">OpenAPI description (/api/v1/openapi.json)</a></li>\n"
    "<li>docs/api.md in the source tree: the guide</li>\n"
    "<li><a href=\"/healthz\">/healthz</a>, <a href=\"/metrics\">/metrics</a></li></ul></body></html>\n";

// ---- small text helpers ----

std::string_view sv(beast::string_view s) { return {s.data(), s.size()}; }

bool valid_request_id(std::string_view id) {
  if (id.empty() || id.size() > 64) return false;
  return std::all_of(id.begin(), id.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
  });
}

std::string trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return "";
  return std::string(s.substr(first, s.find_last_not_of(" \t") - first + 1));
}

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

/// Header values from handlers may carry user text (file names): no CR, LF or NUL gets through.
std::string header_safe(std::string_view v) {
  std::string out;
  out.reserve(v.size());
  for (const char c : v)
    if (c != '\r' && c != '\n' && c != '\0') out += c;
  return out;
}

/// Methods as metric labels: unknown ones share one label, so clients cannot grow the registry.
std::string method_label(const std::string& m) {
  static const std::set<std::string> known{"GET", "POST", "PUT", "DELETE", "PATCH", "HEAD", "OPTIONS"};
  return known.count(m) ? m : "other";
}

std::string utc_now() {
  const auto now = std::chrono::system_clock::now();
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  return fmt::format("{:%Y-%m-%dT%H:%M:%S}.{:03d}Z", fmt::gmtime(std::chrono::system_clock::to_time_t(now)),
                     static_cast<int>(ms));
}

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// ---- the state every session shares ----

class Session {
 public:
  virtual ~Session() = default;
  /// Closes the connection (from any thread): posted to the session's strand.
  virtual void shutdown() = 0;
};

struct Core {
  Core(ServerConfig c, Router& r, EventSource& events)
      : cfg(std::move(c)),
        router(r),
        hub(events, cfg.event_poll),
        handlers(static_cast<std::size_t>(std::max(1, cfg.handler_threads))),
        probes(1),
        control(1) {
    std::random_device rd;
    id_counter = (static_cast<std::uint64_t>(rd()) << 32) ^ rd();
    host_policy.listen_host = parse_listen(cfg.listen).host;
    host_policy.allowed = cfg.allowed_hosts;
  }

  ServerConfig cfg;
  Router& router;
  EventHub hub;
  std::atomic<std::uint64_t> id_counter{0};

  std::mutex mutex;
  std::condition_variable changed;
  bool stopping = false;
  std::uint64_t next_session = 1;
  std::map<std::uint64_t, std::weak_ptr<Session>> sessions;

  HostPolicy host_policy;  ///< its port is set once the acceptor is bound

  // The API handlers and the operations probes (/readyz, /metrics: database calls) run here, never on
  // the I/O threads, so a slow validation or a locked database cannot hold /healthz or other
  // connections. Declared last: destroyed (joined) first.
  net::thread_pool handlers;
  net::thread_pool probes;
  /// A live flight's controls (its commands: abort, land, RTL, ...; its DELETE and GET) run on their own
  /// thread, so that a validation or a plan read holding every handler thread cannot delay an abort.
  net::thread_pool control;
  std::atomic<std::size_t> handler_load{0};  ///< requests queued for or running on `handlers`
  std::atomic<std::size_t> probe_load{0};
  std::atomic<std::size_t> control_load{0};
  std::mutex pool_mutex;
  bool pools_closed = false;  ///< set before the pools are joined: nothing is posted afterwards

  /// Posts `work` to `pool` unless `load` would exceed `max` or the server stops; false then.
  template <class Work>
  bool post_bounded(net::thread_pool& pool, std::atomic<std::size_t>& load, std::size_t max, Work&& work) {
    const std::lock_guard lock(pool_mutex);
    if (pools_closed) return false;
    if (load.fetch_add(1) >= max) {
      load.fetch_sub(1);
      return false;
    }
    net::post(pool, [&load, work = std::forward<Work>(work)]() mutable {
      struct Done {
        std::atomic<std::size_t>& load;
        ~Done() { load.fetch_sub(1); }
      } done{load};
      work();
    });
    return true;
  }

  /// Waits for every posted request to be answered (the I/O threads must still run).
  void drain_pools() {
    {
      const std::lock_guard lock(pool_mutex);
      pools_closed = true;
    }
    handlers.join();
    probes.join();
    control.join();
  }

  std::string next_request_id() { return fmt::format("{:016x}", splitmix64(id_counter.fetch_add(1))); }

  /// 0 when the server stops or is full: the caller closes the connection.
  std::uint64_t add_session(std::weak_ptr<Session> s) {
    const std::lock_guard lock(mutex);
    if (stopping || sessions.size() >= kMaxConnections) return 0;
    const auto id = next_session++;
    sessions.emplace(id, std::move(s));
    return id;
  }
  void remove_session(std::uint64_t id) {
    if (id == 0) return;
    {
      const std::lock_guard lock(mutex);
      sessions.erase(id);
    }
    changed.notify_all();
  }

  bool authorized(const Request& req) const {
    if (!cfg.token) return true;
    const auto h = req.header("authorization");
    if (!h || h->size() < 7 || lower(h->substr(0, 7)) != "bearer ") return false;
    return constant_time_equals(h->substr(7), *cfg.token);
  }

  void add_cors(std::vector<std::pair<std::string, std::string>>& headers) const {
    if (!cfg.cors_origin) return;
    headers.emplace_back("Access-Control-Allow-Origin", *cfg.cors_origin);
    headers.emplace_back("Vary", "Origin");
    headers.emplace_back("Access-Control-Expose-Headers",
                         "X-Request-Id, Location, Retry-After, Content-Disposition");
  }

  void log_request(const std::string& id, const std::string& method, const std::string& route,
                   const std::string& path, int status, double seconds, std::size_t bytes) const {
    metrics().observe_request(route, method_label(method), status, seconds);
    const double ms = seconds * 1000.0;
    if (cfg.log_json) {
      const nlohmann::json line{
          {"time", utc_now()}, {"level", "info"}, {"msg", "request"}, {"request_id", id},  {"method", method},
          {"route", route},    {"path", path},    {"status", status}, {"duration_ms", ms}, {"bytes", bytes}};
      spdlog::info("{}", line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    } else {
      spdlog::info("{} {} {} {} {:.1f}ms {}B", id, method, route, status, ms, bytes);
    }
  }
};

using StringResponse = http::response<http::string_body>;

/// `head`: the answer to a HEAD request, the GET's headers (its Content-Length too) without the body.
StringResponse to_beast(Response&& r, unsigned version, bool keep_alive, const std::string& request_id,
                        const Core& core, bool head = false) {
  StringResponse res;
  res.version(version);
  res.result(static_cast<unsigned>(std::clamp(r.status, 100, 599)));
  res.set(http::field::server, "uavcover");
  if (r.status != 204 && r.status != 304) res.set(http::field::content_type, header_safe(r.content_type));
  auto headers = std::move(r.headers);
  core.add_cors(headers);
  for (const auto& [name, value] : headers) res.set(header_safe(name), header_safe(value));
  res.set("X-Request-Id", request_id);
  res.keep_alive(keep_alive);
  if (r.status != 204 && r.status != 304) res.body() = std::move(r.body);
  res.prepare_payload();
  if (head && r.status != 204 && r.status != 304) {
    const auto length = res.body().size();
    res.body().clear();
    res.content_length(length);
  }
  return res;
}

std::string error_message(const std::string& field, const std::string& message) {
  return nlohmann::json{{"type", "error"}, {"error", {{"field", field}, {"message", message}}}}.dump(
      -1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// ---- WebSocket: /api/v1/events ----

class WsSession : public Session, public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(tcp::socket&& socket, Core& core) : ws_(std::move(socket)), core_(core) {}
  ~WsSession() override {
    core_.hub.close(sub_);
    core_.remove_session(reg_);
  }

  void start(http::request<http::string_body> req, const std::string& request_id) {
    reg_ = core_.add_session(weak_from_this());
    if (reg_ == 0) return;  // closing: the socket goes with this object
    req_ = std::move(req);
    beast::get_lowest_layer(ws_).expires_never();
    websocket::stream_base::timeout t{};
    t.handshake_timeout =
        std::max<std::chrono::steady_clock::duration>(core_.cfg.header_timeout, std::chrono::seconds(1));
    t.idle_timeout = std::chrono::seconds(60);
    t.keep_alive_pings = true;
    ws_.set_option(t);
    ws_.read_message_max(kWsMessageMax);
    const auto cors = core_.cfg.cors_origin;
    ws_.set_option(websocket::stream_base::decorator([request_id, cors](websocket::response_type& res) {
      res.set(http::field::server, "uavcover");
      res.set("X-Request-Id", request_id);
      if (cors) res.set("Access-Control-Allow-Origin", *cors);
    }));
    ws_.async_accept(req_, beast::bind_front_handler(&WsSession::on_accept, shared_from_this()));
  }

  void shutdown() override {
    net::post(ws_.get_executor(), [self = shared_from_this()] { self->close_now(); });
  }

 private:
  void on_accept(beast::error_code ec) {
    if (ec) return;
    std::weak_ptr<WsSession> weak = weak_from_this();
    sub_ = core_.hub.open([weak](const std::string& message) {
      const auto self = weak.lock();
      if (!self) return false;
      net::post(self->ws_.get_executor(), [self, message] { self->enqueue(message); });
      return true;
    });
    do_read();
  }

  void do_read() {
    ws_.async_read(buffer_, beast::bind_front_handler(&WsSession::on_read, shared_from_this()));
  }

  void on_read(beast::error_code ec, std::size_t) {
    if (ec) return close_now();
    const std::string text = beast::buffers_to_string(buffer_.data());
    buffer_.consume(buffer_.size());
    handle(text);
    if (!closed_) do_read();
  }

  void handle(const std::string& text) {
    const std::size_t max = static_cast<std::size_t>(std::max(0, core_.cfg.max_subscriptions));
    const ClientMessage msg = parse_client_message(text, max);
    switch (msg.op) {
      case ClientMessage::Op::Invalid:
        return enqueue(error_message(msg.error_field, msg.error_message));
      case ClientMessage::Op::Unsubscribe:
        core_.hub.unsubscribe(sub_, msg.jobs);
        return core_.hub.unsubscribe_flights(sub_, msg.flights);
      case ClientMessage::Op::Subscribe:
        if (!core_.hub.subscribe(sub_, msg.jobs, max))
          enqueue(error_message("subscribe.jobs",
                                fmt::format("at most {} job subscriptions per connection", max)));
        if (!core_.hub.subscribe_flights(sub_, msg.flights, max))
          enqueue(error_message("subscribe.flights",
                                fmt::format("at most {} flight subscriptions per connection", max)));
        return;
    }
  }

  void enqueue(const std::string& message) {
    if (closed_) return;
    // a message larger than the cap still goes out alone; behind others it must fit
    if (queue_.size() >= kMaxPendingMessages ||
        (!queue_.empty() && queued_bytes_ + message.size() > core_.cfg.max_event_queue_bytes)) {
      spdlog::warn("events: closing a WebSocket client that does not read ({} messages, {} bytes pending)",
                   queue_.size(), queued_bytes_);
      metrics().count_dropped_event_client();
      return close_now(websocket::close_code::try_again_later);
    }
    queued_bytes_ += message.size();
    queue_.push_back(message);
    if (!writing_) do_write();
  }

  void do_write() {
    writing_ = true;
    ws_.text(true);
    ws_.async_write(net::buffer(queue_.front()),
                    beast::bind_front_handler(&WsSession::on_write, shared_from_this()));
  }

  void on_write(beast::error_code ec, std::size_t) {
    writing_ = false;
    if (ec) return close_now();
    if (closed_) return;
    queued_bytes_ -= queue_.front().size();
    queue_.pop_front();
    if (!queue_.empty()) do_write();
  }

  void close_now(websocket::close_code code = websocket::close_code::going_away) {
    if (closed_) return;
    closed_ = true;
    core_.hub.close(sub_);
    // the message being written stays until its write completes
    if (!writing_)
      queue_.clear();
    else if (!queue_.empty())
      queue_.erase(std::next(queue_.begin()), queue_.end());
    queued_bytes_ = queue_.empty() ? 0 : queue_.front().size();
    if (!writing_ && ws_.is_open()) {
      // a close frame when nothing is being written; the socket goes when the close completes
      ws_.async_close(code, [self = shared_from_this()](beast::error_code) {
        beast::error_code ignored;
        beast::get_lowest_layer(self->ws_).socket().close(ignored);
      });
      return;
    }
    beast::get_lowest_layer(ws_).close();
  }

  websocket::stream<beast::tcp_stream> ws_;
  Core& core_;
  http::request<http::string_body> req_;
  beast::flat_buffer buffer_;
  std::deque<std::string> queue_;
  std::size_t queued_bytes_ = 0;  ///< the bytes in queue_ (the event queue cap)
  bool writing_ = false;
  bool closed_ = false;
  std::uint64_t sub_ = 0;
  std::uint64_t reg_ = 0;
};

// ---- Server-Sent Events: /api/v1/events?jobs=... ----

class SseSession : public Session, public std::enable_shared_from_this<SseSession> {
 public:
  SseSession(tcp::socket&& socket, Core& core)
      : stream_(std::move(socket)), core_(core), timer_(stream_.get_executor()) {}
  ~SseSession() override {
    core_.hub.close(sub_);
    core_.remove_session(reg_);
  }

  void start(unsigned version, std::vector<std::int64_t> ids, const std::string& request_id) {
    reg_ = core_.add_session(weak_from_this());
    if (reg_ == 0) return;
    ids_ = std::move(ids);
    chunked_ = version >= 11;
    stream_.expires_never();
    auto res = std::make_shared<http::response<http::empty_body>>(http::status::ok, version);
    res->set(http::field::server, "uavcover");
    res->set(http::field::content_type, "text/event-stream");
    res->set(http::field::cache_control, "no-cache");
    res->set("X-Accel-Buffering", "no");
    res->set("X-Request-Id", request_id);
    if (core_.cfg.cors_origin) {
      res->set(http::field::access_control_allow_origin, *core_.cfg.cors_origin);
      res->set(http::field::vary, "Origin");
    }
    if (chunked_)
      res->chunked(true);
    else
      res->keep_alive(false);
    auto sr = std::make_shared<http::response_serializer<http::empty_body>>(*res);
    writing_ = true;
    http::async_write_header(
        stream_, *sr,
        [self = shared_from_this(), res, sr](beast::error_code ec, std::size_t) { self->on_header(ec); });
  }

  void shutdown() override {
    net::post(stream_.get_executor(), [self = shared_from_this()] {
      self->stopping_ = true;
      if (!self->writing_) self->finish_stream();
    });
  }

 private:
  void on_header(beast::error_code ec) {
    writing_ = false;
    if (ec) return close_now();
    if (stopping_) return finish_stream();
    std::weak_ptr<SseSession> weak = weak_from_this();
    sub_ = core_.hub.open([weak](const std::string& message) {
      const auto self = weak.lock();
      if (!self) return false;
      net::post(self->stream_.get_executor(),
                [self, message] { self->enqueue("event: job\ndata: " + message + "\n\n"); });
      return true;
    });
    core_.hub.subscribe(sub_, ids_, ids_.size());
    arm_keepalive();
    watch_peer();
  }

  void arm_keepalive() {
    timer_.expires_after(core_.cfg.sse_keepalive);
    timer_.async_wait([self = shared_from_this()](beast::error_code ec) {
      if (ec || self->closed_) return;
      self->enqueue(": keepalive\n\n");
      self->arm_keepalive();
    });
  }

  // The client never sends anything: a read completes only when it goes away.
  void watch_peer() {
    stream_.async_read_some(net::buffer(scratch_),
                            [self = shared_from_this()](beast::error_code ec, std::size_t) {
                              if (ec) return self->close_now();
                              self->watch_peer();
                            });
  }

  void enqueue(std::string record) {
    if (closed_ || stopping_) return;
    if (queue_.size() >= kMaxPendingMessages ||
        (!queue_.empty() && queued_bytes_ + record.size() > core_.cfg.max_event_queue_bytes)) {
      spdlog::warn("events: closing an SSE client that does not read ({} records, {} bytes pending)",
                   queue_.size(), queued_bytes_);
      metrics().count_dropped_event_client();
      return close_now();
    }
    queued_bytes_ += record.size();
    queue_.push_back(std::move(record));
    if (!writing_) do_write();
  }

  void do_write() {
    writing_ = true;
    auto done = [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_write(ec); };
    if (chunked_)
      net::async_write(stream_, http::make_chunk(net::buffer(queue_.front())), std::move(done));
    else
      net::async_write(stream_, net::buffer(queue_.front()), std::move(done));
  }

  void on_write(beast::error_code ec) {
    writing_ = false;
    if (ec) return close_now();
    if (closed_) return;
    queued_bytes_ -= queue_.front().size();
    queue_.pop_front();
    if (stopping_) return finish_stream();
    if (!queue_.empty()) do_write();
  }

  // On server stop: the last chunk, then the connection closes.
  void finish_stream() {
    if (closed_) return;
    core_.hub.close(sub_);
    timer_.cancel();
    if (!chunked_) return close_now();
    queue_.clear();  // nothing is being written (the callers check)
    queued_bytes_ = 0;
    writing_ = true;
    net::async_write(stream_, http::make_chunk_last(),
                     [self = shared_from_this()](beast::error_code, std::size_t) { self->close_now(); });
  }

  void close_now() {
    if (closed_) return;
    closed_ = true;
    core_.hub.close(sub_);
    timer_.cancel();
    if (!writing_)
      queue_.clear();
    else if (!queue_.empty())
      queue_.erase(std::next(queue_.begin()), queue_.end());
    queued_bytes_ = queue_.empty() ? 0 : queue_.front().size();
    beast::error_code ec;
    stream_.socket().shutdown(tcp::socket::shutdown_both, ec);
    stream_.close();
  }

  beast::tcp_stream stream_;
  Core& core_;
  net::steady_timer timer_;
  std::vector<std::int64_t> ids_;
  std::deque<std::string> queue_;
  std::size_t queued_bytes_ = 0;
  std::array<char, 256> scratch_{};
  bool chunked_ = true;
  bool writing_ = false;
  bool stopping_ = false;
  bool closed_ = false;
  std::uint64_t sub_ = 0;
  std::uint64_t reg_ = 0;
};

// ---- plain HTTP ----

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
    if (has_body && decoded && probe.path.rfind("/api/", 0) == 0 &&
        media_type(sv(req[http::field::content_type])) != "application/json")
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
    const bool posted = core_.post_bounded(pool, load, max, [self, shared, fn, route, method, version, keep] {
      Response out = run_guarded(fn, *shared, route);
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
        std::make_shared<WsSession>(stream_.release_socket(), core_)
            ->start(parser_->release(), req.request_id);
        return Dispatched::Stream;
      }
      const auto ids = parse_jobs_param(req, static_cast<std::size_t>(std::max(0, cfg.max_subscriptions)));
      core_.log_request(req.request_id, req.method, route, req.path, 200, seconds, 0);
      stream_.expires_never();
      std::make_shared<SseSession>(stream_.release_socket(), core_)
          ->start(breq.version(), ids, req.request_id);
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

// ---- free functions ----

ListenAddress parse_listen(const std::string& listen) {
  auto bad = [&](const std::string& why) {
    return InputError("--listen",
                      "expected HOST:PORT or [IPv6]:PORT, " + why + ", got '" + listen.substr(0, 80) + "'");
  };
  ListenAddress out;
  std::string port_text;
  if (!listen.empty() && listen.front() == '[') {
    const auto close = listen.find(']');
    if (close == std::string::npos || close + 1 >= listen.size() || listen[close + 1] != ':')
      throw bad("an IPv6 address needs brackets and a port");
    out.host = listen.substr(1, close - 1);
    port_text = listen.substr(close + 2);
  } else {
    const auto colon = listen.rfind(':');
    if (colon == std::string::npos) throw bad("the port is missing");
    out.host = listen.substr(0, colon);
    port_text = listen.substr(colon + 1);
    if (out.host.find(':') != std::string::npos) throw bad("write IPv6 addresses in brackets");
  }
  if (out.host.empty()) throw bad("the host is missing");
  if (port_text.empty() || port_text.size() > 5 ||
      port_text.find_first_not_of("0123456789") != std::string::npos || std::stoul(port_text) > 65535)
    throw bad("the port must be a number in 0..65535");
  out.port = static_cast<std::uint16_t>(std::stoul(port_text));
  if (out.host != "localhost") {
    beast::error_code ec;
    net::ip::make_address(out.host, ec);
    if (ec) throw bad("the host must be an IP address or localhost");
  }
  return out;
}

void check_listen_policy(const ServerConfig& config) {
  const auto addr = parse_listen(config.listen);
  if (!is_loopback(addr.host) && !config.token)
    throw InputError("--listen",
                     "listening on " + addr.host +
                         " (not loopback) needs --token-file: every request must then carry the token");
}

bool constant_time_equals(const std::string& a, const std::string& b) {
  const std::size_t n = std::max(a.size(), b.size());
  volatile unsigned diff = a.size() == b.size() ? 0U : 1U;
  for (std::size_t i = 0; i < n; ++i) {
    const auto x = static_cast<unsigned char>(i < a.size() ? a[i] : 0);
    const auto y = static_cast<unsigned char>(i < b.size() ? b[i] : 0);
    diff = diff | static_cast<unsigned>(x ^ y);
  }
  return diff == 0;
}

// ---- HttpServer ----

struct HttpServer::Impl {
  Impl(ServerConfig config, Router& router, EventSource& events)
      : core(std::move(config), router, events),
        ioc(std::max(1, core.cfg.io_threads)),
        acceptor(net::make_strand(ioc)) {
    const auto addr = parse_listen(core.cfg.listen);
    const auto ip = net::ip::make_address(addr.host == "localhost" ? "127.0.0.1" : addr.host);
    const tcp::endpoint endpoint(ip, addr.port);
    beast::error_code ec;
    acceptor.open(endpoint.protocol(), ec);
    if (!ec) acceptor.set_option(net::socket_base::reuse_address(true), ec);
    if (!ec) acceptor.bind(endpoint, ec);
    if (!ec) acceptor.listen(net::socket_base::max_listen_connections, ec);
    if (ec) throw OperationError("cannot listen on " + core.cfg.listen + ": " + ec.message());
    port = acceptor.local_endpoint().port();
    core.host_policy.port = port;
  }

  ~Impl() {
    core.hub.stop();
    stop_threads();
  }

  void do_accept() {
    acceptor.async_accept(net::make_strand(ioc), [this](beast::error_code ec, tcp::socket socket) {
      if (!acceptor.is_open()) return;
      if (ec) {
        spdlog::warn("accept failed: {}", ec.message());
        // e.g. too many open files: try again shortly instead of spinning
        auto timer =
            std::make_shared<net::steady_timer>(acceptor.get_executor(), std::chrono::milliseconds(100));
        timer->async_wait([this, timer](beast::error_code) {
          if (acceptor.is_open()) do_accept();
        });
        return;
      }
      std::make_shared<HttpSession>(std::move(socket), core)->start();
      do_accept();
    });
  }

  void run() {
    core.hub.start();
    net::post(acceptor.get_executor(), [this] {
      if (acceptor.is_open()) do_accept();
    });
    work.emplace(net::make_work_guard(ioc));
    for (int i = 0; i < std::max(1, core.cfg.io_threads); ++i)
      threads.emplace_back([this] {
        for (;;) {
          try {
            ioc.run();
            return;
          } catch (const std::exception& e) {
            spdlog::error("I/O thread: {}", e.what());
          }
        }
      });
    std::stop_callback on_stop(core.cfg.stop, [this] { stop(); });
    {
      std::unique_lock lock(core.mutex);
      core.changed.wait(lock, [this] { return core.stopping; });
      // give open connections a moment to close cleanly
      core.changed.wait_for(lock, std::chrono::seconds(3), [this] { return core.sessions.empty(); });
    }
    core.hub.stop();
    stop_threads();
  }

  void stop_threads() {
    core.drain_pools();  // the requests they hold are answered (or fail) on the still running I/O threads
    work.reset();
    ioc.stop();
    for (auto& t : threads)
      if (t.joinable()) t.join();
    threads.clear();
  }

  void stop() {
    std::vector<std::shared_ptr<Session>> open;
    {
      const std::lock_guard lock(core.mutex);
      if (core.stopping) return;
      core.stopping = true;
      for (const auto& [id, weak] : core.sessions)
        if (auto s = weak.lock()) open.push_back(std::move(s));
    }
    core.changed.notify_all();
    net::post(acceptor.get_executor(), [this] {
      beast::error_code ec;
      acceptor.close(ec);
    });
    for (const auto& s : open) s->shutdown();
  }

  Core core;  // before ioc: sessions destroyed with the io_context still reach it
  net::io_context ioc;
  tcp::acceptor acceptor;
  std::optional<net::executor_work_guard<net::io_context::executor_type>> work;
  std::vector<std::thread> threads;
  std::uint16_t port = 0;
};

HttpServer::HttpServer(ServerConfig config, Router& router, EventSource& events)
    : impl_(std::make_unique<Impl>(std::move(config), router, events)) {}

HttpServer::~HttpServer() = default;

std::uint16_t HttpServer::port() const { return impl_->port; }

void HttpServer::run() { impl_->run(); }

void HttpServer::stop() { impl_->stop(); }

}  // namespace uavcover::server
