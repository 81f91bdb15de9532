// FlightManager: live flights, their simulated fleets, and the writer that keeps their logs and
// snapshots in the store.
#include "server/flights.hpp"
#include "codec/plan_codec.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <set>

#include "export/export.hpp"
#include "flight/coverage.hpp"
#include "io/plan_io.hpp"
#include "server/api.hpp"
#include "server/http.hpp"
#include "sim/sim_vehicle.hpp"
#include "uavcover/error.hpp"

namespace uavcover::server {

namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

/// Records waiting for the store per flight; beyond this, telemetry is dropped first (the store is down).
constexpr std::size_t kMaxPendingRecords = 100000;
/// Log records read back to rebuild tracks of a flight that is not live.
constexpr std::int64_t kMaxTrackRecords = 500000;
/// A flight's flown coverage is computed again at most this often.
constexpr auto kCoverageMaxAge = std::chrono::seconds(3);

std::int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

const json* member(const json& obj, const char* key) {
  const auto it = obj.find(key);
  return it == obj.end() || it->is_null() ? nullptr : &*it;
}

double number_in(const json& obj, const char* key, double fallback, double lo, double hi) {
  const json* v = member(obj, key);
  if (!v) return fallback;
  const std::string field = std::string("simulate.") + key;
  if (!v->is_number()) throw InputError(field, "must be a number");
  const double x = v->get<double>();
  if (!(x >= lo && x <= hi)) throw InputError(field, fmt::format("must be in [{}, {}]", lo, hi));
  return x;
}

/// The simulated fleet of a "simulate" request: one vehicle per flying UAV of the plan, at its start,
/// with the UAV's speed, acceleration and endurance (docs/flights.md); system id = the UAV's position.
struct SimulateRequest {
  sim::FleetOptions options;
  std::vector<sim::VehicleConfig> vehicles;
  std::vector<std::string> uavs;  ///< the UAV of each vehicle
  bool tcp = false;               ///< the vehicles listen on TCP (the flight connects), not UDP
};

SimulateRequest parse_simulate(const json& s, const Plan& plan, std::size_t max_vehicles) {
  if (!s.is_object()) throw InputError("simulate", "must be an object");
  for (const auto& [k, v] : s.items())
    if (k != "speedup" && k != "fail" && k != "loss" && k != "wind_mps" && k != "wind_from_deg" &&
        k != "battery_min" && k != "seed" && k != "transport")
      throw InputError("simulate." + k.substr(0, 100), "unknown field");
  SimulateRequest out;
  if (const json* t = member(s, "transport")) {
    if (!t->is_string() || (*t != "udp" && *t != "tcp"))
      throw InputError("simulate.transport", "must be \"udp\" or \"tcp\"");
    out.tcp = *t == "tcp";
  }
  out.options.speedup = number_in(s, "speedup", 1.0, 0.1, 1000);
  const double loss = number_in(s, "loss", 0.0, 0.0, 0.9);
  const double wind = number_in(s, "wind_mps", 0.0, 0.0, 30);
  const double wind_from = number_in(s, "wind_from_deg", 270.0, 0.0, 360);
  const json* battery = member(s, "battery_min");
  const double battery_min = battery ? number_in(s, "battery_min", 0.0, 0.5, 600) : 0.0;
  const auto seed = static_cast<std::uint64_t>(number_in(s, "seed", 1, 0, 1e9));
  std::optional<std::pair<std::uint8_t, sim::Failure>> failure;
  if (const json* f = member(s, "fail")) {
    if (!f->is_string() || f->get<std::string>().size() > 100)
      throw InputError("simulate.fail", "must be a string ID@FRACTION[:link|:land|:stuck]");
    failure = sim::parse_failure(f->get<std::string>(), "simulate.fail");
  }
  if (plan.uavs.size() > 255) throw InputError("simulate", "at most 255 simulated vehicles");
  for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
    if (exporting::idle(plan.uavs[i])) continue;
    const Uav& u = plan.mission.uavs.at(i);
    sim::VehicleConfig c;
    c.sysid = static_cast<std::uint8_t>(i + 1);
    c.listen = mavlink::Endpoint{"127.0.0.1", 0};
    c.tcp = out.tcp;
    c.home = u.start_resolved;
    // a plan with a DEM: AMSL heights over the ground under home, terrain-frame heights over the DEM
    if (plan.mission.terrain) c.set_ground(plan.mission.terrain->grid);
    c.v_max = u.speed_mps;
    c.a_max = u.max_accel_mps2;
    c.v_up = u.climb_mps;  // the mission's vertical speeds (the whole-flight time, docs/wind.md)
    c.v_down = u.descent_mps;
    c.endurance_min = battery ? battery_min : u.endurance_min;
    c.wind_mps = wind;
    c.wind_from_deg = wind_from;
    c.loss = loss;
    c.seed = seed;
    if (failure && failure->first == c.sysid) c.failure = failure->second;
    out.vehicles.push_back(c);
    out.uavs.push_back(plan.uavs[i].id);
  }
  if (out.vehicles.empty()) throw InputError("simulate", "the plan has no UAV with a coverage path");
  if (out.vehicles.size() > max_vehicles)
    throw InputError("simulate", fmt::format("at most {} vehicles per flight", max_vehicles));
  if (failure && std::none_of(out.vehicles.begin(), out.vehicles.end(),
                              [&](const sim::VehicleConfig& c) { return c.sysid == failure->first; }))
    throw InputError("simulate.fail", fmt::format("no flying UAV at position {} of the plan (1-based)",
                                                  static_cast<int>(failure->first)));
  return out;
}

}  // namespace

