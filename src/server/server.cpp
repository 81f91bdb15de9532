// HttpServer: the listener (Boost.Beast) and its I/O threads, behind which the sessions run: plain HTTP
// (http_session.cpp), the WebSocket (ws_session.cpp) and Server-Sent Events (sse_session.cpp), over
// session_internal.hpp. Also the listen address and its policy.
#include "server/server.hpp"

#include <boost/asio/strand.hpp>
#include <thread>

#include "server/session_internal.hpp"
#include "uavcover/error.hpp"

namespace uavcover::server {

using namespace detail;

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
      start_http(std::move(socket), core);
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
