// The HTTP/1.1 + WebSocket transport (Boost.Beast, kept out of this header): sessions with header,
// body and idle timeouts, keep-alive, body and header limits, bearer-token auth, request ids,
// structured request logs, metrics, CORS, live job events (WebSocket and Server-Sent Events) at
// /api/v1/events, /healthz, /readyz, /metrics and static files. Requests are answered by the Router.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <stop_token>
#include <string>
#include <vector>

#include "server/events.hpp"
#include "server/http.hpp"

namespace uavcover::server {

/// A file served at a fixed URL path (the web app); bytes are held in memory.
struct StaticFile {
  std::string media_type;
  std::string bytes;
};

struct ServerConfig {
  std::string listen = "127.0.0.1:8080";  ///< "host:port" or "[v6]:port"; port 0 picks a free port
  int io_threads = 2;                     ///< threads reading and writing connections (no handler runs there)
  /// Threads running the API handlers (parsing, validation, geometry, database calls) off the I/O
  /// threads; at most `max_pending` requests wait for them or run (503 with Retry-After beyond).
  int handler_threads = 2;
  std::size_t max_pending = 64;
  std::size_t max_body = std::size_t{10} << 20;
  std::optional<std::string> token;        ///< when set, every request but /healthz, /readyz needs it
  std::optional<std::string> cors_origin;  ///< when set, CORS headers for this origin, and it may call
  /// Host names served besides the listen address, localhost, 127.0.0.1 and [::1] (a proxy's public
  /// name; any port). Any other Host gets 421 (DNS rebinding).
  std::vector<std::string> allowed_hosts;
  /// Bytes of live events a WebSocket or SSE connection may have waiting to be written; a client that
  /// falls further behind is closed (WebSocket close code 1013, try again later).
  std::size_t max_event_queue_bytes = std::size_t{4} << 20;
  std::chrono::seconds idle_timeout{30};    ///< between requests on a kept-alive connection, and per body
  std::chrono::seconds header_timeout{10};  ///< for the request line and headers of a new connection
  int max_subscriptions = 64;               ///< job subscriptions per WebSocket / SSE connection
  bool log_json = false;                    ///< request logs as one JSON object per line
  std::map<std::string, StaticFile> static_files;  ///< URL path ("/index.html") -> file
  /// /readyz: true when the store takes writes (unset: ready). Runs off the I/O threads.
  std::function<bool()> ready_check;
  /// run() returns when a stop is requested here (the CLI passes its SIGINT/SIGTERM token: signals
  /// are blocked in every thread of the uavcover process, so asio::signal_set would not see them).
  std::stop_token stop;
  std::chrono::milliseconds event_poll{100};  ///< how often subscribed jobs are polled
  std::chrono::seconds sse_keepalive{15};     ///< SSE comment interval
};

/// "host:port" / "[v6]:port" split; InputError("--listen", ...) when malformed.
struct ListenAddress {
  std::string host;  ///< without brackets
  std::uint16_t port = 0;
};
ListenAddress parse_listen(const std::string& listen);

/// The serve command's rule: a non-loopback address needs a token. InputError("--listen", ...) otherwise
/// (and when the address is malformed).
void check_listen_policy(const ServerConfig& config);

/// Compares in time independent of where the strings differ (the token check).
bool constant_time_equals(const std::string& a, const std::string& b);

class HttpServer {
 public:
  /// Binds the address (OperationError when it cannot; InputError for a malformed one). The router
  /// and the event source must outlive the server. The server owns an EventHub over `events`.
  HttpServer(ServerConfig config, Router& router, EventSource& events);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  /// The bound port (the one picked when the configured port is 0).
  [[nodiscard]] std::uint16_t port() const;
  /// Serves until stop(); open connections are closed then (WebSocket and SSE included).
  void run();
  /// Thread-safe; may be called before or during run().
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uavcover::server
