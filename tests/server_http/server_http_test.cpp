// The transport against a live HttpServer on a free loopback port, driven by a Beast client: routing
// errors as JSON, limits, auth, request ids, metrics, CORS, static files, timeouts and live events.
#include <gtest/gtest.h>
#include <spdlog/sinks/base_sink.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include "io/static_dir.hpp"
#include "server/metrics.hpp"
#include "server/server.hpp"
#include "uavcover/error.hpp"

namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using nlohmann::json;
using namespace uavcover;
using namespace uavcover::server;

using Res = http::response<http::string_body>;
constexpr auto kWait = std::chrono::seconds(10);

class MapSource : public EventSource {
 public:
  std::vector<json> snapshot(const std::vector<std::int64_t>& ids) override {
    const std::lock_guard lock(mutex_);
    std::vector<json> out;
    for (const auto id : ids)
      if (const auto it = jobs_.find(id); it != jobs_.end()) out.push_back(it->second);
    return out;
  }
  void set(std::int64_t id, const std::string& state, double progress) {
    const std::lock_guard lock(mutex_);
    jobs_[id] = {
        {"id", id}, {"state", state}, {"progress", progress}, {"stage", "division"}, {"updated", "t"}};
  }

 private:
  std::mutex mutex_;
  std::map<std::int64_t, json> jobs_;
};

/// Asynchronous operations run with a bound, so a server bug fails the test instead of hanging it.
class Client {
 public:
  explicit Client(std::uint16_t port) : stream_(ioc_) {
    stream_.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
  }

  Res send(http::verb verb, const std::string& target, const std::string& body = "",
           const std::map<std::string, std::string>& headers = {}) {
    http::request<http::string_body> req{verb, target, 11};
    req.set(http::field::host, "127.0.0.1");
    for (const auto& [k, v] : headers) req.set(k, v);
    // the server takes JSON bodies only (415 otherwise): a test sends another type explicitly
    if (!body.empty() && req.count(http::field::content_type) == 0)
      req.set(http::field::content_type, "application/json");
    req.body() = body;
    if (!body.empty() || verb == http::verb::post) req.prepare_payload();
    write(req);
    return read();
  }
  template <class Msg>
  void write(Msg& msg) {
    beast::error_code ec = net::error::timed_out;
    http::async_write(stream_, msg, [&](beast::error_code e, std::size_t) { ec = e; });
    run();
    if (ec) throw std::runtime_error("write: " + ec.message());
  }
  Res read() {
    Res res;
    beast::error_code ec = net::error::timed_out;
    http::async_read(stream_, buffer_, res, [&](beast::error_code e, std::size_t) { ec = e; });
    run();
    if (ec) throw std::runtime_error("read: " + ec.message());
    return res;
  }
  void write_raw(const std::string& text) {
    beast::error_code ec = net::error::timed_out;
    net::async_write(stream_, net::buffer(text), [&](beast::error_code e, std::size_t) { ec = e; });
    run();
    if (ec) throw std::runtime_error("write: " + ec.message());
  }
  /// Reads raw bytes until `until` appears in what was read, or the connection ends (the error).
  beast::error_code read_raw_until(const std::string& until, std::string& text) {
    std::array<char, 4096> chunk{};
    while (text.find(until) == std::string::npos || until.empty()) {
      beast::error_code ec = net::error::timed_out;
      std::size_t n = 0;
      stream_.async_read_some(net::buffer(chunk), [&](beast::error_code e, std::size_t m) {
        ec = e;
        n = m;
      });
      run();
      text.append(chunk.data(), n);
      if (ec) return ec;
    }
    return {};
  }

 private:
  void run() {
    ioc_.restart();
    ioc_.run_for(kWait);
    if (!ioc_.stopped()) {  // timed out: cancel, and let the handler run before its captures go
      stream_.close();
      ioc_.restart();
      ioc_.run();
    }
  }
  net::io_context ioc_;
  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
};

class WsClient {
 public:
  WsClient(std::uint16_t port, const std::map<std::string, std::string>& headers = {}) : ws_(ioc_) {
    beast::get_lowest_layer(ws_).connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
    ws_.set_option(websocket::stream_base::decorator([headers](websocket::request_type& req) {
      for (const auto& [k, v] : headers) req.set(k, v);
    }));
    beast::error_code ec = net::error::timed_out;
    ws_.async_handshake(res_, "127.0.0.1", "/api/v1/events", [&](beast::error_code e) { ec = e; });
    run();
    handshake_error = ec;
  }
  void send(const std::string& text) {
    beast::error_code ec = net::error::timed_out;
    ws_.async_write(net::buffer(text), [&](beast::error_code e, std::size_t) { ec = e; });
    run();
    if (ec) throw std::runtime_error("ws write: " + ec.message());
  }
  /// The next message, or nullopt when the connection ended (or nothing came in time).
  std::optional<json> receive() {
    beast::flat_buffer buffer;
    beast::error_code ec = net::error::timed_out;
    ws_.async_read(buffer, [&](beast::error_code e, std::size_t) { ec = e; });
    run();
    if (ec) return std::nullopt;
    return json::parse(beast::buffers_to_string(buffer.data()));
  }
  /// Reads until a job message whose job matches `pred`.
  std::optional<json> receive_job(const std::function<bool(const json&)>& pred) {
    for (int i = 0; i < 50; ++i) {
      auto m = receive();
      if (!m) return std::nullopt;
      if ((*m)["type"] == "job" && pred((*m)["job"])) return m;
    }
    return std::nullopt;
  }
  beast::error_code handshake_error;
  websocket::response_type res_;

 private:
  void run() {
    ioc_.restart();
    ioc_.run_for(kWait);
    if (!ioc_.stopped()) {
      beast::get_lowest_layer(ws_).close();
      ioc_.restart();
      ioc_.run();
    }
  }
  net::io_context ioc_;
  websocket::stream<beast::tcp_stream> ws_;
};

json body_of(const Res& res) { return json::parse(res.body()); }

class ServerHttp : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { spdlog::set_level(spdlog::level::warn); }

  void start(ServerConfig cfg = {}) {
    cfg.listen = "127.0.0.1:0";
    router_.add("GET", "/api/v1/things/{id}", [](const Request& r) {
      return Response::json(200, {{"id", r.params.at("id")}, {"query", r.query}, {"path", r.path}});
    });
    router_.add("PUT", "/api/v1/things/{id}",
                [](const Request&) { return Response::json(200, json::object()); });
    router_.add("POST", "/api/v1/things", [](const Request& r) {
      return Response::json(201, {{"size", r.body.size()}, {"type", r.header("content-type").value_or("")}});
    });
    router_.add("GET", "/api/v1/boom",
                [](const Request&) -> Response { throw std::runtime_error("secret detail"); });
    router_.add("GET", "/api/v1/busy", [](const Request&) -> Response {
      HttpError e(503, "", "queue full");
      e.headers.emplace_back("Retry-After", "7");
      throw e;
    });
    server_ = std::make_unique<HttpServer>(cfg, router_, source_);
    port_ = server_->port();
    thread_ = std::thread([this] { server_->run(); });
  }
  void stop() {
    if (!server_) return;
    server_->stop();
    thread_.join();
    server_.reset();
  }
  void TearDown() override { stop(); }

  Router router_;
  MapSource source_;
  std::unique_ptr<HttpServer> server_;
  std::thread thread_;
  std::uint16_t port_ = 0;
};

bool hex16(const std::string& s) {
  return s.size() == 16 && s.find_first_not_of("0123456789abcdef") == std::string::npos;
}

