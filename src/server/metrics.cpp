#include "server/metrics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace uavcover::server {
namespace {

const std::vector<double>& http_buckets() {
  static const std::vector<double> b{0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10};
  return b;
}

const std::vector<double>& plan_buckets() {
  static const std::vector<double> b{0.1, 0.25, 0.5, 1, 2.5, 5, 10, 30, 60, 120, 300, 600, 1800};
  return b;
}

// Label values: backslash, double quote and line feed escaped (exposition format 0.0.4).
std::string escape_label(const std::string& v) {
  std::string out;
  out.reserve(v.size());
  for (const char c : v) {
    if (c == '\\')
      out += "\\\\";
    else if (c == '"')
      out += "\\\"";
    else if (c == '\n')
      out += "\\n";
    else
      out += c;
  }
  return out;
}

std::string number(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "+Inf" : "-Inf";
  return fmt::format("{}", v);
}

}  // namespace

void Metrics::observe(Histogram& h, const std::vector<double>& bounds, double value) {
  if (!std::isfinite(value) || value < 0) value = 0;
  if (h.counts.empty()) h.counts.assign(bounds.size() + 1, 0);
  const auto it = std::lower_bound(bounds.begin(), bounds.end(), value);  // le: value <= bound
  ++h.counts[static_cast<std::size_t>(it - bounds.begin())];
  h.sum += value;
  ++h.count;
}

void Metrics::observe_request(const std::string& route, const std::string& method, int code, double seconds) {
  const std::lock_guard lock(mutex_);
  ++requests_[{route, method, code}];
  observe(durations_[route], http_buckets(), seconds);
}

void Metrics::count_dropped_event_client() {
  const std::lock_guard lock(mutex_);
  ++dropped_event_clients_;
}

std::uint64_t Metrics::dropped_event_clients() const {
  const std::lock_guard lock(mutex_);
  return dropped_event_clients_;
}

void Metrics::observe_plan_duration(double seconds) {
  const std::lock_guard lock(mutex_);
  observe(plan_durations_, plan_buckets(), seconds);
}

void Metrics::set_job_counts_provider(std::function<std::map<std::string, std::int64_t>()> provider) {
  const std::lock_guard lock(mutex_);
  job_counts_ = std::move(provider);
}

void Metrics::render_histogram(std::string& out, const std::string& name, const std::string& labels,
                               const Histogram& h, const std::vector<double>& bounds) {
  const std::string sep = labels.empty() ? "" : ",";
  std::uint64_t cumulative = 0;
  for (std::size_t i = 0; i <= bounds.size(); ++i) {
    cumulative += h.counts.empty() ? 0 : h.counts[i];
    const std::string le = i < bounds.size() ? number(bounds[i]) : "+Inf";
    out += fmt::format("{}_bucket{{{}{}le=\"{}\"}} {}\n", name, labels, sep, le, cumulative);
  }
  const std::string braces = labels.empty() ? "" : "{" + labels + "}";
  out += fmt::format("{}_sum{} {}\n", name, braces, number(h.sum));
  out += fmt::format("{}_count{} {}\n", name, braces, h.count);
}

std::string Metrics::render() const {
  std::function<std::map<std::string, std::int64_t>()> provider;
  {
    const std::lock_guard lock(mutex_);
    provider = job_counts_;
  }
  std::map<std::string, std::int64_t> jobs;
  if (provider) jobs = provider();  // outside the lock: it may query the store

  const std::lock_guard lock(mutex_);
  std::string out;
  out += "# HELP uavcover_http_requests_total HTTP requests answered, by route pattern, method and status.\n";
  out += "# TYPE uavcover_http_requests_total counter\n";
  for (const auto& [key, n] : requests_) {
    const auto& [route, method, code] = key;
    out += fmt::format("uavcover_http_requests_total{{route=\"{}\",method=\"{}\",code=\"{}\"}} {}\n",
                       escape_label(route), escape_label(method), code, n);
  }
  out += "# HELP uavcover_http_request_duration_seconds Time to answer a request, by route pattern.\n";
  out += "# TYPE uavcover_http_request_duration_seconds histogram\n";
  for (const auto& [route, h] : durations_)
    render_histogram(out, "uavcover_http_request_duration_seconds", "route=\"" + escape_label(route) + "\"",
                     h, http_buckets());
  out += "# HELP uavcover_jobs Jobs in the store, by state.\n";
  out += "# TYPE uavcover_jobs gauge\n";
  for (const auto& [state, n] : jobs)
    out += fmt::format("uavcover_jobs{{state=\"{}\"}} {}\n", escape_label(state), n);
  out += "# HELP uavcover_event_clients_dropped_total Event clients closed for falling behind (queue cap).\n";
  out += "# TYPE uavcover_event_clients_dropped_total counter\n";
  out += fmt::format("uavcover_event_clients_dropped_total {}\n", dropped_event_clients_);
  out += "# HELP uavcover_plan_duration_seconds Planning time of finished plan jobs.\n";
  out += "# TYPE uavcover_plan_duration_seconds histogram\n";
  render_histogram(out, "uavcover_plan_duration_seconds", "", plan_durations_, plan_buckets());
  return out;
}

Metrics& metrics() {
  static Metrics m;
  return m;
}

void set_job_counts_provider(std::function<std::map<std::string, std::int64_t>()> provider) {
  metrics().set_job_counts_provider(std::move(provider));
}

void observe_plan_duration(double seconds) { metrics().observe_plan_duration(seconds); }

}  // namespace uavcover::server
