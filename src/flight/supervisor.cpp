// The flight's supervisor (docs/flights.md): link health, alerts, the automatic next sortie,
// reassignment offers, and the flush of records to the observer.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "evaluation/cost.hpp"
#include "flight/runtime.hpp"
#include "sorties/sorties.hpp"
#include "uavcover/error.hpp"

namespace uavcover::flight {

using namespace detail;
using namespace std::chrono_literals;
using nlohmann::json;
namespace mav = uavcover::mavlink;

// ---- waypoint retries (Hong et al. 2021 §2.3: a waypoint not reached is retried, then the UAV fails) ----

double Flight::Impl::waypoint_timeout_s(const UavRt& u, const MissionSpec& m, int item) const {
  const auto j = static_cast<std::size_t>(item);
  const auto& to = m.where[j];
  if (!to) return config.waypoint_timeout_floor_s;
  const Uav& spec = plan.mission.uavs[u.index];
  const Point from = u.have_position                       ? frame.to_local(LonLat{u.lon, u.lat})
                     : j > 0 && m.where[j - 1].has_value() ? *m.where[j - 1]
                                                           : *to;
  // the leg in the mission's wind (issue 32) and its climb or descent, at the UAV's speed
  const double air = evaluation::air_distance_m(from, *to, spec.speed_mps, plan.mission.wind);
  const double climb =
      m.items[j].frame == waypoints::kFrameGlobalRelativeAlt ? std::abs(m.items[j].alt - u.alt_m) : 0.0;
  const double leg_s = std::hypot(air, climb) / spec.speed_mps;
  const double t = config.waypoint_timeout_factor * leg_s;
  return std::isfinite(t) ? std::clamp(t, config.waypoint_timeout_floor_s, 86400.0) : 86400.0;
}

void Flight::Impl::fail_uav(UavRt& u) {
  if (u.current < u.missions.size() && u.missions[u.current].state == "flying")
    u.missions[u.current].state = "interrupted";
  u.actions.clear();
  u.command_active = false;
  u.deadline.reset();  // the waypoint and its count stay shown
  set_phase(u, "failed");
}

void Flight::Impl::check_waypoint(UavRt& u, Clock::time_point now) {
  if (config.waypoint_retries <= 0 || u.phase == "failed") return;  // failed: its last count stays shown
  // the coverage item the vehicle flies to, not reached yet
  std::optional<std::pair<std::size_t, int>> at;
  int waypoint = -1;
  if (u.current < u.missions.size() && u.current_item && u.missions[u.current].state == "flying" &&
      (u.phase == "flying" || u.phase == "paused")) {
    const MissionSpec& m = u.missions[u.current];
    const int j = *u.current_item;
    if (j >= 0 && j < static_cast<int>(m.items.size()) &&
        m.items[static_cast<std::size_t>(j)].waypoint >= 0) {
      waypoint = m.items[static_cast<std::size_t>(j)].waypoint;
      if (waypoint_status(u, m, waypoint) == 'C') at = std::pair{u.current, j};
    }
  }
  const auto secs = [](double x) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(x));
  };
  if (at != u.timed) {  // reached, moved on, or a new mission: the count starts again
    if (u.retries > 0) set_alert("waypoint_retry", u.binding.uav, "", false, "reached or moved on");
    u.timed = at;
    u.timed_waypoint = waypoint;
    u.retries = 0;
    u.deadline.reset();
  }
  if (!at) return;
  const MissionSpec& m = u.missions[at->first];
  if (u.phase != "flying") {  // paused: the time starts again on continue
    u.deadline.reset();
    return;
  }
  if (!u.deadline) {
    u.deadline = now + secs(waypoint_timeout_s(u, m, at->second));
    return;
  }
  if (now < *u.deadline) return;
  const std::string what = m.kind == "reassigned"
                               ? fmt::format("waypoint {} of reassignment {}", waypoint, m.reassignment)
                               : fmt::format("waypoint {}", waypoint);
  if (u.retries >= config.waypoint_retries) {
    set_alert("waypoint_retry", u.binding.uav, "", false, what + " not reached: failed");
    set_alert("waypoint_failed", u.binding.uav, "", true,
              fmt::format("{} not reached after {} retries", what, u.retries));
    fail_uav(u);
    return;
  }
  const double timeout = waypoint_timeout_s(u, m, at->second);
  const int seq = at->second + (u.binding.home_item ? 1 : 0);
  if (u.actions.size() >= kActionsMax) return;  // a full queue: tried again next round
  queue_command(u, "retry_waypoint", mav::kCmdDoSetMissionCurrent, static_cast<float>(seq));
  ++u.retries;
  ++u.retries_total;
  set_alert("waypoint_retry", u.binding.uav, "", true,
            fmt::format("{} not reached in time: commanded again ({} of {})", what, u.retries,
                        config.waypoint_retries));
  json d{{"waypoint", waypoint},          {"mission", m.kind},   {"seq", seq}, {"retry", u.retries},
         {"of", config.waypoint_retries}, {"timeout_s", timeout}};
  if (m.kind == "reassigned") d["reassignment"] = m.reassignment;
  record(u.binding.uav, "retry", std::move(d));
  u.deadline = now + secs(timeout);
}