TEST_F(ServerHttp, KeepAliveDecodingAndRequestIds) {
  start();
  ASSERT_NE(port_, 0);
  Client c(port_);
  std::set<std::string> ids;
  for (int i = 0; i < 3; ++i) {  // one connection, three requests
    const auto res = c.send(http::verb::get, "/api/v1/things/7?name=a%20b+c&x=%2F&flag");
    ASSERT_EQ(res.result_int(), 200);
    EXPECT_TRUE(res.keep_alive());
    const auto b = body_of(res);
    EXPECT_EQ(b["id"], "7");
    EXPECT_EQ(b["query"]["name"], "a b c");
    EXPECT_EQ(b["query"]["x"], "/");
    EXPECT_EQ(b["query"]["flag"], "");
    EXPECT_EQ(res[http::field::content_type], "application/json");
    const std::string id(res["X-Request-Id"]);
    EXPECT_TRUE(hex16(id)) << id;
    ids.insert(id);
  }
  EXPECT_EQ(ids.size(), 3U);
  // a client's id is kept when it is plain, replaced otherwise
  EXPECT_EQ(
      c.send(http::verb::get, "/api/v1/things/1", "", {{"X-Request-Id", "client-id_42"}})["X-Request-Id"],
      "client-id_42");
  EXPECT_TRUE(hex16(std::string(
      c.send(http::verb::get, "/api/v1/things/1", "", {{"X-Request-Id", "bad id!"}})["X-Request-Id"])));
  EXPECT_TRUE(hex16(std::string(c.send(http::verb::get, "/api/v1/things/1", "",
                                       {{"X-Request-Id", std::string(65, 'a')}})["X-Request-Id"])));
  // a body reaches the handler, headers lower-case
  const auto posted =
      c.send(http::verb::post, "/api/v1/things", R"({"a":1})", {{"Content-Type", "application/json"}});
  EXPECT_EQ(posted.result_int(), 201);
  EXPECT_EQ(body_of(posted)["size"], 7);
  EXPECT_EQ(body_of(posted)["type"], "application/json");
}

TEST_F(ServerHttp, RoutingErrorsAreJson) {
  start();
  Client c(port_);
  const auto missing = c.send(http::verb::get, "/api/v1/nothing/here");
  EXPECT_EQ(missing.result_int(), 404);
  EXPECT_TRUE(body_of(missing)["error"].contains("field"));
  EXPECT_TRUE(body_of(missing)["error"]["message"].is_string());
  EXPECT_FALSE(missing["X-Request-Id"].empty());

  const auto wrong = c.send(http::verb::delete_, "/api/v1/things/3");
  EXPECT_EQ(wrong.result_int(), 405);
  EXPECT_EQ(wrong[http::field::allow], "GET, HEAD, PUT");  // HEAD is served wherever GET is
  EXPECT_TRUE(body_of(wrong).contains("error"));
  // without --cors-origin, OPTIONS is a method like any other
  const auto options = c.send(http::verb::options, "/api/v1/things/3");
  EXPECT_EQ(options.result_int(), 405);
  EXPECT_TRUE(options[http::field::access_control_allow_origin].empty());

  const auto boom = c.send(http::verb::get, "/api/v1/boom");
  EXPECT_EQ(boom.result_int(), 500);
  EXPECT_EQ(body_of(boom), json::parse(R"({"error":{"field":"","message":"internal error"}})"));
  EXPECT_EQ(boom.body().find("secret"), std::string::npos);

  const auto busy = c.send(http::verb::get, "/api/v1/busy");
  EXPECT_EQ(busy.result_int(), 503);
  EXPECT_EQ(busy[http::field::retry_after], "7");
}

TEST_F(ServerHttp, BadPercentEncodingIs400) {
  start();
  for (const std::string target : {"/api/v1/things/%zz", "/api/v1/things/%4", "/api/v1/things/a%00b",
                                   "/api/v1/things/1?a=%4", "/api/v1/things/1?%00=1"}) {
    Client c(port_);
    const auto res = c.send(http::verb::get, target);
    EXPECT_EQ(res.result_int(), 400) << target;
    const auto field = body_of(res)["error"]["field"].get<std::string>();
    EXPECT_TRUE(field == "path" || field == "query") << target << " " << field;
  }
}

TEST_F(ServerHttp, BodyOverTheLimitIs413) {
  ServerConfig cfg;
  cfg.max_body = 1024;
  start(cfg);
  Client ok(port_);
  EXPECT_EQ(ok.send(http::verb::post, "/api/v1/things", std::string(1024, 'x')).result_int(), 201);
  Client c(port_);
  const auto res = c.send(http::verb::post, "/api/v1/things", std::string(1025, 'x'));
  EXPECT_EQ(res.result_int(), 413);
  EXPECT_EQ(body_of(res)["error"]["field"], "body");
  EXPECT_FALSE(res.keep_alive());
  // chunked bodies are held to the same limit
  Client chunked(port_);
  chunked.write_raw(
      "POST /api/v1/things HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
      "Transfer-Encoding: chunked\r\n\r\n"
      "800\r\n" +
      std::string(2048, 'y') + "\r\n0\r\n\r\n");
  EXPECT_EQ(chunked.read().result_int(), 413);
}

TEST_F(ServerHttp, ExpectContinuePipeliningAndHeaderLimit) {
  start();
  Client c(port_);
  c.write_raw(
      "POST /api/v1/things HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nContent-Length: "
      "5\r\nExpect: 100-continue\r\n\r\n");
  std::string text;
  ASSERT_FALSE(c.read_raw_until("\r\n\r\n", text));
  EXPECT_EQ(text.rfind("HTTP/1.1 100 Continue\r\n", 0), 0U) << text;
  c.write_raw("hello");
  const auto res = c.read();
  EXPECT_EQ(res.result_int(), 201);
  EXPECT_EQ(body_of(res)["size"], 5);
  // two requests in one write, two answers in order
  c.write_raw(
      "GET /api/v1/things/1 HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\nGET /api/v1/things/2 HTTP/1.1\r\nHost: "
      "127.0.0.1\r\n\r\n");
  EXPECT_EQ(body_of(c.read())["id"], "1");
  EXPECT_EQ(body_of(c.read())["id"], "2");

  Client big(port_);
  const auto huge =
      big.send(http::verb::get, "/api/v1/things/1", "", {{"X-Filler", std::string(20000, 'a')}});
  EXPECT_EQ(huge.result_int(), 431);
  EXPECT_TRUE(body_of(huge).contains("error"));
  Client garbage(port_);
  garbage.write_raw("NOT AN HTTP REQUEST\r\n\r\n");
  EXPECT_EQ(garbage.read().result_int(), 400);
}

TEST_F(ServerHttp, TokenRule) {
  ServerConfig cfg;
  cfg.token = "0123456789abcdef-secret";
  start(cfg);
  Client c(port_);
  const auto none = c.send(http::verb::get, "/api/v1/things/1");
  EXPECT_EQ(none.result_int(), 401);
  EXPECT_EQ(none[http::field::www_authenticate], "Bearer");
  EXPECT_TRUE(body_of(none).contains("error"));
  EXPECT_EQ(
      c.send(http::verb::get, "/api/v1/things/1", "", {{"Authorization", "Bearer 0123456789abcdef-secreT"}})
          .result_int(),
      401);
  EXPECT_EQ(
      c.send(http::verb::get, "/api/v1/things/1", "", {{"Authorization", "Bearer 0123456789abcdef-secret2"}})
          .result_int(),
      401);
  EXPECT_EQ(c.send(http::verb::get, "/api/v1/things/1", "", {{"Authorization", "0123456789abcdef-secret"}})
                .result_int(),
            401);
  EXPECT_EQ(
      c.send(http::verb::get, "/api/v1/things/1", "", {{"Authorization", "Bearer 0123456789abcdef-secret"}})
          .result_int(),
      200);
  EXPECT_EQ(
      c.send(http::verb::get, "/api/v1/things/1", "", {{"Authorization", "bearer 0123456789abcdef-secret"}})
          .result_int(),
      200);
  EXPECT_EQ(c.send(http::verb::get, "/healthz").result_int(), 200);
  EXPECT_EQ(c.send(http::verb::get, "/readyz").result_int(), 200);
  EXPECT_EQ(c.send(http::verb::get, "/metrics").result_int(), 401);
  EXPECT_EQ(c.send(http::verb::get, "/nothing").result_int(), 401);
  // the WebSocket upgrade follows the same rule
  WsClient refused(port_);
  EXPECT_TRUE(refused.handshake_error);
  WsClient accepted(port_, {{"Authorization", "Bearer 0123456789abcdef-secret"}});
  EXPECT_FALSE(accepted.handshake_error) << accepted.handshake_error.message();
}

