// Live job events: the API side implements EventSource over the store; EventHub polls it for the
// jobs subscribers follow and hands each subscriber the jobs whose JSON changed since it last got them.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "server/http.hpp"

namespace uavcover::server {

/// A WebSocket client message on /api/v1/events, parsed: {"subscribe": {"jobs": [ids], "flights": [ids]}}
/// or {"unsubscribe": {...}} with either list or both.
struct ClientMessage {
  enum class Op { Subscribe, Unsubscribe, Invalid };
  Op op = Op::Invalid;
  std::vector<std::int64_t> jobs;     ///< positive ids, in the message's order; at most `max` to subscribe
  std::vector<std::int64_t> flights;  ///< likewise (docs/flights.md)
  std::string error_field;            ///< when Invalid: the field ("", "subscribe.jobs[2]", ...)
  std::string error_message;          ///< when Invalid: what is wrong
};
/// Parses one client text message (strict JSON); a subscribe list longer than `max` is Invalid.
ClientMessage parse_client_message(const std::string& text, std::size_t max);

/// The SSE request's ?jobs=12,13: sorted, unique positive ids; HttpError 400 "jobs" when missing,
/// malformed or more than `max`.
std::vector<std::int64_t> parse_jobs_param(const Request& req, std::size_t max);

class EventSource {
 public:
  virtual ~EventSource() = default;
  /// The current job objects ("id", "state", "progress", "stage", "updated", ...) of the ids that exist.
  /// Called from the hub's poller thread only.
  virtual std::vector<nlohmann::json> snapshot(const std::vector<std::int64_t>& job_ids) = 0;
  /// The current Flight objects (docs/flights.md, with "id") of the ids that exist. Poller thread only.
  virtual std::vector<nlohmann::json> flights(const std::vector<std::int64_t>& /*flight_ids*/) { return {}; }
};

/// Owns the subscriptions and one poller thread. Every `period` (and right after a subscription) it
/// asks the source for the union of subscribed ids and sends {"type":"job","job":...} to each
/// subscriber whose last copy of that job differs (the first time: the current state). Flights alike,
/// {"type":"flight","flight":...}, polled at most every `flight_period` (but at once for a new
/// subscription).
class EventHub {
 public:
  /// Receives a serialized message; returns false when the subscriber is gone (it is then dropped).
  /// Called from the poller thread (without the hub's lock): it should only hand the text over.
  using Sink = std::function<bool(const std::string& message)>;

  explicit EventHub(EventSource& source, std::chrono::milliseconds period = std::chrono::milliseconds(100),
                    std::chrono::milliseconds flight_period = std::chrono::milliseconds(200));
  ~EventHub();
  EventHub(const EventHub&) = delete;
  EventHub& operator=(const EventHub&) = delete;

  void start();
  /// Stops and joins the poller (idempotent); sinks are not called afterwards.
  void stop();

  /// A new subscriber; its id is used by the calls below.
  std::uint64_t open(Sink sink);
  void close(std::uint64_t subscriber);
  /// Adds ids; refuses (returns false, adds none) when the subscriber would follow more than `max` jobs.
  bool subscribe(std::uint64_t subscriber, const std::vector<std::int64_t>& ids, std::size_t max);
  void unsubscribe(std::uint64_t subscriber, const std::vector<std::int64_t>& ids);
  /// The same for flights (a separate cap of `max`).
  bool subscribe_flights(std::uint64_t subscriber, const std::vector<std::int64_t>& ids, std::size_t max);
  void unsubscribe_flights(std::uint64_t subscriber, const std::vector<std::int64_t>& ids);
  [[nodiscard]] std::size_t subscriber_count() const;

 private:
  struct Subscriber {
    Sink sink;
    std::map<std::int64_t, std::string> last_sent;     ///< id -> JSON last sent ("" none yet)
    std::map<std::int64_t, std::string> flights_sent;  ///< likewise for flights
  };
  void poll_loop();
  void poll_once();
  bool add(std::uint64_t subscriber, const std::vector<std::int64_t>& ids, std::size_t max, bool flights);

  EventSource& source_;
  std::chrono::milliseconds period_;
  std::chrono::milliseconds flight_period_;
  std::chrono::steady_clock::time_point flights_polled_{};
  bool flights_pending_ = false;  ///< a flight subscription waits for its first state
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  bool pending_ = false;  ///< a subscription waits for its first state
  std::uint64_t next_id_ = 1;
  std::map<std::uint64_t, Subscriber> subscribers_;
  std::thread poller_;
};

}  // namespace uavcover::server
