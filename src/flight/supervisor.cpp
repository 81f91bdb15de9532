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
        u.phase != "failed" && has_work_left(u) && started) {
      if (u.current < u.missions.size() && u.missions[u.current].state == "flying")
        u.missions[u.current].state = "interrupted";
      u.actions.clear();
      u.command_active = false;
      set_phase(u, "failed");
    }
    // the automatic next sortie (and a start that failed on a lossy link, tried again)
    if (config.auto_next_sortie && started && !aborted && u.link_state == "ok" && u.actions.empty() &&
        !u.command_active && now >= u.retry_after && !u.interrupted && u.current < u.missions.size()) {
      const auto& st = u.missions[u.current].state;
      if ((u.phase == "landed" || u.phase == "done" || u.phase == "idle") && st == "pending") {
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
        std::vector<Helper> hs;
        for (const auto& h : uavs)
          if (&h != &u && h.link_state == "ok" && h.phase != "failed")
            hs.push_back(Helper{h.index, airborne_phase(h.phase)
                                             ? std::clamp(h.battery_pct.value_or(100.0) / 100.0, 0.01, 1.0)
                                             : 1.0});
        offers.push_back(i);
        helpers.push_back(std::move(hs));
        reached.push_back(last_reached(u));
      }
    }
    for (std::size_t k = 0; k < offers.size(); ++k) {
      const std::size_t i = offers[k];
      ReassignmentRt r;
      r.failed = uavs[i].index;  // immutable after construction
      r.failed_uav = uavs[i].binding.uav;
      r.last_reached = reached[k];
      r.helpers = helpers[k];
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
      if (!error.empty()) {
        record(r.failed_uav, "reassignment", {{"state", "impossible"}, {"reason", error}});
        continue;
      }
      r.id = static_cast<int>(reassignments.size()) + 1;
      reassignments.push_back(r);
      const json j = snapshot_locked()["reassignments"].back();
      record(r.failed_uav, "reassignment", j);
      if (config.auto_reassign) apply_reassignment(reassignments.back());
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