TEST_F(ServerHttp, HealthReadyAndMetrics) {
  std::atomic<bool> ready{true};
  ServerConfig cfg;
  cfg.ready_check = [&] { return ready.load(); };
  start(cfg);
  metrics().set_job_counts_provider([] {
    return std::map<std::string, std::int64_t>{{"queued", 3}, {"running", 1}};
  });
  observe_plan_duration(1.5);
  Client c(port_);
  EXPECT_EQ(body_of(c.send(http::verb::get, "/healthz")), json::parse(R"({"status":"ok"})"));
  EXPECT_EQ(body_of(c.send(http::verb::get, "/readyz")), json::parse(R"({"status":"ready"})"));
  ready = false;
  EXPECT_EQ(c.send(http::verb::get, "/readyz").result_int(), 503);
  c.send(http::verb::get, "/api/v1/things/5");
  c.send(http::verb::get, "/api/v1/things/6");
  c.send(http::verb::get, "/api/v1/nope");
  const auto res = c.send(http::verb::get, "/metrics");
  EXPECT_EQ(res.result_int(), 200);
  EXPECT_EQ(res[http::field::content_type].substr(0, 25), "text/plain; version=0.0.4");
  const std::string& text = res.body();
  EXPECT_NE(text.find("# TYPE uavcover_http_requests_total counter"), std::string::npos);
  EXPECT_NE(
      text.find(R"(uavcover_http_requests_total{route="/api/v1/things/{id}",method="GET",code="200"} )"),
      std::string::npos)
      << text;
  EXPECT_NE(text.find(R"(uavcover_http_requests_total{route="unmatched",method="GET",code="404"} )"),
            std::string::npos);
  EXPECT_NE(text.find(R"(uavcover_http_requests_total{route="/readyz",method="GET",code="503"} )"),
            std::string::npos);
  EXPECT_NE(
      text.find(R"(uavcover_http_request_duration_seconds_bucket{route="/api/v1/things/{id}",le="+Inf"} )"),
      std::string::npos);
  EXPECT_NE(text.find(R"(uavcover_http_request_duration_seconds_bucket{route="/healthz",le="0.001"})"),
            std::string::npos);
  EXPECT_NE(text.find(R"(uavcover_jobs{state="queued"} 3)"), std::string::npos);
  EXPECT_NE(text.find("uavcover_plan_duration_seconds_count "), std::string::npos);
  EXPECT_NE(text.find(R"(uavcover_plan_duration_seconds_bucket{le="+Inf"} )"), std::string::npos);
  metrics().set_job_counts_provider({});
}

