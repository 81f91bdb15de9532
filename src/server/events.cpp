#include "server/events.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <limits>
#include <set>
#include <string_view>

#include "json/strict.hpp"
#include "uavcover/error.hpp"

namespace uavcover::server {

ClientMessage parse_client_message(const std::string& text, std::size_t max) {
  ClientMessage out;
  auto invalid = [&out](std::string field, std::string message) {
    out.op = ClientMessage::Op::Invalid;
    out.jobs.clear();
    out.flights.clear();
    out.error_field = std::move(field);
    out.error_message = std::move(message);
    return out;
  };
  nlohmann::json msg;
  try {
    msg = strict::parse_json(text, "message");
  } catch (const InputError& e) {
    return invalid(e.field(), e.what());
  }
  if (!msg.is_object() || msg.size() != 1 || !(msg.contains("subscribe") || msg.contains("unsubscribe")))
    return invalid("", R"(expected {"subscribe": {"jobs": [ids]}} or {"unsubscribe": {"jobs": [ids]}})");
  const bool subscribe = msg.contains("subscribe");
  const std::string op = subscribe ? "subscribe" : "unsubscribe";
  const auto& body = msg[op];
  if (!body.is_object() || body.empty() ||
      !std::all_of(body.items().begin(), body.items().end(),
                   [](const auto& kv) { return kv.key() == "jobs" || kv.key() == "flights"; }))
    return invalid(op, R"(expected {"jobs": [ids]} and/or {"flights": [ids]})");
  for (const char* kind : {"jobs", "flights"}) {
    if (!body.contains(kind)) continue;
    const std::string word = std::string(kind) == "jobs" ? "job" : "flight";
    const auto& ids = body[kind];
    const std::string field = op + "." + kind;
    if (!ids.is_array()) return invalid(field, "expected an array of " + word + " ids");
    if (subscribe && ids.size() > max)
      return invalid(field, fmt::format("at most {} {} subscriptions per connection", max, word));
    auto& list = word == "job" ? out.jobs : out.flights;
    list.reserve(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const auto& j = ids[i];
      if (!j.is_number_unsigned() || j.get<std::uint64_t>() < 1 ||
          j.get<std::uint64_t>() > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
        return invalid(fmt::format("{}[{}]", field, i), "expected a positive integer " + word + " id");
      list.push_back(static_cast<std::int64_t>(j.get<std::uint64_t>()));
    }
  }
  out.op = subscribe ? ClientMessage::Op::Subscribe : ClientMessage::Op::Unsubscribe;
  return out;
}

std::vector<std::int64_t> parse_jobs_param(const Request& req, std::size_t max) {
  const auto it = req.query.find("jobs");
  if (it == req.query.end() || it->second.empty())
    throw HttpError(400, "jobs", "give the job ids to follow, e.g. ?jobs=12,13");
  std::vector<std::int64_t> ids;
  std::string_view rest = it->second;
  while (true) {
    const auto comma = rest.find(',');
    ids.push_back(parse_id(std::string(rest.substr(0, comma)), "jobs"));
    if (ids.size() > max) throw HttpError(400, "jobs", fmt::format("at most {} jobs per connection", max));
    if (comma == std::string_view::npos) break;
    rest = rest.substr(comma + 1);
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

EventHub::EventHub(EventSource& source, std::chrono::milliseconds period,
                   std::chrono::milliseconds flight_period)
    : source_(source), period_(period), flight_period_(flight_period) {}

EventHub::~EventHub() { stop(); }

void EventHub::start() {
  const std::lock_guard lock(mutex_);
  if (poller_.joinable() || stopping_) return;
  poller_ = std::thread([this] { poll_loop(); });
}

void EventHub::stop() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
    subscribers_.clear();
  }
  wake_.notify_all();
  if (poller_.joinable() && poller_.get_id() != std::this_thread::get_id()) poller_.join();
}

std::uint64_t EventHub::open(Sink sink) {
  const std::lock_guard lock(mutex_);
  const std::uint64_t id = next_id_++;
  if (!stopping_) subscribers_[id] = Subscriber{std::move(sink), {}, {}};
  return id;
}

void EventHub::close(std::uint64_t subscriber) {
  const std::lock_guard lock(mutex_);
  subscribers_.erase(subscriber);
}

bool EventHub::add(std::uint64_t subscriber, const std::vector<std::int64_t>& ids, std::size_t max,
                   bool flights) {
  {
    const std::lock_guard lock(mutex_);
    const auto it = subscribers_.find(subscriber);
    if (it == subscribers_.end()) return true;  // closed meanwhile: nothing to follow
    auto& followed = flights ? it->second.flights_sent : it->second.last_sent;
    std::set<std::int64_t> added;
    for (const auto id : ids)
      if (!followed.count(id)) added.insert(id);
    if (followed.size() + added.size() > max) return false;
    if (added.empty()) return true;
    for (const auto id : added) followed.emplace(id, std::string());
    pending_ = true;
    if (flights) flights_pending_ = true;
  }
  wake_.notify_all();
  return true;
}

bool EventHub::subscribe(std::uint64_t subscriber, const std::vector<std::int64_t>& ids, std::size_t max) {
  return add(subscriber, ids, max, false);
}

bool EventHub::subscribe_flights(std::uint64_t subscriber, const std::vector<std::int64_t>& ids,
                                 std::size_t max) {
  return add(subscriber, ids, max, true);
}

void EventHub::unsubscribe(std::uint64_t subscriber, const std::vector<std::int64_t>& ids) {
  const std::lock_guard lock(mutex_);
  const auto it = subscribers_.find(subscriber);
  if (it == subscribers_.end()) return;
  for (const auto id : ids) it->second.last_sent.erase(id);
}

void EventHub::unsubscribe_flights(std::uint64_t subscriber, const std::vector<std::int64_t>& ids) {
  const std::lock_guard lock(mutex_);
  const auto it = subscribers_.find(subscriber);
  if (it == subscribers_.end()) return;
  for (const auto id : ids) it->second.flights_sent.erase(id);
}

std::size_t EventHub::subscriber_count() const {
  const std::lock_guard lock(mutex_);
  return subscribers_.size();
}

void EventHub::poll_loop() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, period_, [this] { return stopping_ || pending_; });
    if (stopping_) break;
    pending_ = false;
    lock.unlock();
    try {
      poll_once();
    } catch (const std::exception& e) {
      spdlog::warn("events: polling the jobs failed: {}", e.what());
    }
    lock.lock();
  }
}