Plan load_job_plan(store::Store& store, const store::Job& job, const DemDir& dem_dir) {
  const auto plan = store.get_artifact(job.id, "plan.json");
  const auto paths = store.get_artifact(job.id, "paths.geojson");
  if (!plan || !paths)
    throw store::Conflict("plan " + std::to_string(job.id) + " has no plan.json and paths.geojson to fly");
  const json pj = json::parse(plan->bytes, nullptr, false);
  const json gj = json::parse(paths->bytes, nullptr, false);
  if (pj.is_discarded() || gj.is_discarded())
    throw store::StoreError("plan " + std::to_string(job.id) + ": a stored artifact is not JSON");
  Plan loaded = codec::load_plan(pj, gj);
  load_server_terrain(loaded.mission, store, dem_dir);
  return loaded;
}

json flight_json(const store::StoredFlight& row, const json& snapshot) {
  json j = snapshot.is_object() ? snapshot : json::object();
  j["id"] = row.id;
  j["plan_id"] = row.plan_id;
  j["mission_id"] = row.mission_id;
  j["simulated"] = row.simulated;
  j["created"] = iso_time(row.created_ms);
  j["updated"] = iso_time(row.updated_ms);
  j["config"] = row.config;
  if (!j.contains("state") || !j["state"].is_string()) j["state"] = row.state;
  return j;
}

// ---- live flights ----

struct FlightManager::Live {
  store::StoredFlight row;  ///< id, plan, mission, config, created (fixed); updated_ms moves
  Plan plan;                ///< what the flight flies (flown coverage)
  std::unique_ptr<sim::Fleet> fleet;
  std::jthread fleet_thread;
  std::unique_ptr<flight::Flight> flight;  ///< declared last: stopped first, before the fleet
  std::string saved_state;                 ///< the state last stored
  Clock::time_point saved_at{};
  std::atomic<std::int64_t> changed_ms{0};
  std::once_flag retired;  ///< retire() runs once; a second caller waits until it has stored the end

  json snapshot_json() const {
    store::StoredFlight r = row;
    r.state = flight->state();
    r.updated_ms = std::max(r.updated_ms, changed_ms.load());
    json s = flight->snapshot();
    s["state"] = r.state;
    return flight_json(r, s);
  }
  void stop() {
    flight->stop();
    if (fleet_thread.joinable()) {
      fleet_thread.request_stop();
      fleet_thread.join();
    }
  }
};