TEST(Metrics, HistogramBucketsAreCumulative) {
  Metrics m;
  m.observe_request("/r", "GET", 200, 0.0005);
  m.observe_request("/r", "GET", 200, 0.003);
  m.observe_request("/r", "GET", 500, 50);
  const auto text = m.render();
  EXPECT_NE(text.find(R"(uavcover_http_request_duration_seconds_bucket{route="/r",le="0.001"} 1)"),
            std::string::npos);
  EXPECT_NE(text.find(R"(uavcover_http_request_duration_seconds_bucket{route="/r",le="0.005"} 2)"),
            std::string::npos);
  EXPECT_NE(text.find(R"(uavcover_http_request_duration_seconds_bucket{route="/r",le="10"} 2)"),
            std::string::npos);
  EXPECT_NE(text.find(R"(uavcover_http_request_duration_seconds_bucket{route="/r",le="+Inf"} 3)"),
            std::string::npos);
  EXPECT_NE(text.find(R"(uavcover_http_request_duration_seconds_count{route="/r"} 3)"), std::string::npos);
  EXPECT_NE(text.find(R"(uavcover_http_requests_total{route="/r",method="GET",code="500"} 1)"),
            std::string::npos);
  m.observe_request("a\"b\\c\nd", "GET", 200, 0);
  EXPECT_NE(m.render().find(R"(route="a\"b\\c\nd")"), std::string::npos);
}

TEST_F(ServerHttp, Cors) {
  ServerConfig cfg;
  cfg.cors_origin = "https://app.example";
  cfg.token = "0123456789abcdef-secret";
  start(cfg);
  Client c(port_);
  const auto pre = c.send(http::verb::options, "/api/v1/things/1", "",
                          {{"Origin", "https://app.example"}, {"Access-Control-Request-Method", "PUT"}});
  EXPECT_EQ(pre.result_int(), 204);
  EXPECT_EQ(pre[http::field::access_control_allow_origin], "https://app.example");
  EXPECT_NE(pre[http::field::access_control_allow_methods].find("PUT"), std::string::npos);
  EXPECT_NE(pre[http::field::access_control_allow_headers].find("Authorization"), std::string::npos);
  const auto get =
      c.send(http::verb::get, "/api/v1/things/1", "", {{"Authorization", "Bearer 0123456789abcdef-secret"}});
  EXPECT_EQ(get.result_int(), 200);
  EXPECT_EQ(get[http::field::access_control_allow_origin], "https://app.example");
}

TEST_F(ServerHttp, StaticFilesAreAMapLookup) {
  ServerConfig cfg;
  cfg.static_files["/index.html"] = {"text/html; charset=utf-8", "<html>app</html>"};
  cfg.static_files["/assets/app.js"] = {"text/javascript; charset=utf-8", "console.log(1)"};
  start(cfg);
  Client c(port_);
  const auto index = c.send(http::verb::get, "/");
  EXPECT_EQ(index.result_int(), 200);
  EXPECT_EQ(index.body(), "<html>app</html>");
  EXPECT_EQ(index[http::field::content_type], "text/html; charset=utf-8");
  const auto js = c.send(http::verb::get, "/assets/app.js");
  EXPECT_EQ(js.body(), "console.log(1)");
  EXPECT_EQ(js[http::field::content_type], "text/javascript; charset=utf-8");
  for (const std::string t : {"/../etc/passwd", "/assets/../../etc/passwd", "/%2e%2e/etc/passwd",
                              "/assets/app.js/", "/etc/passwd", "/assets//app.js/.."}) {
    const auto res = c.send(http::verb::get, t);
    EXPECT_EQ(res.result_int(), 404) << t;
    EXPECT_TRUE(body_of(res).contains("error")) << t;
  }
  EXPECT_EQ(c.send(http::verb::post, "/index.html", "x").result_int(), 404);
}

TEST_F(ServerHttp, DefaultIndexWithoutStaticFiles) {
  start();
  Client c(port_);
  const auto index = c.send(http::verb::get, "/");
  EXPECT_EQ(index.result_int(), 200);
  EXPECT_NE(index.body().find("/api/v1/openapi.json"), std::string::npos);
}

TEST_F(ServerHttp, SilentConnectionIsClosed) {
  ServerConfig cfg;
  cfg.header_timeout = std::chrono::seconds(1);
  cfg.idle_timeout = std::chrono::seconds(1);
  start(cfg);
  Client silent(port_);
  std::string text;
  const auto ec = silent.read_raw_until("never", text);
  EXPECT_NE(ec, net::error::timed_out) << "the server should close a silent connection";
  EXPECT_TRUE(ec == net::error::eof || ec == net::error::connection_reset) << ec.message();
  // an idle kept-alive connection too
  Client idle(port_);
  EXPECT_EQ(idle.send(http::verb::get, "/healthz").result_int(), 200);
  text.clear();
  const auto ec2 = idle.read_raw_until("never", text);
  EXPECT_TRUE(ec2 == net::error::eof || ec2 == net::error::connection_reset) << ec2.message();
}

TEST_F(ServerHttp, WebSocketEvents) {
  ServerConfig cfg;
  cfg.max_subscriptions = 3;
  cfg.event_poll = std::chrono::milliseconds(20);
  source_.set(1, "queued", 0);
  source_.set(2, "running", 0.5);
  start(cfg);
  WsClient ws(port_);
  ASSERT_FALSE(ws.handshake_error) << ws.handshake_error.message();
  EXPECT_TRUE(hex16(std::string(ws.res_["X-Request-Id"])));
  ws.send(R"({"subscribe": {"jobs": [1, 99]}})");
  auto first = ws.receive();
  ASSERT_TRUE(first);
  EXPECT_EQ((*first)["type"], "job");
  EXPECT_EQ((*first)["job"]["id"], 1);
  EXPECT_EQ((*first)["job"]["state"], "queued");
  source_.set(1, "running", 0.25);
  auto change = ws.receive_job([](const json& j) { return j["id"] == 1 && j["state"] == "running"; });
  ASSERT_TRUE(change);
  EXPECT_EQ((*change)["job"]["progress"], 0.25);

  ws.send("{not json");
  auto err = ws.receive();
  ASSERT_TRUE(err);
  EXPECT_EQ((*err)["type"], "error");
  EXPECT_TRUE((*err)["error"]["message"].is_string());
  ws.send(R"({"subscribe": {"jobs": "1"}})");
  err = ws.receive();
  ASSERT_TRUE(err);
  EXPECT_EQ((*err)["error"]["field"], "subscribe.jobs");
  ws.send(R"({"subscribe": {"jobs": [1, -2]}})");
  err = ws.receive();
  ASSERT_TRUE(err);
  EXPECT_EQ((*err)["error"]["field"], "subscribe.jobs[1]");
  ws.send(R"({"hello": 1})");
  err = ws.receive();
  ASSERT_TRUE(err);
  EXPECT_EQ((*err)["type"], "error");
  // 1 and 99 followed; 2 more would make 4 > 3
  ws.send(R"({"subscribe": {"jobs": [2, 3]}})");
  err = ws.receive();
  ASSERT_TRUE(err);
  EXPECT_EQ((*err)["type"], "error");
  EXPECT_EQ((*err)["error"]["field"], "subscribe.jobs");
  // the connection still works: after unsubscribing 99, job 2 fits
  ws.send(R"({"unsubscribe": {"jobs": [99]}})");
  ws.send(R"({"subscribe": {"jobs": [2]}})");
  auto two = ws.receive_job([](const json& j) { return j["id"] == 2; });
  ASSERT_TRUE(two);
  EXPECT_EQ((*two)["job"]["state"], "running");
  // a message over 64 KiB ends the connection
  ws.send("[" + std::string(70 * 1024, ' ') + "]");
  EXPECT_FALSE(ws.receive_job([](const json&) { return true; }));
}

TEST_F(ServerHttp, ServerStopClosesEventStreams) {
  source_.set(1, "queued", 0);
  start();
  WsClient ws(port_);
  ASSERT_FALSE(ws.handshake_error);
  ws.send(R"({"subscribe": {"jobs": [1]}})");
  ASSERT_TRUE(ws.receive());
  Client sse(port_);
  sse.write_raw("GET /api/v1/events?jobs=1 HTTP/1.1\r\nHost: 127.0.0.1\r\nAccept: text/event-stream\r\n\r\n");
  std::string text;
  ASSERT_FALSE(sse.read_raw_until("event: job", text));
  stop();
  EXPECT_FALSE(ws.receive());
  const auto ec = sse.read_raw_until("never", text);
  EXPECT_NE(ec, net::error::timed_out);
}

TEST_F(ServerHttp, ServerSentEvents) {
  ServerConfig cfg;
  cfg.event_poll = std::chrono::milliseconds(20);
  source_.set(5, "queued", 0);
  start(cfg);
  {
    Client bad(port_);
    for (const std::string t :
         {"/api/v1/events", "/api/v1/events?jobs=", "/api/v1/events?jobs=1,x", "/api/v1/events?jobs=0",
          "/api/v1/events?jobs=1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,"
          "17,18,19,20,21,22,23,24,25,26,27,28,29,30,31,32,33,34,35,36,"
          "37,38,39,40,41,42,43,44,45,46,47,48,49,50,51,52,53,54,55,56,"
          "57,58,59,60,61,62,63,64,65"}) {
      const auto res = bad.send(http::verb::get, t);
      EXPECT_EQ(res.result_int(), 400) << t;
      EXPECT_EQ(body_of(res)["error"]["field"], "jobs") << t;
    }
  }
  Client sse(port_);
  sse.write_raw(
      "GET /api/v1/events?jobs=5,6 HTTP/1.1\r\nHost: 127.0.0.1\r\nAccept: text/event-stream\r\n\r\n");
  std::string text;
  ASSERT_FALSE(sse.read_raw_until("\"state\":\"queued\"", text)) << text;
  EXPECT_NE(text.find("HTTP/1.1 200"), std::string::npos);
  EXPECT_NE(text.find("Content-Type: text/event-stream"), std::string::npos);
  EXPECT_NE(text.find("Cache-Control: no-cache"), std::string::npos);
  EXPECT_NE(text.find("event: job\ndata: {"), std::string::npos);
  EXPECT_NE(text.find("\"id\":5"), std::string::npos);
  source_.set(5, "done", 1);
  ASSERT_FALSE(sse.read_raw_until("\"state\":\"done\"", text)) << text;
}

TEST(ListenPolicy, AddressesAndTokens) {
  EXPECT_EQ(parse_listen("127.0.0.1:8080").host, "127.0.0.1");
  EXPECT_EQ(parse_listen("127.0.0.1:8080").port, 8080);
  EXPECT_EQ(parse_listen("[::1]:9000").host, "::1");
  EXPECT_EQ(parse_listen("[::1]:9000").port, 9000);
  EXPECT_EQ(parse_listen("localhost:0").port, 0);
  for (const std::string bad : {"", "127.0.0.1", "127.0.0.1:", ":80", "127.0.0.1:65536", "127.0.0.1:-1",
                                "::1:80", "[::1]80", "[::1]", "example.com:80", "127.0.0.1:8o"}) {
    try {
      parse_listen(bad);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "--listen");
    }
  }
  EXPECT_TRUE(is_loopback("127.0.0.1"));
  EXPECT_TRUE(is_loopback("127.3.2.1"));
  EXPECT_TRUE(is_loopback("::1"));
  EXPECT_TRUE(is_loopback("localhost"));
  EXPECT_TRUE(is_loopback("::ffff:127.0.0.1"));
  EXPECT_FALSE(is_loopback("0.0.0.0"));
  EXPECT_FALSE(is_loopback("::"));
  EXPECT_FALSE(is_loopback("192.168.1.2"));

  ServerConfig cfg;
  EXPECT_NO_THROW(check_listen_policy(cfg));
  cfg.listen = "0.0.0.0:8080";
  try {
    check_listen_policy(cfg);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--listen");
    EXPECT_NE(std::string(e.what()).find("--token-file"), std::string::npos);
  }
  cfg.token = "0123456789abcdef";
  EXPECT_NO_THROW(check_listen_policy(cfg));

  EXPECT_TRUE(constant_time_equals("abc", "abc"));
  EXPECT_FALSE(constant_time_equals("abc", "abd"));
  EXPECT_FALSE(constant_time_equals("abc", "abcd"));
  EXPECT_FALSE(constant_time_equals("", "a"));
  EXPECT_TRUE(constant_time_equals("", ""));
}

