// Prometheus metrics of the server (text exposition format 0.0.4), process-wide and thread-safe.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <tuple>
#include <vector>

namespace uavcover::server {

class Metrics {
 public:
  /// One answered request: uavcover_http_requests_total{route,method,code} and
  /// uavcover_http_request_duration_seconds{route}.
  void observe_request(const std::string& route, const std::string& method, int code, double seconds);
  /// uavcover_event_clients_dropped_total: a WebSocket / SSE client closed for not reading.
  void count_dropped_event_client();
  [[nodiscard]] std::uint64_t dropped_event_clients() const;
  /// uavcover_plan_duration_seconds.
  void observe_plan_duration(double seconds);
  /// uavcover_jobs{state} is filled at scrape time from this callback (state -> count).
  void set_job_counts_provider(std::function<std::map<std::string, std::int64_t>()> provider);
  /// The exposition text (content type "text/plain; version=0.0.4").
  [[nodiscard]] std::string render() const;

 private:
  struct Histogram {
    std::vector<std::uint64_t> counts;  ///< per bucket (not cumulative), last one +Inf
    double sum = 0;
    std::uint64_t count = 0;
  };
  static void observe(Histogram& h, const std::vector<double>& bounds, double value);
  static void render_histogram(std::string& out, const std::string& name, const std::string& labels,
                               const Histogram& h, const std::vector<double>& bounds);

  mutable std::mutex mutex_;
  std::map<std::tuple<std::string, std::string, int>, std::uint64_t> requests_;
  std::map<std::string, Histogram> durations_;
  Histogram plan_durations_;
  std::uint64_t dropped_event_clients_ = 0;
  std::function<std::map<std::string, std::int64_t>()> job_counts_;
};

/// The process-wide registry the server renders at GET /metrics.
Metrics& metrics();
void set_job_counts_provider(std::function<std::map<std::string, std::int64_t>()> provider);
void observe_plan_duration(double seconds);

inline constexpr const char* kMetricsContentType = "text/plain; version=0.0.4; charset=utf-8";

}  // namespace uavcover::server
