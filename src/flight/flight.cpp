// The flight (docs/flights.md): its construction, the observer's records, alerts and phases, and the
// public class. Each UAV's missions are in missions.cpp, the supervisor in supervisor.cpp, operator
// commands in commands.cpp, snapshot and restore in snapshot.cpp, the per-vehicle link threads in
// link.cpp.
#include "flight/flight.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "evaluation/cost.hpp"
#include "flight/runtime.hpp"
#include "sorties/sorties.hpp"
#include "uavcover/error.hpp"

namespace uavcover::flight {

using namespace detail;
using namespace std::chrono_literals;
using nlohmann::json;
namespace mav = uavcover::mavlink;

std::int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// ---- construction ----

Flight::Impl::Impl(std::int64_t id_, Plan plan_, FlightConfig config_, Observer& observer_)
    : id(id_), plan(std::move(plan_)), config(std::move(config_)), observer(observer_), frame(plan.origin) {
  if (config.vehicles.empty()) throw InputError("vehicles", "needs at least one vehicle");
  for (std::size_t i = 0; i < config.vehicles.size(); ++i) {
    const auto& b = config.vehicles[i];
    const auto it =
        std::find_if(plan.uavs.begin(), plan.uavs.end(), [&](const UavPlan& u) { return u.id == b.uav; });
    if (it == plan.uavs.end()) throw InputError(fmt::format("vehicles[{}].uav", i), "not a UAV of the plan");
    for (std::size_t j = 0; j < i; ++j)
      if (config.vehicles[j].uav == b.uav)
        throw InputError(fmt::format("vehicles[{}].uav", i), "bound twice");
    UavRt u;
    u.index = static_cast<std::size_t>(it - plan.uavs.begin());
    u.binding = b;
    u.waypoints.assign(sorties::coverage_waypoints(*it).size(), 'P');
    u.missions = own_missions(u.index, -1);
    uavs.push_back(std::move(u));
  }
}

// ---- records, alerts, phases ----

void Flight::Impl::record(const std::string& uav, const std::string& kind, json data) {
  dirty = true;
  if (pending.size() >= kPendingMax) {
    if (kind == "telemetry") return;  // the observer is behind: telemetry goes first
    const auto it = std::find_if(pending.begin(), pending.end(),
                                 [](const LogRecord& r) { return r.kind == "telemetry"; });
    if (it != pending.end())
      pending.erase(it);
    else
      pending.erase(pending.begin());
  }
  pending.push_back(LogRecord{now_ms(), uav, kind, std::move(data)});
}

void Flight::Impl::set_alert(const std::string& kind, const std::string& uav, const std::string& other,
                             bool active, const std::string& message) {
  auto it = std::find_if(alerts.begin(), alerts.end(), [&](const Alert& a) {
    return a.active && a.kind == kind && a.uav == uav && a.other == other;
  });
  if (active == (it != alerts.end())) return;
  if (active) {
    if (alerts.size() >= kAlertsMax) {
      const auto old = std::find_if(alerts.begin(), alerts.end(), [](const Alert& a) { return !a.active; });
      alerts.erase(old != alerts.end() ? old : alerts.begin());
    }
    alerts.push_back(Alert{kind, uav, other, message, now_ms(), true});
  } else {
    it->active = false;
  }
  json d{{"kind", kind}, {"active", active}, {"message", message}};
  if (!other.empty()) d["other"] = other;
  record(uav, "alert", std::move(d));
}

void Flight::Impl::set_phase(UavRt& u, const std::string& phase) {
  if (u.phase == phase) return;
  record(u.binding.uav, "state", {{"phase", phase}, {"from", u.phase}});
  u.phase = phase;
}

void Flight::Impl::queue_command(UavRt& u, const std::string& name, std::uint16_t command, float p1,
                                 float p2) {
  if (u.actions.size() >= kActionsMax)
    throw CommandRefused("too many commands queued for UAV " + u.binding.uav);
  Action a;
  a.kind = Action::Kind::Command;
  a.name = name;
  a.cmd.command = command;
  a.cmd.param1 = p1;
  a.cmd.param2 = p2;
  u.actions.push_back(std::move(a));
}

void Flight::Impl::queue_upload_and_start(UavRt& u) {
  if (u.current >= u.missions.size()) return;
  Action up;
  up.kind = Action::Kind::Upload;
  up.mission = u.current;
  up.name = "upload";
  u.actions.push_back(std::move(up));
  queue_command(u, "arm", mav::kCmdComponentArmDisarm, 1.0F);
  queue_command(u, "mission_start", mav::kCmdMissionStart);
  u.retry_after = Clock::now() + 2s;
}

void Flight::Impl::update_state() {
  std::string s;
  if (aborted) {
    s = "aborted";
  } else if (std::all_of(uavs.begin(), uavs.end(), [&](const UavRt& u) { return settled(u); })) {
    s = "done";
  } else if (started) {
    const bool any_flying = std::any_of(uavs.begin(), uavs.end(), [](const UavRt& u) {
      return u.phase == "flying" || u.phase == "returning";
    });
    const bool any_paused =
        std::any_of(uavs.begin(), uavs.end(), [](const UavRt& u) { return u.phase == "paused"; });
    s = !any_flying && any_paused ? "paused" : "flying";
  } else if (std::any_of(uavs.begin(), uavs.end(), [](const UavRt& u) { return u.phase == "uploading"; })) {
    s = "uploading";
  } else if (std::any_of(uavs.begin(), uavs.end(), [](const UavRt& u) { return u.phase == "ready"; })) {
    s = "ready";
  } else {
    s = "created";
  }
  if (s != state) {
    record("", "state", {{"state", s}, {"from", state}});
    state = s;
  }
}

// ---- the public class ----

Flight::Flight(std::int64_t id, Plan plan, FlightConfig config, Observer& observer,
               const std::optional<json>& restored)
    : impl_(std::make_unique<Impl>(id, std::move(plan), std::move(config), observer)) {
  if (restored) impl_->restore(*restored);
}

Flight::~Flight() { stop(); }

void Flight::start() {
  std::lock_guard lock(impl_->mutex);
  Impl& f = *impl_;
  if (f.running) return;
  f.links.clear();
  for (std::size_t i = 0; i < f.uavs.size(); ++i) {
    const auto& b = f.uavs[i].binding;
    try {
      f.links.push_back(mav::open_link(link_address(b), kGcsSysid, kGcsCompid));
    } catch (const std::exception& e) {
      f.links.clear();
      throw InputError(fmt::format("vehicles[{}].endpoint", i), e.what());
    }
  }
  const auto now = Clock::now();
  for (auto& u : f.uavs) u.last_heard = now;  // judged lost only after link_timeout_s of silence
  f.running = true;
  for (std::size_t i = 0; i < f.uavs.size(); ++i)
    f.threads.emplace_back([&f, i](const std::stop_token& st) { f.vehicle_loop(i, st); });
  f.threads.emplace_back([&f](const std::stop_token& st) { f.supervisor_loop(st); });
}

void Flight::stop() {
  std::vector<std::jthread> threads;
  {
    std::lock_guard lock(impl_->mutex);
    if (!impl_->running) return;
    impl_->running = false;
    threads.swap(impl_->threads);
  }
  for (auto& t : threads) t.request_stop();
  threads.clear();  // joins
  impl_->links.clear();
  impl_->flush();
}

std::string Flight::state() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->state;
}

bool Flight::finished() const {
  std::lock_guard lock(impl_->mutex);
  if (impl_->state == "done") return true;
  if (!impl_->aborted) return false;
  return std::all_of(impl_->uavs.begin(), impl_->uavs.end(),
                     [](const UavRt& u) { return u.actions.empty() && !u.command_active; });
}

json Flight::snapshot() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->snapshot_locked();
}

std::vector<std::pair<std::string, std::vector<std::array<double, 3>>>> Flight::tracks() const {
  std::lock_guard lock(impl_->mutex);
  std::vector<std::pair<std::string, std::vector<std::array<double, 3>>>> out;
  for (const auto& u : impl_->uavs) out.emplace_back(u.binding.uav, u.track);
  return out;
}

}  // namespace uavcover::flight