TEST(StaticDir, ReadsServedFilesOnly) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("uavcover-static-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "assets");
  fs::create_directories(dir / ".git");
  auto write = [](const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; };
  write(dir / "index.html", "<html></html>");
  write(dir / "assets" / "app.js", "let a = 1;");
  write(dir / "assets" / "logo.png", std::string("\x89PNG\0\1", 6));
  write(dir / "notes.xyz", "unknown");
  write(dir / ".git" / "config.txt", "hidden");
  fs::create_symlink("/etc/passwd", dir / "passwd.txt");
  const auto files = io::read_static_dir(dir, 1 << 20);
  std::map<std::string, std::string> types;
  for (const auto& f : files) types[f.name] = f.media_type;
  EXPECT_EQ(types.size(), 3U);
  EXPECT_EQ(types["index.html"], "text/html; charset=utf-8");
  EXPECT_EQ(types["assets/app.js"], "text/javascript; charset=utf-8");
  EXPECT_EQ(types["assets/logo.png"], "image/png");
  for (const auto& f : files) {
    if (f.name == "assets/logo.png") {
      EXPECT_EQ(f.bytes.size(), 6U);
    }
  }
  try {
    io::read_static_dir(dir, 20);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--static");
  }
  EXPECT_THROW(io::read_static_dir(dir / "index.html", 1 << 20), InputError);
  EXPECT_THROW(io::read_static_dir(dir / "missing", 1 << 20), InputError);
  fs::remove_all(dir);
}

}  // namespace

namespace {

TEST(EventHub, SendsChangesOnlyAndDropsGoneSubscribers) {
  MapSource source;
  source.set(1, "queued", 0);
  EventHub hub(source, std::chrono::milliseconds(10));
  hub.start();
  std::mutex m;
  std::condition_variable cv;
  std::vector<json> got;
  const auto sub = hub.open([&](const std::string& text) {
    const std::lock_guard lock(m);
    got.push_back(json::parse(text));
    cv.notify_all();
    return true;
  });
  auto wait_for = [&](std::size_t n) {
    std::unique_lock lock(m);
    return cv.wait_for(lock, std::chrono::seconds(10), [&] { return got.size() >= n; });
  };
  EXPECT_FALSE(hub.subscribe(sub, {1, 2, 3}, 2));  // over the cap: none added
  EXPECT_TRUE(hub.subscribe(sub, {1, 2}, 2));
  ASSERT_TRUE(wait_for(1));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // several polls, no change
  {
    const std::lock_guard lock(m);
    ASSERT_EQ(got.size(), 1U);
    EXPECT_EQ(got[0]["type"], "job");
    EXPECT_EQ(got[0]["job"]["id"], 1);
  }
  source.set(2, "running", 0.1);  // job 2 appears
  ASSERT_TRUE(wait_for(2));
  hub.unsubscribe(sub, {1});
  EXPECT_TRUE(hub.subscribe(sub, {1}, 2));  // again: the current state is sent again
  ASSERT_TRUE(wait_for(3));
  {
    const std::lock_guard lock(m);
    EXPECT_EQ(got[1]["job"]["id"], 2);
    EXPECT_EQ(got[2]["job"]["id"], 1);
  }
  // a sink reporting its subscriber gone is dropped
  const auto gone = hub.open([](const std::string&) { return false; });
  hub.subscribe(gone, {1}, 10);
  for (int i = 0; i < 500 && hub.subscriber_count() != 1; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(hub.subscriber_count(), 1U);
  hub.close(sub);
  EXPECT_EQ(hub.subscriber_count(), 0U);
  hub.stop();
}

TEST(EventHub, ParsesFlightSubscriptionsBesideJobs) {
  auto m = parse_client_message(R"({"subscribe": {"jobs": [1], "flights": [7, 8]}})", 64);
  ASSERT_EQ(m.op, ClientMessage::Op::Subscribe) << m.error_message;
  EXPECT_EQ(m.jobs, (std::vector<std::int64_t>{1}));
  EXPECT_EQ(m.flights, (std::vector<std::int64_t>{7, 8}));
  m = parse_client_message(R"({"unsubscribe": {"flights": [8]}})", 64);
  ASSERT_EQ(m.op, ClientMessage::Op::Unsubscribe);
  EXPECT_TRUE(m.jobs.empty());
  EXPECT_EQ(m.flights, (std::vector<std::int64_t>{8}));
  m = parse_client_message(R"({"subscribe": {"flights": [3, 0]}})", 64);
  EXPECT_EQ(m.op, ClientMessage::Op::Invalid);
  EXPECT_EQ(m.error_field, "subscribe.flights[1]");
  m = parse_client_message(R"({"subscribe": {"flights": [1, 2, 3]}})", 2);
  EXPECT_EQ(m.op, ClientMessage::Op::Invalid);
  EXPECT_EQ(m.error_field, "subscribe.flights");
  m = parse_client_message(R"({"subscribe": {"planes": [1]}})", 64);
  EXPECT_EQ(m.op, ClientMessage::Op::Invalid);
  EXPECT_EQ(m.error_field, "subscribe");
  m = parse_client_message(R"({"subscribe": {}})", 64);
  EXPECT_EQ(m.op, ClientMessage::Op::Invalid);
}

// A flight that changes on every look is sent at most once per flight period (200 ms), never per poll.
TEST(EventHub, SendsAChangingFlightAtMostEveryFlightPeriod) {
  struct Changing : MapSource {
    std::atomic<int> looks{0};
    std::vector<json> flights(const std::vector<std::int64_t>& ids) override {
      std::vector<json> out;
      for (const auto id : ids) out.push_back({{"id", id}, {"look", ++looks}});
      return out;
    }
  } source;
  EventHub hub(source, std::chrono::milliseconds(10), std::chrono::milliseconds(200));
  hub.start();
  std::mutex m;
  std::vector<std::pair<std::chrono::steady_clock::time_point, json>> got;
  const auto sub = hub.open([&](const std::string& text) {
    const std::lock_guard lock(m);
    got.emplace_back(std::chrono::steady_clock::now(), json::parse(text));
    return true;
  });
  EXPECT_FALSE(hub.subscribe_flights(sub, {1, 2, 3}, 2));
  ASSERT_TRUE(hub.subscribe_flights(sub, {5}, 2));
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  hub.stop();
  const std::lock_guard lock(m);
  ASSERT_GE(got.size(), 1U) << "the first state is sent at once";
  for (const auto& [t, message] : got) {
    EXPECT_EQ(message["type"], "flight");
    EXPECT_EQ(message["flight"]["id"], 5);
  }
  for (std::size_t i = 1; i < got.size(); ++i)
    EXPECT_GE(got[i].first - got[i - 1].first, std::chrono::milliseconds(150)) << "message " << i;
}

class CaptureSink : public spdlog::sinks::base_sink<std::mutex> {
 public:
  std::vector<std::string> lines() {
    const std::lock_guard lock(mutex_);
    return lines_;
  }

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    lines_.emplace_back(msg.payload.data(), msg.payload.size());
  }
  void flush_() override {}

 private:
  std::vector<std::string> lines_;
};

TEST_F(ServerHttp, JsonRequestLog) {
  auto sink = std::make_shared<CaptureSink>();
  auto previous = spdlog::default_logger();
  spdlog::set_default_logger(std::make_shared<spdlog::logger>("capture", sink));
  spdlog::set_level(spdlog::level::info);
  ServerConfig cfg;
  cfg.log_json = true;
  start(cfg);
  {
    Client c(port_);
    c.send(http::verb::get, "/api/v1/things/42", "", {{"X-Request-Id", "log-test-1"}});
  }
  stop();
  spdlog::set_default_logger(previous);
  spdlog::set_level(spdlog::level::warn);
  bool found = false;
  for (const auto& line : sink->lines()) {
    const auto j = json::parse(line, nullptr, false);
    if (j.is_discarded() || j.value("request_id", "") != "log-test-1") continue;
    found = true;
    EXPECT_EQ(j["method"], "GET");
    EXPECT_EQ(j["route"], "/api/v1/things/{id}");
    EXPECT_EQ(j["status"], 200);
    EXPECT_TRUE(j["duration_ms"].is_number());
    EXPECT_TRUE(j["bytes"].is_number_unsigned());
  }
  EXPECT_TRUE(found);
}

}  // namespace