namespace {

/// The objects by id, serialized once.
std::map<std::int64_t, std::pair<const nlohmann::json*, std::string>> by_id(
    const std::vector<nlohmann::json>& items) {
  std::map<std::int64_t, std::pair<const nlohmann::json*, std::string>> out;
  for (const auto& item : items) {
    if (!item.is_object() || !item.contains("id") || !item["id"].is_number_integer()) continue;
    out[item["id"].get<std::int64_t>()] = {
        &item, item.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)};
  }
  return out;
}

/// Appends the messages of the objects whose text differs from what the subscriber got last.
void changed_messages(std::map<std::int64_t, std::string>& last_sent,
                      const std::map<std::int64_t, std::pair<const nlohmann::json*, std::string>>& now,
                      const char* type, std::vector<std::string>& out) {
  for (auto& [id, last] : last_sent) {
    const auto t = now.find(id);
    if (t == now.end() || t->second.second == last) continue;
    last = t->second.second;
    const nlohmann::json message{{"type", type}, {type, *t->second.first}};
    out.push_back(message.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  }
}

}  // namespace

void EventHub::poll_once() {
  std::set<std::int64_t> wanted, wanted_flights;
  bool poll_flights = false;
  {
    const std::lock_guard lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    poll_flights = flights_pending_ || now - flights_polled_ >= flight_period_;
    if (poll_flights) {
      flights_pending_ = false;
      flights_polled_ = now;
    }
    for (const auto& [sid, sub] : subscribers_) {
      for (const auto& [id, last] : sub.last_sent) wanted.insert(id);
      if (poll_flights)
        for (const auto& [id, last] : sub.flights_sent) wanted_flights.insert(id);
    }
  }
  if (wanted.empty() && wanted_flights.empty()) return;
  // the source may query a database: no lock is held meanwhile
  std::vector<nlohmann::json> jobs, flights;
  if (!wanted.empty()) jobs = source_.snapshot(std::vector<std::int64_t>(wanted.begin(), wanted.end()));
  if (!wanted_flights.empty())
    flights = source_.flights(std::vector<std::int64_t>(wanted_flights.begin(), wanted_flights.end()));
  const auto job_text = by_id(jobs);
  const auto flight_text = by_id(flights);
  // sinks are called without the lock (a sink may drop the last reference to its session, whose
  // destructor closes the subscription); only this thread calls them, so each sees its objects in order
  std::vector<std::pair<std::uint64_t, Sink>> sinks;
  std::vector<std::vector<std::string>> messages;
  {
    const std::lock_guard lock(mutex_);
    if (stopping_) return;
    for (auto& [sid, sub] : subscribers_) {
      std::vector<std::string> out;
      changed_messages(sub.last_sent, job_text, "job", out);
      if (poll_flights) changed_messages(sub.flights_sent, flight_text, "flight", out);
      if (out.empty()) continue;
      sinks.emplace_back(sid, sub.sink);
      messages.push_back(std::move(out));
    }
  }
  std::vector<std::uint64_t> gone;
  for (std::size_t i = 0; i < sinks.size(); ++i)
    for (const auto& m : messages[i])
      if (!sinks[i].second(m)) {
        gone.push_back(sinks[i].first);
        break;
      }
  if (gone.empty()) return;
  const std::lock_guard lock(mutex_);
  for (const auto id : gone) subscribers_.erase(id);
}

}  // namespace uavcover::server