// ---- reassignment helpers ----

void Flight::Impl::apply_safely(ReassignmentRt& r) {
  try {  // from the supervisor: a refusal is recorded, the thread goes on
    apply_reassignment(r);
  } catch (const std::exception& e) {
    record(r.failed_uav, "reassignment", {{"id", r.id}, {"state", r.state}, {"reason", e.what()}});
  }
}

bool Flight::Impl::divertable(const UavRt& h) const {
  return h.phase == "flying" && h.have_position && h.link_state == "ok" && h.current < h.missions.size() &&
         h.missions[h.current].state == "flying" && h.missions[h.current].kind != "reassigned";
}

std::string Flight::Impl::stale_depot(const ReassignmentRt& r) const {
  for (const Helper& h : r.helpers) {
    if (!h.depot) continue;
    const auto it =
        std::find_if(uavs.begin(), uavs.end(), [&](const UavRt& u) { return u.index == h.index; });
    if (it == uavs.end()) continue;
    if (!divertable(*it)) return fmt::format("{} can no longer be diverted ({})", it->binding.uav, it->phase);
    const Point here = frame.to_local(LonLat{it->lon, it->lat}), depot = frame.to_local(*h.depot);
    const double moved = std::hypot(here.x() - depot.x(), here.y() - depot.y());
    if (moved > kStaleDepotM)
      return fmt::format("{} is {:.0f} m from where the offer starts its work", it->binding.uav, moved);
  }
  return {};
}

std::vector<Helper> Flight::Impl::helpers_for(const UavRt& failed, const std::string& from) const {
  std::vector<Helper> hs;
  for (const auto& h : uavs)
    if (&h != &failed && h.link_state == "ok" && h.phase != "failed") {
      Helper x{h.index,
               airborne_phase(h.phase) ? std::clamp(h.battery_pct.value_or(100.0) / 100.0, 0.01, 1.0) : 1.0};
      if (from == "air" && divertable(h)) x.depot = LonLat{h.lon, h.lat};
      hs.push_back(x);
    }
  return hs;
}

// ---- supervision ----

void Flight::Impl::supervise_locked(Clock::time_point now) {
  const auto secs = [](double s) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
  };
  for (auto& u : uavs) {
    // link health (an upload reads the link itself: not judged meanwhile)
    if (u.phase != "uploading" && u.link_state != "lost" &&
        now - u.last_heard > secs(config.link_timeout_s)) {
      u.link_state = "lost";
      u.lost_since = now;
      set_alert("link_lost", u.binding.uav, "", true,
                fmt::format("no message for {} s", config.link_timeout_s));
    }
    const bool low = u.battery_pct && *u.battery_pct < config.low_battery_pct;
    if (low != u.low_battery) {
      u.low_battery = low;
      set_alert("low_battery", u.binding.uav, "", low,
                fmt::format("battery {:.0f}%", u.battery_pct.value_or(0)));
    }
    // a UAV lost for reassign_after_s with work left has failed
    if (u.link_state == "lost" && u.lost_since && now - *u.lost_since >= secs(config.reassign_after_s) &&
        u.phase != "failed" && has_work_left(u) && started)
      fail_uav(u);
    // a coverage waypoint not reached in time: retried, then the UAV fails
    if (u.link_state == "ok")
      check_waypoint(u, now);
    else
      u.deadline.reset();  // timed again once the link is back
    // the automatic next sortie (and a start that failed on a lossy link, tried again)
    if (config.auto_next_sortie && started && !aborted && u.link_state == "ok" && u.actions.empty() &&
        !u.command_active && now >= u.retry_after && !u.interrupted && u.current < u.missions.size()) {
      const auto& st = u.missions[u.current].state;
      // (flying with its current mission pending: a diversion from the air whose upload failed, again)
      if ((u.phase == "landed" || u.phase == "done" || u.phase == "idle" || u.phase == "flying") &&
          st == "pending") {
        queue_upload_and_start(u);
      } else if (u.phase == "ready" && st == "ready") {
        queue_command(u, "arm", mav::kCmdComponentArmDisarm, 1.0F);
        queue_command(u, "mission_start", mav::kCmdMissionStart);
        u.retry_after = now + 2s;
      }
    }
  }
  // separation between airborne UAVs
  for (std::size_t a = 0; a < uavs.size(); ++a)
    for (std::size_t b = a + 1; b < uavs.size(); ++b) {
      const UavRt &ua = uavs[a], &ub = uavs[b];
      bool close = false;
      double d = 0;
      if (ua.have_position && ub.have_position && ua.alt_m > 1.0 && ub.alt_m > 1.0 && ua.link_state == "ok" &&
          ub.link_state == "ok") {
        const double h =
            bg::distance(frame.to_local(LonLat{ua.lon, ua.lat}), frame.to_local(LonLat{ub.lon, ub.lat}));
        d = std::hypot(h, ua.alt_m - ub.alt_m);
        close = d < config.separation_m;
      }
      set_alert("separation", ua.binding.uav, ub.binding.uav, close, fmt::format("{:.1f} m apart", d));
    }
  update_state();
}