// ---- hardening (issue 28) ----

/// Everything a raw request gets back until the server closes the connection.
std::string raw_exchange(std::uint16_t port, const std::string& request) {
  Client c(port);
  c.write_raw(request);
  std::string text;
  c.read_raw_until("", text);  // until the connection ends (an error), bounded by kWait
  return text;
}

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + 1)) ++n;
  return n;
}

/// A handler that holds until released: the hook a test uses to keep a request "running".
class Hold {
 public:
  Response enter() {
    std::unique_lock lock(mutex_);
    ++entered_;
    changed_.notify_all();
    changed_.wait(lock, [&] { return released_; });
    return Response::json(200, {{"held", true}});
  }
  bool wait_entered(int n) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, kWait, [&] { return entered_ >= n; });
  }
  void release() {
    const std::lock_guard lock(mutex_);
    released_ = true;
    changed_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  int entered_ = 0;
  bool released_ = false;
};

TEST_F(ServerHttp, HandlersRunOffTheIoThreadsOnABoundedPool) {
  Hold hold;
  router_.add("GET", "/api/v1/hold", [&hold](const Request&) { return hold.enter(); });
  ServerConfig cfg;
  cfg.io_threads = 1;  // one I/O thread: a handler running on it would hold every other connection
  cfg.handler_threads = 1;
  cfg.max_pending = 1;
  start(cfg);
  Res held;
  std::thread first([&] {
    Client c(port_);
    held = c.send(http::verb::get, "/api/v1/hold");
  });
  ASSERT_TRUE(hold.wait_entered(1));
  // the handler is held: /healthz and static answers still come from the I/O thread
  Client probe(port_);
  EXPECT_EQ(probe.send(http::verb::get, "/healthz").result_int(), 200);
  EXPECT_EQ(probe.send(http::verb::get, "/").result_int(), 200);
  // the pool admits max_pending requests; the next one is told to come back
  const auto busy = probe.send(http::verb::get, "/api/v1/things/1");
  EXPECT_EQ(busy.result_int(), 503);
  EXPECT_EQ(busy[http::field::retry_after], "1");
  EXPECT_TRUE(body_of(busy)["error"]["message"].is_string());
  hold.release();
  first.join();
  EXPECT_EQ(held.result_int(), 200);
  EXPECT_EQ(body_of(held)["held"], true);
  EXPECT_EQ(probe.send(http::verb::get, "/api/v1/things/1").result_int(), 200);
}

// a handler's header over Beast's 64 KiB field limit ended the connection with no answer (the export
// warnings of a large plan did): it is left out, and the answer and the connection stay
TEST_F(ServerHttp, AnOversizedResponseHeaderIsLeftOutNotTheAnswer) {
  router_.add("GET", "/api/v1/huge-header", [](const Request&) {
    Response r = Response::json(200, {{"ok", true}});
    r.headers.emplace_back("X-Huge", std::string(150 * 1024, 'w'));
    r.headers.emplace_back("X-Small", "kept");
    return r;
  });
  start(ServerConfig{});
  Client c(port_);
  const auto res = c.send(http::verb::get, "/api/v1/huge-header");
  EXPECT_EQ(res.result_int(), 200);
  EXPECT_EQ(body_of(res)["ok"], true);
  EXPECT_EQ(res.count("X-Huge"), 0u);
  EXPECT_EQ(res["X-Small"], "kept");
  // the same connection answers the next request
  EXPECT_EQ(c.send(http::verb::get, "/healthz").result_int(), 200);
}

TEST_F(ServerHttp, AFlightsControlsAnswerWhileEveryHandlerThreadIsHeld) {
  Hold hold;
  router_.add("GET", "/api/v1/hold", [&hold](const Request&) { return hold.enter(); });
  router_.add("POST", "/api/v1/flights/{id}/commands", [](const Request&) {
    return Response::json(202, {{"command", "abort"}});
  });
  router_.add("DELETE", "/api/v1/flights/{id}", [](const Request&) { return Response::json(200, {}); });
  ServerConfig cfg;
  cfg.handler_threads = 2;
  cfg.max_pending = 2;
  start(cfg);
  std::vector<Res> held(2);
  std::vector<std::thread> holders;
  for (int i = 0; i < 2; ++i)
    holders.emplace_back([&, i] {
      Client c(port_);
      held[static_cast<std::size_t>(i)] = c.send(http::verb::get, "/api/v1/hold");
    });
  ASSERT_TRUE(hold.wait_entered(2));
  Client operator_(port_);
  // every handler thread is held and their queue is full, yet an abort and a flight's DELETE are served
  EXPECT_EQ(operator_.send(http::verb::get, "/api/v1/things/1").result_int(), 503);
  EXPECT_EQ(
      operator_.send(http::verb::post, "/api/v1/flights/3/commands", R"({"command": "abort"})").result_int(),
      202);
  EXPECT_EQ(operator_.send(http::verb::delete_, "/api/v1/flights/3").result_int(), 200);
  hold.release();
  for (auto& t : holders) t.join();
  for (const auto& r : held) EXPECT_EQ(r.result_int(), 200);
}

TEST_F(ServerHttp, HostHeaderAndAbsoluteForm) {
  ServerConfig cfg;
  cfg.allowed_hosts = {"uav.example.org"};
  start(cfg);
  const std::string port = std::to_string(port_);
  const auto status_of = [](const std::string& text) { return text.substr(0, 12); };
  // DNS rebinding: a foreign name is refused, and the connection closes
  EXPECT_EQ(status_of(raw_exchange(port_, "GET /api/v1/things/1 HTTP/1.1\r\nHost: attacker.example\r\n\r\n")),
            "HTTP/1.1 421");
  EXPECT_EQ(status_of(raw_exchange(port_, "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1:1\r\n\r\n")),
            "HTTP/1.1 421");  // our name, another port
  // RFC 9112: no Host, or two, is 400
  EXPECT_EQ(status_of(raw_exchange(port_, "GET /healthz HTTP/1.1\r\n\r\n")), "HTTP/1.1 400");
  const auto two = raw_exchange(port_, "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nHost: 127.0.0.1\r\n\r\n");
  EXPECT_EQ(status_of(two), "HTTP/1.1 400");
  EXPECT_NE(two.find("\"field\":\"host\""), std::string::npos) << two;
  // HTTP/1.0 may leave Host out
  EXPECT_EQ(status_of(raw_exchange(port_, "GET /healthz HTTP/1.0\r\n\r\n")), "HTTP/1.0 200");
  Client c(port_);
  for (const std::string& host :
       std::vector<std::string>{"127.0.0.1:" + port, "localhost:" + port, "[::1]:" + port, "LOCALHOST",
                                "uav.example.org", "uav.example.org:443", "UAV.example.org."}) {
    const auto res = c.send(http::verb::get, "/api/v1/things/2", "", {{"Host", host}});
    EXPECT_EQ(res.result_int(), 200) << host;
  }
  // the absolute form is accepted; its authority is the host that is checked
  const auto absolute = c.send(http::verb::get, "http://127.0.0.1:" + port + "/api/v1/things/3?x=1", "",
                               {{"Host", "127.0.0.1"}});
  EXPECT_EQ(absolute.result_int(), 200);
  EXPECT_EQ(body_of(absolute)["path"], "/api/v1/things/3");
  EXPECT_EQ(body_of(absolute)["query"]["x"], "1");
  EXPECT_EQ(c.send(http::verb::get, "http://127.0.0.1/healthz").result_int(), 200);
  EXPECT_EQ(status_of(raw_exchange(
                port_, "GET http://attacker.example/healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")),
            "HTTP/1.1 421");
}

