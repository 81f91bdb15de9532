// Internal to src/server: what the Boost.Beast sessions behind HttpServer share (the limits, the text
// helpers, the Core every session reaches, the conversion of a Response) and how each kind of session
// starts: plain HTTP (http_session.cpp), the WebSocket (ws_session.cpp) and Server-Sent Events
// (sse_session.cpp). The listener is in server.cpp. One strand per connection.
#pragma once

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/thread_pool.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include "server/events.hpp"
#include "server/http.hpp"
#include "server/metrics.hpp"
#include "server/server.hpp"

namespace uavcover::server::detail {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

inline constexpr std::size_t kHeaderLimit = 16 * 1024;
inline constexpr std::size_t kWsMessageMax = 64 * 1024;
inline constexpr std::size_t kMaxPendingMessages = 1000;
inline constexpr std::size_t kMaxConnections = 10000;
inline constexpr std::size_t kMaxPendingProbes = 16;    // /readyz and /metrics waiting for the probe thread
inline constexpr std::size_t kMaxPendingControls = 32;  // flight controls waiting for the control thread

/// A live flight's controls: `POST /api/v1/flights/{id}/commands`, `GET` and `DELETE
/// /api/v1/flights/{id}` (the router's route pattern).
inline bool is_flight_control(const std::string& method, const std::string& route) {
  static const std::string flight = "/api/v1/flights/{id}";
  return (route == flight && (method == "GET" || method == "DELETE")) ||
         (route == flight + "/commands" && method == "POST");
}
inline constexpr std::size_t kDrainBytes = std::size_t{64} << 20;  // bounded by the 2 s linger too
inline constexpr const char* kEventsPath = "/api/v1/events";

inline constexpr const char* kIndexPage =
    "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>uavcover</title></head>\n"
    "<body><h1>uavcover</h1><p>The multi-UAV coverage planner's HTTP API.</p>\n"
    "<ul><li><a href=\"/api/v1/openapi.json\">OpenAPI description (/api/v1/openapi.json)</a></li>\n"
    "<li>docs/api.md in the source tree: the guide</li>\n"
    "<li><a href=\"/healthz\">/healthz</a>, <a href=\"/metrics\">/metrics</a></li></ul></body></html>\n";

// ---- small text helpers ----

inline std::string_view sv(beast::string_view s) { return {s.data(), s.size()}; }

inline bool valid_request_id(std::string_view id) {
  if (id.empty() || id.size() > 64) return false;
  return std::all_of(id.begin(), id.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
  });
}

inline std::string trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return "";
  return std::string(s.substr(first, s.find_last_not_of(" \t") - first + 1));
}

inline std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

/// The longest response header value sent (Beast's own limit is 64 KiB; the export warnings header keeps
/// to 4 KiB of its own accord).
inline constexpr std::size_t kMaxHeaderValue = 32 * 1024;

/// Header values from handlers may carry user text (file names): no CR, LF or NUL gets through.
inline std::string header_safe(std::string_view v) {
  std::string out;
  out.reserve(v.size());
  for (const char c : v)
    if (c != '\r' && c != '\n' && c != '\0') out += c;
  return out;
}

/// Methods as metric labels: unknown ones share one label, so clients cannot grow the registry.
inline std::string method_label(const std::string& m) {
  static const std::set<std::string> known{"GET", "POST", "PUT", "DELETE", "PATCH", "HEAD", "OPTIONS"};
  return known.count(m) ? m : "other";
}

inline std::string utc_now() {
  const auto now = std::chrono::system_clock::now();
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  return fmt::format("{:%Y-%m-%dT%H:%M:%S}.{:03d}Z", fmt::gmtime(std::chrono::system_clock::to_time_t(now)),
                     static_cast<int>(ms));
}

inline std::uint64_t splitmix64(std::uint64_t x) {
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

  /// A request's place in a bounded pool's `load`, given back once: by release() (before the answer is
  /// handed to the connection, so that a client that has its answer and asks again is not told the pool
  /// is busy), or at the latest when the work ends.
  class PoolSlot {
   public:
    explicit PoolSlot(std::atomic<std::size_t>& load) : load_(load) {}
    PoolSlot(const PoolSlot&) = delete;
    PoolSlot& operator=(const PoolSlot&) = delete;
    ~PoolSlot() { release(); }
    void release() {
      if (held_) load_.fetch_sub(1);
      held_ = false;
    }

   private:
    std::atomic<std::size_t>& load_;
    bool held_ = true;
  };

  /// Posts `work` to `pool` unless `load` would exceed `max` or the server stops; false then. `work` is
  /// called with its PoolSlot when it takes one (`work(slot)`), else with nothing.
  template <class Work>
  bool post_bounded(net::thread_pool& pool, std::atomic<std::size_t>& load, std::size_t max, Work&& work) {
    const std::lock_guard lock(pool_mutex);
    if (pools_closed) return false;
    if (load.fetch_add(1) >= max) {
      load.fetch_sub(1);
      return false;
    }
    net::post(pool, [&load, work = std::forward<Work>(work)]() mutable {
      PoolSlot slot(load);
      if constexpr (std::is_invocable_v<Work&, PoolSlot&>)
        work(slot);
      else
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
inline StringResponse to_beast(Response&& r, unsigned version, bool keep_alive, const std::string& request_id,
                               const Core& core, bool head = false) {
  StringResponse res;
  res.version(version);
  res.result(static_cast<unsigned>(std::clamp(r.status, 100, 599)));
  res.set(http::field::server, "uavcover");
  if (r.status != 204 && r.status != 304) res.set(http::field::content_type, header_safe(r.content_type));
  auto headers = std::move(r.headers);
  core.add_cors(headers);
  for (const auto& [name, value] : headers) {
    // Beast refuses a field value of 64 KiB or more and the connection would end with no answer: such a
    // header (a handler's bug) is left out and logged, and the answer still goes out
    if (value.size() > kMaxHeaderValue) {
      spdlog::error("request {}: header {} of {} bytes left out (over {} bytes)", request_id,
                    header_safe(name).substr(0, 64), value.size(), kMaxHeaderValue);
      continue;
    }
    res.set(header_safe(name), header_safe(value));
  }
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

inline std::string error_message(const std::string& field, const std::string& message) {
  return nlohmann::json{{"type", "error"}, {"error", {{"field", field}, {"message", message}}}}.dump(
      -1, ' ', false, nlohmann::json::error_handler_t::replace);
}

/// Hands the connection to a WebSocket session answering `req` (the upgrade request).
void start_websocket(tcp::socket&& socket, Core& core, http::request<http::string_body> req,
                     const std::string& request_id);
/// Hands the connection to an event stream of the jobs `ids` (HTTP `version`).
void start_sse(tcp::socket&& socket, Core& core, unsigned version, std::vector<std::int64_t> ids,
               const std::string& request_id);
/// Serves plain HTTP on an accepted connection.
void start_http(tcp::socket&& socket, Core& core);

}  // namespace uavcover::server::detail