FlightManager::FlightManager(store::Store& store, FlightLimits limits) : store_(store), limits_(limits) {}

FlightManager::~FlightManager() { stop(); }

void FlightManager::start() {
  for (const auto& row : store_.list_active_flights()) {
    if (row.simulated) {
      const json snapshot = row.snapshot;
      store_.append_flight_log(row.id, {{0,
                                         now_ms(),
                                         "",
                                         "state",
                                         {{"state", "aborted"},
                                          {"from", row.state},
                                          {"reason", "the server restarted: its simulated fleet is gone"}}}});
      store_.update_flight(row.id, "aborted", [&] {
        json s = snapshot.is_object() ? snapshot : json::object();
        s["state"] = "aborted";
        return s;
      }());
      continue;
    }
    try {
      attach(row, row.snapshot.is_object() && !row.snapshot.empty() ? std::optional<json>(row.snapshot)
                                                                    : std::nullopt);
      spdlog::info("flight {}: followed again ({})", row.id, row.state);
    } catch (const std::exception& e) {
      spdlog::warn("flight {}: cannot follow it again: {}", row.id, e.what());
    }
  }
  const std::lock_guard lock(queue_mutex_);
  if (!writer_.joinable() && !stopping_) writer_ = std::thread([this] { writer_loop(); });
}