TEST_F(ServerHttp, ForeignOriginsAreRefused) {
  start();
  const std::string own = "http://127.0.0.1:" + std::to_string(port_);
  Client c(port_);
  // the server's own origin (the web app it serves) and no Origin at all (curl) may call
  EXPECT_EQ(c.send(http::verb::get, "/api/v1/things/1", "",
                   {{"Host", "127.0.0.1:" + std::to_string(port_)}, {"Origin", own}})
                .result_int(),
            200);
  EXPECT_EQ(c.send(http::verb::get, "/api/v1/things/1").result_int(), 200);
  for (const std::string origin :
       {"http://evil.example", "null", "http://127.0.0.1:1", "https://127.0.0.1.evil"}) {
    Client d(port_);
    const auto res = d.send(http::verb::post, "/api/v1/things", "{}",
                            {{"Host", "127.0.0.1:" + std::to_string(port_)}, {"Origin", origin}});
    EXPECT_EQ(res.result_int(), 403) << origin;
    EXPECT_EQ(body_of(res)["error"]["field"], "origin") << origin;
  }
  // a WebSocket upgrade from a foreign page is refused too
  WsClient foreign(port_, {{"Origin", "http://evil.example"}});
  EXPECT_TRUE(foreign.handshake_error);
  WsClient same(port_, {{"Origin", "http://127.0.0.1"}});  // WsClient sends Host: 127.0.0.1
  EXPECT_FALSE(same.handshake_error) << same.handshake_error.message();
}

TEST_F(ServerHttp, CorsOriginMayCallAndOthersMayNot) {
  ServerConfig cfg;
  cfg.cors_origin = "https://app.example";
  start(cfg);
  Client c(port_);
  EXPECT_EQ(
      c.send(http::verb::post, "/api/v1/things", "{}", {{"Origin", "https://app.example"}}).result_int(),
      201);
  Client d(port_);
  EXPECT_EQ(
      c.send(http::verb::post, "/api/v1/things", "{}", {{"Origin", "https://other.example"}}).result_int(),
      403);
}

// the importer's upload is the one non-JSON body the API takes: multipart/form-data on POST
// /api/v1/missions/import only, and never from a foreign Origin
TEST_F(ServerHttp, MultipartOnlyForTheImportUpload) {
  router_.add("POST", "/api/v1/missions/import", [](const Request& req) {
    return Response::json(200, {{"bytes", req.body.size()}});
  });
  start();
  const auto status_of = [](const std::string& text) { return text.substr(0, 12); };
  const std::string body =
      "--b\r\nContent-Disposition: form-data; name=\"file\"; filename=\"f.kml\"\r\n\r\nx\r\n--b--\r\n";
  const auto upload = [&](const std::string& path, const std::string& extra) {
    return raw_exchange(port_, "POST " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\n" + extra +
                                   "Content-Type: multipart/form-data; boundary=b\r\nContent-Length: " +
                                   std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body);
  };
  const auto ok = upload("/api/v1/missions/import", "");
  EXPECT_EQ(status_of(ok), "HTTP/1.1 200") << ok;
  EXPECT_EQ(status_of(upload("/api/v1/things", "")), "HTTP/1.1 415");
  EXPECT_EQ(status_of(upload("/api/v1/missions/import", "Origin: https://attacker.example\r\n")),
            "HTTP/1.1 403");
}

TEST_F(ServerHttp, JsonBodiesOnlyAndNoContentCoding) {
  start();
  const auto status_of = [](const std::string& text) { return text.substr(0, 12); };
  // a browser's cross-site Blob body has no Content-Type: refused before the body is read
  const auto blob =
      raw_exchange(port_, "POST /api/v1/things HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 2\r\n\r\n{}");
  EXPECT_EQ(status_of(blob), "HTTP/1.1 415");
  EXPECT_NE(blob.find("Content-Type: application/json"), std::string::npos) << blob;
  EXPECT_EQ(status_of(raw_exchange(port_,
                                   "POST /api/v1/things HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: "
                                   "text/plain\r\nContent-Length: 2\r\n\r\n{}")),
            "HTTP/1.1 415");
  for (const std::string coding : {"gzip", "br", "identity, gzip"}) {
    const auto res =
        raw_exchange(port_,
                     "POST /api/v1/things HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
                     "Content-Encoding: " +
                         coding + "\r\nContent-Length: 2\r\n\r\n{}");
    EXPECT_EQ(status_of(res), "HTTP/1.1 415") << coding;
    EXPECT_NE(res.find("content-encoding"), std::string::npos) << res;
  }
  Client c(port_);
  EXPECT_EQ(c.send(http::verb::post, "/api/v1/things", "{}", {{"Content-Encoding", "identity"}}).result_int(),
            201);
  // no body needs no Content-Type
  EXPECT_EQ(c.send(http::verb::post, "/api/v1/things").result_int(), 201);
}

TEST_F(ServerHttp, TransferEncodingOtherThanChunkedIsNotSmuggled) {
  start();
  // the answer without its X-Request-Id line (16 random hex digits may hold "666" themselves: 1 in ~300)
  auto mentions_666 = [](const std::string& text) {
    std::string kept;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
      if (!line.starts_with("X-Request-Id:")) kept += line + "\n";
    return kept.find("666") != std::string::npos;
  };
  // the "body" is a second request: it must never be answered
  const std::string smuggled = "GET /api/v1/things/666 HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
  for (const std::string te :
       {"Transfer-Encoding: xchunked\r\n", "Transfer-Encoding: chunked, identity\r\n",
        "Transfer-Encoding: identity\r\n", "Transfer-Encoding: chunked\r\nTransfer-Encoding: chunked\r\n"}) {
    const auto text = raw_exchange(port_,
                                   "POST /api/v1/things HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: "
                                   "application/json\r\n" +
                                       te + "\r\n" + smuggled);
    EXPECT_TRUE(text.rfind("HTTP/1.1 501", 0) == 0 || text.rfind("HTTP/1.1 400", 0) == 0) << te << text;
    EXPECT_EQ(count_of(text, "HTTP/1.1 "), 1U) << te << text;
    EXPECT_FALSE(mentions_666(text)) << te << text;
  }
  const auto both =
      raw_exchange(port_,
                   "POST /api/v1/things HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
                   "Content-Length: 5\r\nTransfer-Encoding: chunked\r\n\r\n0\r\n\r\n" +
                       smuggled);
  EXPECT_EQ(count_of(both, "HTTP/1.1 "), 1U) << both;
  EXPECT_FALSE(mentions_666(both)) << both;
  // chunked itself works
  Client c(port_);
  c.write_raw(
      "POST /api/v1/things HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: "
      "application/json\r\nTransfer-Encoding: "
      "Chunked\r\n\r\n2\r\n{}\r\n0\r\n\r\n");
  const auto res = c.read();
  EXPECT_EQ(res.result_int(), 201);
  EXPECT_EQ(body_of(res)["size"], 2);
}