void Flight::Impl::supervisor_loop(const std::stop_token& stop) {
  while (!stop.stop_requested()) {
    std::vector<std::size_t> offers;  // failed UAVs to re-plan
    std::vector<std::vector<Helper>> helpers;
    std::vector<int> reached;
    std::vector<std::string> from;
    std::vector<int> replans;  // ids of reassignments the operator asked to re-plan (state "replanning")
    {
      std::lock_guard lock(mutex);
      const auto now = Clock::now();
      supervise_locked(now);
      const auto after =
          std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(config.reassign_after_s));
      for (std::size_t i = 0; i < uavs.size(); ++i) {
        UavRt& u = uavs[i];
        const bool failed = u.phase == "failed";
        const bool landed_early = u.phase == "landed" && u.interrupted && u.interrupted_since &&
                                  now - *u.interrupted_since >= after;
        if (u.offered || aborted || !(failed || landed_early) || reassignments.size() >= kReassignMax)
          continue;
        u.offered = true;
        offers.push_back(i);
        helpers.push_back(helpers_for(u, config.reassign_from));
        reached.push_back(last_reached(u));
        from.push_back(config.reassign_from);
        replans.push_back(0);
      }
      for (const auto& r : reassignments) {
        if (r.state != "replanning") continue;
        const auto it =
            std::find_if(uavs.begin(), uavs.end(), [&](const UavRt& x) { return x.index == r.failed; });
        if (it == uavs.end()) continue;
        offers.push_back(static_cast<std::size_t>(it - uavs.begin()));
        helpers.push_back(helpers_for(*it, r.replan_from));
        reached.push_back(r.last_reached);
        from.push_back(r.replan_from);
        replans.push_back(r.id);
      }
    }
    for (std::size_t k = 0; k < offers.size(); ++k) {
      const std::size_t i = offers[k];
      ReassignmentRt r;
      r.failed = uavs[i].index;  // immutable after construction
      r.failed_uav = uavs[i].binding.uav;
      r.last_reached = reached[k];
      r.helpers = helpers[k];
      r.from = from[k];
      r.at_ms = now_ms();
      std::string error;
      if (r.helpers.empty()) {
        error = "no UAV left to help";
      } else {
        try {
          r.result =
              std::make_shared<const Reassignment>(reassign(plan, r.failed, r.last_reached, r.helpers));
          if (r.result->work.empty()) error = "nothing left to cover";
        } catch (const std::exception& e) {
          error = e.what();
        }
      }
      std::lock_guard lock(mutex);
      if (replans[k] > 0) {  // the operator's other choice: re-planned, then applied (or offered again)
        ReassignmentRt& old = reassignments[static_cast<std::size_t>(replans[k] - 1)];
        if (old.state != "replanning") continue;
        if (!error.empty()) {
          old.state = "offered";
          record(r.failed_uav, "reassignment",
                 {{"id", old.id}, {"state", "offered"}, {"reason", "re-plan impossible: " + error}});
          continue;
        }
        old.helpers = r.helpers;
        old.result = r.result;
        old.from = r.from;
        old.at_ms = r.at_ms;
        old.state = "offered";
        json j = snapshot_locked()["reassignments"][static_cast<std::size_t>(old.id - 1)];
        j["replanned"] = true;
        record(r.failed_uav, "reassignment", std::move(j));
        apply_safely(old);
        continue;
      }
      if (!error.empty()) {
        record(r.failed_uav, "reassignment", {{"state", "impossible"}, {"reason", error}});
        continue;
      }
      r.id = static_cast<int>(reassignments.size()) + 1;
      reassignments.push_back(r);
      const json j = snapshot_locked()["reassignments"].back();
      record(r.failed_uav, "reassignment", j);
      if (config.auto_reassign) apply_safely(reassignments.back());
    }
    flush();
    std::this_thread::sleep_for(50ms);
  }
  add_thread_cpu();
}

void Flight::Impl::add_thread_cpu() {
  timespec ts{};
  if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) == 0) cpu_ns += ts.tv_sec * 1'000'000'000LL + ts.tv_nsec;
}

void Flight::Impl::flush() {
  std::lock_guard order(flush_mutex);
  std::vector<LogRecord> out;
  bool changed = false;
  {
    std::lock_guard lock(mutex);
    out.swap(pending);
    const std::int64_t t = now_ms();
    if (dirty && t - last_changed_ms >= 100) {
      dirty = false;
      changed = true;
      last_changed_ms = t;
    }
  }
  try {  // the observer's failure (a store that cannot write) must not stop the flight
    if (!out.empty()) observer.on_records(id, out);
    if (changed) observer.on_changed(id);
  } catch (const std::exception&) {
  }
}

}  // namespace uavcover::flight