void FlightManager::stop() {
  std::map<store::Id, std::shared_ptr<Live>> live;
  {
    const std::lock_guard lock(mutex_);
    live.swap(live_);
  }
  for (auto& [id, l] : live) l->stop();
  {
    const std::lock_guard lock(queue_mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (writer_.joinable()) writer_.join();
  // the last records and snapshots (the vehicles were left flying: the state stays what it was)
  try {
    write_pending();
    for (auto& [id, l] : live) store_.update_flight(id, l->flight->state(), l->flight->snapshot());
  } catch (const std::exception& e) {
    spdlog::warn("flights: the last records could not be stored: {}", e.what());
  }
}

std::size_t FlightManager::live_count() const {
  const std::lock_guard lock(mutex_);
  return live_.size();
}

std::shared_ptr<FlightManager::Live> FlightManager::find(store::Id id) const {
  const std::lock_guard lock(mutex_);
  const auto it = live_.find(id);
  return it == live_.end() ? nullptr : it->second;
}

void FlightManager::attach(const store::StoredFlight& row, const std::optional<json>& restored) {
  const auto job = store_.get_job(row.plan_id);
  if (!job) throw store::NotFound("plan " + std::to_string(row.plan_id) + " does not exist");
  Plan plan = load_job_plan(store_, *job, limits_.dem_dir);
  flight::FlightConfig config = flight::parse_config(row.config, plan);
  auto live = std::make_shared<Live>();
  live->row = row;
  live->saved_state = row.state;
  live->saved_at = Clock::now();
  live->plan = plan;
  live->flight =
      std::make_unique<flight::Flight>(row.id, std::move(plan), std::move(config), *this, restored);
  live->flight->start();
  const std::lock_guard lock(mutex_);
  live_[row.id] = std::move(live);
}

json FlightManager::create(const store::Job& plan_job, const json& body) {
  if (!body.is_object()) throw InputError("", "the flight request must be a JSON object");
  const std::lock_guard create_lock(create_mutex_);  // 24 concurrent POSTs must not make 17 flights
  if (live_count() >= limits_.max_live)
    throw HttpError(
        409, "", fmt::format("{} flights are followed already (at most {})", live_count(), limits_.max_live));
  Plan plan = load_job_plan(store_, plan_job, limits_.dem_dir);
  json request = body;
  std::unique_ptr<sim::Fleet> fleet;
  const bool simulated = member(body, "simulate") != nullptr;
  if (simulated) {
    if (member(body, "vehicles")) throw InputError("simulate", "give either vehicles or simulate, not both");
    SimulateRequest s = parse_simulate(body["simulate"], plan, limits_.max_vehicles);
    try {
      fleet = std::make_unique<sim::Fleet>(s.vehicles, s.options);
    } catch (const std::runtime_error& e) {
      throw OperationError(std::string("cannot open the simulated vehicles' sockets: ") + e.what());
    }
    json vehicles = json::array();
    for (std::size_t i = 0; i < s.vehicles.size(); ++i)
      vehicles.push_back(
          {{"uav", s.uavs[i]},
           {"endpoint", fmt::format("{}:127.0.0.1:{}", s.tcp ? "tcp" : "udp", fleet->vehicles()[i]->port())},
           {"sysid", s.vehicles[i].sysid}});
    request.erase("simulate");
    request["vehicles"] = std::move(vehicles);
  } else if (const json* v = member(body, "vehicles");
             v && v->is_array() && v->size() > limits_.max_vehicles) {
    throw InputError("vehicles", fmt::format("at most {} vehicles per flight", limits_.max_vehicles));
  }
  flight::FlightConfig config = flight::parse_config(request, plan);
  if (!limits_.allow_remote)
    for (std::size_t i = 0; i < config.vehicles.size(); ++i)
      if (!is_loopback(config.vehicles[i].endpoint.host))
        throw InputError(
            fmt::format("vehicles[{}].endpoint", i),
            "only loopback endpoints (127.0.0.1, localhost) unless the server runs with a token");

  store::NewFlight nf;
  nf.plan_id = plan_job.id;
  nf.config = flight::config_json(config);
  nf.simulated = simulated;
  const store::Id id = store_.create_flight(nf);
  auto live = std::make_shared<Live>();
  live->row = *store_.get_flight(id);
  live->saved_state = live->row.state;
  live->saved_at = Clock::now();
  live->fleet = std::move(fleet);
  live->plan = plan;
  try {
    live->flight = std::make_unique<flight::Flight>(id, std::move(plan), std::move(config), *this);
    live->flight->start();
  } catch (...) {
    store_.update_flight(id, "aborted", {{"state", "aborted"}});  // its links could not be opened
    throw;
  }
  if (live->fleet)
    live->fleet_thread = std::jthread([fleet = live->fleet.get(), id](const std::stop_token& stop) {
      try {
        fleet->run(stop);
      } catch (const std::exception& e) {
        spdlog::warn("flight {}: the simulated fleet stopped: {}", id, e.what());
      }
    });
  json out = live->snapshot_json();
  store_.update_flight(id, live->flight->state(), live->flight->snapshot());
  {
    const std::lock_guard lock(mutex_);
    live_[id] = std::move(live);
  }
  wake_.notify_all();
  return out;
}

std::optional<json> FlightManager::get(store::Id id) {
  if (const auto live = find(id)) {
    // a flight is shown ended only once its whole log is stored (the writer may not have retired it yet)
    if (!live->flight->finished()) return live->snapshot_json();
    retire(live, live->flight->state(), "finished");
  }
  const auto row = store_.get_flight(id);
  if (!row) return std::nullopt;
  return flight_json(*row, row->snapshot);
}

std::vector<json> FlightManager::get_many(const std::vector<store::Id>& ids) {
  std::vector<json> out;
  for (const auto id : ids)
    if (auto j = get(id)) out.push_back(std::move(*j));
  return out;
}

json FlightManager::command(store::Id id, const json& body) {
  const flight::Command c = flight::parse_command(body);
  const auto live = find(id);
  if (!live) {
    const auto row = store_.get_flight(id);
    if (!row) throw store::NotFound("no flight " + std::to_string(id));
    throw HttpError(409, "command",
                    "flight " + std::to_string(id) + " is " + row->state + ": it is not followed");
  }
  try {
    live->flight->command(c);
  } catch (const flight::CommandRefused& e) {
    throw HttpError(409, "command", e.what());
  }
  return live->snapshot_json();
}

void FlightManager::retire(const std::shared_ptr<Live>& live, const std::string& state,
                           const std::string& reason) {
  std::call_once(live->retired, [&] {
    {
      const std::lock_guard lock(mutex_);
      live_.erase(live->row.id);
    }
    const std::string from = live->flight->state();
    live->stop();
    flush();  // what the flight recorded up to its stop
    json snapshot = live->flight->snapshot();
    snapshot["state"] = state;
    if (state != from)
      store_.append_flight_log(
          live->row.id, {{0, now_ms(), "", "state", {{"state", state}, {"from", from}, {"reason", reason}}}});
    store_.update_flight(live->row.id, state, snapshot);
  });
}

json FlightManager::remove(store::Id id) {
  if (const auto live = find(id)) {
    retire(live, live->flight->finished() ? live->flight->state() : "aborted", "DELETE");
    return *get(id);
  }
  const auto row = store_.get_flight(id);
  if (!row) throw store::NotFound("no flight " + std::to_string(id));
  json out = flight_json(*row, row->snapshot);
  if (store::flight_terminal(row->state)) {
    store_.delete_flight(id);
  } else {
    // followed by another server (PostgreSQL) or by nobody: it ends aborted here
    json s = row->snapshot.is_object() ? row->snapshot : json::object();
    s["state"] = "aborted";
    store_.update_flight(id, "aborted", s);
    out = *get(id);
  }
  return out;
}

Tracks FlightManager::tracks(store::Id id) {
  if (const auto live = find(id)) return live->flight->tracks();
  if (!store_.get_flight(id)) throw store::NotFound("no flight " + std::to_string(id));
  Tracks out;
  std::map<std::string, std::size_t> index;
  std::int64_t after = 0, read = 0;
  while (read < kMaxTrackRecords) {
    const auto page = store_.read_flight_log(id, after, 10000);
    for (const auto& r : page.items) {
      if (r.kind != "telemetry" || !r.data.is_object()) continue;
      const json* lon = member(r.data, "lon");
      const json* lat = member(r.data, "lat");
      const json* alt = member(r.data, "alt_m");
      if (!lon || !lat || !lon->is_number() || !lat->is_number()) continue;
      auto [it, fresh] = index.emplace(r.uav, out.size());
      if (fresh) out.emplace_back(r.uav, std::vector<std::array<double, 3>>{});
      out[it->second].second.push_back(
          {lon->get<double>(), lat->get<double>(), alt && alt->is_number() ? alt->get<double>() : 0.0});
    }
    read += static_cast<std::int64_t>(page.items.size());
    if (!page.next_after) break;
    after = *page.next_after;
  }
  return out;
}

std::shared_ptr<const FlightManager::Coverage> FlightManager::coverage(store::Id id) {
  const auto now = Clock::now();
  {
    const std::lock_guard lock(coverage_mutex_);
    if (const auto it = coverage_cache_.find(id);
        it != coverage_cache_.end() && now - it->second.first < kCoverageMaxAge)
      return it->second.second;
  }
  Plan plan;
  if (const auto live = find(id)) {
    plan = live->plan;
  } else {
    const auto row = store_.get_flight(id);
    if (!row) throw store::NotFound("no flight " + std::to_string(id));
    const auto job = store_.get_job(row->plan_id);
    if (!job) throw store::NotFound("plan " + std::to_string(row->plan_id) + " does not exist");
    plan = load_job_plan(store_, *job, limits_.dem_dir);
  }
  const flight::FlownCoverage fc = flight::flown_coverage(plan, tracks(id));
  auto out = std::make_shared<Coverage>();
  out->summary = {{"flown_poc", fc.flown_poc},
                  {"planned_poc", fc.planned_poc},
                  {"flown_pooc", fc.flown_pooc},
                  {"bounds", {{fc.bounds.south, fc.bounds.west}, {fc.bounds.north, fc.bounds.east}}},
                  {"updated", iso_time(now_ms())}};
  out->png = fc.overlay.bytes;
  const std::lock_guard lock(coverage_mutex_);
  std::erase_if(coverage_cache_, [&](const auto& e) { return now - e.second.first >= kCoverageMaxAge; });
  coverage_cache_[id] = {now, out};
  return out;
}

// ---- the observer and the writer ----

void FlightManager::on_records(std::int64_t flight_id, const std::vector<flight::LogRecord>& records) {
  {
    const std::lock_guard lock(queue_mutex_);
    auto& q = pending_[flight_id];
    for (const auto& r : records) {
      if (q.size() >= kMaxPendingRecords) {
        if (r.kind == "telemetry") continue;
        const auto t = std::find_if(q.begin(), q.end(), [](const auto& p) { return p.kind == "telemetry"; });
        q.erase(t != q.end() ? t : q.begin());
      }
      q.push_back({0, r.t_ms, r.uav, r.kind, r.data});
    }
  }
  wake_.notify_all();
}

void FlightManager::on_changed(std::int64_t flight_id) {
  if (const auto live = find(flight_id)) live->changed_ms = now_ms();
  const std::lock_guard lock(queue_mutex_);
  changed_.insert(flight_id);
}

void FlightManager::flush() { write_pending(); }

void FlightManager::write_pending() {
  const std::lock_guard write_lock(write_mutex_);
  std::map<store::Id, std::vector<store::FlightLogRecord>> records;
  std::set<store::Id> changed;
  {
    const std::lock_guard lock(queue_mutex_);
    records.swap(pending_);
    changed.swap(changed_);
  }
  for (auto it = records.begin(); it != records.end(); ++it) {
    try {
      store_.append_flight_log(it->first, it->second);
    } catch (const store::NotFound&) {
      // the flight was deleted meanwhile: its records go with it
    } catch (const store::StoreError& e) {
      // kept for the next round, before what arrived meanwhile
      spdlog::warn("flight {}: {} log records wait for the database: {}", it->first, it->second.size(),
                   e.what());
      const std::lock_guard lock(queue_mutex_);
      for (auto jt = it; jt != records.end(); ++jt) {
        auto& q = pending_[jt->first];
        q.insert(q.begin(), jt->second.begin(), jt->second.end());
      }
      changed_.insert(changed.begin(), changed.end());
      return;
    }
  }
  std::vector<std::shared_ptr<Live>> live;
  {
    const std::lock_guard lock(mutex_);
    for (const auto& [id, l] : live_) live.push_back(l);
  }
  const auto now = Clock::now();
  for (const auto& l : live) {
    const std::string state = l->flight->state();
    const bool due = changed.count(l->row.id) && now - l->saved_at >= limits_.snapshot_period;
    if (state == l->saved_state && !due) {
      if (changed.count(l->row.id)) {
        const std::lock_guard lock(queue_mutex_);
        changed_.insert(l->row.id);  // stored at its next period
      }
      continue;
    }
    json snapshot = l->flight->snapshot();
    snapshot["state"] = state;
    store_.update_flight(l->row.id, state, snapshot);
    l->saved_state = state;
    l->saved_at = now;
  }
}

void FlightManager::writer_loop() {
  std::unique_lock lock(queue_mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, limits_.flush_period, [this] { return stopping_; });
    if (stopping_) break;
    lock.unlock();
    try {
      write_pending();
      // flights that ended are no longer followed: their fleets stop, their last state is stored
      std::vector<std::shared_ptr<Live>> done;
      {
        const std::lock_guard live_lock(mutex_);
        for (const auto& [id, l] : live_)
          if (l->flight->finished()) done.push_back(l);
      }
      for (const auto& l : done) retire(l, l->flight->state(), "finished");
    } catch (const std::exception& e) {
      spdlog::warn("flights: writing to the database failed: {}", e.what());
    }
    lock.lock();
  }
}

}  // namespace uavcover::server