TEST_F(ServerHttp, TokenIsCheckedBeforeTheBodyIsRead) {
  ServerConfig cfg;
  cfg.token = "0123456789abcdef-secret";
  cfg.max_body = std::size_t{10} << 20;
  start(cfg);
  Client c(port_);
  // headers of a 9 MB body, and none of the body: the 401 comes anyway
  c.write_raw(
      "POST /api/v1/things HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: "
      "application/json\r\nContent-Length: " +
      std::to_string(9 << 20) + "\r\n\r\n");
  const auto res = c.read();
  EXPECT_EQ(res.result_int(), 401);
  EXPECT_EQ(res[http::field::www_authenticate], "Bearer");
  EXPECT_FALSE(res.keep_alive());
  // with the token, the body is read as before
  Client ok(port_);
  EXPECT_EQ(
      ok.send(http::verb::post, "/api/v1/things", "{}", {{"Authorization", "Bearer 0123456789abcdef-secret"}})
          .result_int(),
      201);
}

TEST_F(ServerHttp, HeadAnswersEveryGetRouteWithoutABody) {
  start();
  // two requests on one connection: a body after the HEAD answer would desync the second
  Client c(port_);
  c.write_raw(
      "HEAD /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\nHEAD /api/v1/things/5 HTTP/1.1\r\nHost: "
      "127.0.0.1\r\n\r\n"
      "GET /api/v1/things/6 HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
  std::string text;
  ASSERT_FALSE(c.read_raw_until("\"id\":\"6\"", text)) << text;
  ASSERT_EQ(count_of(text, "HTTP/1.1 200 OK\r\n"), 3U) << text;
  const auto first_end = text.find("\r\n\r\n");
  EXPECT_EQ(text.find("HTTP/1.1 200 OK\r\n", first_end), first_end + 4)
      << "a body followed the HEAD answer: " << text;
  EXPECT_NE(text.find("Content-Length: 15\r\n"), std::string::npos) << text;  // {"status":"ok"}
  EXPECT_EQ(text.find("\"5\""), std::string::npos) << text;
  // a path without GET: 405 listing the methods (HEAD beside GET), without a body
  const auto put_only =
      raw_exchange(port_, "HEAD /api/v1/nope HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(put_only.substr(0, 12), "HTTP/1.1 404");
  EXPECT_EQ(put_only.find("{"), std::string::npos) << put_only;
  Client d(port_);
  const auto allowed = d.send(http::verb::delete_, "/api/v1/things/3");
  EXPECT_EQ(allowed[http::field::allow], "GET, HEAD, PUT");
}

/// A job that changes on every poll, with a large JSON: a subscriber that never reads falls behind.
class FloodSource : public EventSource {
 public:
  std::vector<json> snapshot(const std::vector<std::int64_t>& ids) override {
    const std::lock_guard lock(mutex_);
    ++polls_;
    std::vector<json> out;
    for (const auto id : ids)
      out.push_back({{"id", id},
                     {"state", "running"},
                     {"progress", 0.5},
                     {"stage", std::to_string(polls_)},
                     {"updated", std::string(100 * 1024, 'x')}});
    return out;
  }
  int polls() {
    const std::lock_guard lock(mutex_);
    return polls_;
  }

 private:
  std::mutex mutex_;
  int polls_ = 0;
};

TEST(ServerEvents, AWebSocketThatDoesNotReadIsClosedAtTheByteCap) {
  spdlog::set_level(spdlog::level::err);
  FloodSource source;
  Router router;
  ServerConfig cfg;
  cfg.listen = "127.0.0.1:0";
  cfg.event_poll = std::chrono::milliseconds(1);
  cfg.max_event_queue_bytes = 1 << 20;  // 1 MiB: ten of the 100 kB messages
  HttpServer server(cfg, router, source);
  std::thread runner([&] { server.run(); });
  {
    net::io_context ioc;
    tcp::socket socket(ioc);
    socket.open(tcp::v4());
    socket.set_option(net::socket_base::receive_buffer_size(4096));  // the kernel holds little for us
    socket.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), server.port()));
    websocket::stream<tcp::socket> ws(std::move(socket));
    ws.handshake("127.0.0.1", "/api/v1/events");
    ws.write(net::buffer(std::string(R"({"subscribe": {"jobs": [1]}})")));
    // every poll makes a 100 kB message for a reader that takes none: the server drops the client
    // once 1 MiB waits for it (the hook: the drop counter; polls stop with the subscription)
    const auto dropped_before = metrics().dropped_event_clients();
    std::uint64_t dropped = dropped_before;
    for (int i = 0; i < 6000 && dropped == dropped_before; ++i) {  // bounded: 60 s at most
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      dropped = metrics().dropped_event_clients();
    }
    ASSERT_EQ(dropped, dropped_before + 1);
    int received = 0;
    beast::error_code ec;
    for (;;) {
      beast::flat_buffer buffer;
      ws.read(buffer, ec);
      if (ec) break;
      ++received;
    }
    EXPECT_TRUE(ec) << "the connection was not closed";
    // what the kernel buffers held and the one being written, not the polls' hundreds of messages
    EXPECT_LT(received, source.polls());
  }
  server.stop();
  runner.join();
}

TEST(HttpHelpers, HostsOriginsIdsAndTargets) {
  HostPolicy p{"127.0.0.1", 8080, {"uav.example.org"}};
  EXPECT_TRUE(host_allowed("127.0.0.1:8080", p));
  EXPECT_TRUE(host_allowed("127.0.0.1", p));
  EXPECT_TRUE(host_allowed("[::1]:8080", p));
  EXPECT_TRUE(host_allowed("Localhost:8080", p));
  EXPECT_TRUE(host_allowed("uav.example.org:8443", p));
  EXPECT_FALSE(host_allowed("127.0.0.1:8081", p));
  EXPECT_FALSE(host_allowed("evil.example:8080", p));
  EXPECT_FALSE(host_allowed("10.0.0.1:8080", p));
  EXPECT_FALSE(host_allowed("", p));
  EXPECT_FALSE(host_allowed("127.0.0.1:", p));
  EXPECT_FALSE(host_allowed("127.0.0.1:99999", p));
  EXPECT_FALSE(host_allowed("a b", p));
  EXPECT_FALSE(host_allowed("[::1", p));
  const HostPolicy any{"0.0.0.0", 8080, {}};
  EXPECT_TRUE(host_allowed("10.0.0.1:8080", any));  // an address literal cannot be rebound
  EXPECT_FALSE(host_allowed("evil.example:8080", any));
  EXPECT_TRUE(origin_allowed("http://127.0.0.1:8080", "127.0.0.1:8080", std::nullopt));
  EXPECT_FALSE(origin_allowed("http://127.0.0.1:8080", "127.0.0.1:9090", std::nullopt));
  EXPECT_FALSE(origin_allowed("null", "127.0.0.1:8080", std::nullopt));
  EXPECT_TRUE(origin_allowed("https://App.example", "127.0.0.1:8080", std::string("https://app.example")));
  EXPECT_FALSE(
      origin_allowed("https://app.example.evil", "127.0.0.1:8080", std::string("https://app.example")));
  EXPECT_EQ(media_type(" Application/JSON ; charset=utf-8"), "application/json");
  EXPECT_EQ(parse_id("12"), 12);
  for (const std::string bad : {"012", "0", "+1", "-1", " 1", "1x", ""})
    EXPECT_THROW(parse_id(bad), HttpError) << bad;
  EXPECT_EQ(target_authority("http://127.0.0.1:80/x"), "127.0.0.1:80");
  EXPECT_EQ(target_authority("/x"), std::nullopt);
  Request r;
  decode_target("HTTP://h/a%20b?q=1", r);
  EXPECT_EQ(r.path, "/a b");
  EXPECT_EQ(r.query["q"], "1");
  Request root;
  decode_target("http://h?q=2", root);
  EXPECT_EQ(root.path, "/");
  EXPECT_EQ(root.query["q"], "2");
}
