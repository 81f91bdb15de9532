// A flight's missions (docs/flights.md): each UAV's own battery sorties and resumed rests, and the
// missions of reassigned work with how a reassignment is applied.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "evaluation/cost.hpp"
#include "flight/runtime.hpp"
#include "sorties/sorties.hpp"
#include "uavcover/error.hpp"
#include "waypoints/vertical.hpp"

namespace uavcover::flight {

using namespace detail;
using namespace std::chrono_literals;
using nlohmann::json;

MissionSpec Flight::Impl::make_mission(std::size_t uav, std::vector<waypoints::MissionItem> items) const {
  MissionSpec m;
  m.items = std::move(items);
  const std::size_t n = m.items.size();
  m.where.resize(n);
  m.rest_m.assign(n + 1, 0.0);
  m.rest_turns.assign(n + 1, 0);
  m.rest_vertical_s.assign(n + 1, 0.0);
  const std::vector<double> vertical = waypoints::vertical_extra_s(plan, uav, m.items);
  const LonLat home = plan.mission.uavs[uav].start_resolved;
  for (std::size_t j = 0; j < n; ++j) {
    const auto& it = m.items[j];
    if (it.command == waypoints::kNavReturnToLaunch)
      m.where[j] = frame.to_local(home);
    else if (it.lat != 0 || it.lon != 0)
      m.where[j] = frame.to_local(LonLat{it.lon, it.lat});
  }
  std::optional<Point> next;
  for (std::size_t j = n; j-- > 0;) {
    // air distances (issue 32): eq. 15 times each leg at its ground speed in the mission's wind
    m.rest_m[j] =
        m.rest_m[j + 1] + (m.where[j] && next
                               ? evaluation::air_distance_m(
                                     *m.where[j], *next, plan.mission.uavs[uav].speed_mps, plan.mission.wind)
                               : 0.0);
    m.rest_turns[j] = m.rest_turns[j + 1] + (m.items[j].waypoint >= 0 ? 1 : 0);
    m.rest_vertical_s[j] = m.rest_vertical_s[j + 1] + vertical[j];
    if (m.where[j]) next = m.where[j];
  }
  return m;
}

bool Flight::Impl::home_item_of(std::size_t uav) const {
  for (const auto& b : config.vehicles)
    if (b.uav == plan.uavs.at(uav).id) return b.home_item;
  return false;
}

const VehicleProfile& Flight::Impl::profile_of(std::size_t uav) const {
  const bool named = !plan.mission.uavs.at(uav).autopilot.empty() || !plan.mission.autopilot.empty();
  const VehicleProfile* p = named ? vehicle_profile(uav_autopilot(plan.mission, uav)) : nullptr;
  if (p == nullptr || !p->mavlink) p = vehicle_profile(home_item_of(uav) ? "ardupilot" : "px4");
  return *p;
}

std::vector<MissionSpec> Flight::Impl::own_missions(std::size_t uav, int from_waypoint) const {
  std::vector<MissionSpec> out;
  const int n = static_cast<int>(sorties::coverage_waypoints(plan.uavs[uav]).size());
  if (n == 0) return out;
  std::vector<Sortie> ss;
  std::vector<std::vector<waypoints::MissionItem>> items;
  try {
    ss = sorties::resume_sorties(plan, uav, from_waypoint);
    items = sorties::resume_items(plan, uav, from_waypoint);
  } catch (const InputError&) {
    if (from_waypoint >= 0) throw;
    // a leg that does not fit one battery: the plan has no sorties; fly it as one mission
    ss = {Sortie{0, 0, n - 1, {}, 0, 0, 0}};
    items = {waypoints::mission_items(plan, uav)};
  }
  // the vehicle's capacity (issue 31): a sortie too long for one upload is cut into consecutive whole
  // missions (each with its lead-in); a leg too long for it alone stays, and its upload is refused
  const std::size_t capacity = mission_capacity(profile_of(uav), plan.mission.max_mission_items);
  const std::size_t home = home_item_of(uav) ? 1 : 0;
  const bool over =
      std::any_of(items.begin(), items.end(), [&](const auto& it) { return it.size() + home > capacity; });
  if (over && !ss.empty() && !plan.uavs[uav].sorties.empty()) {
    try {
      auto pieces = sorties::capacity_sorties(
          plan, uav, capacity,
          [&](const Plan& sp, std::size_t u) { return waypoints::mission_items(sp, u).size() + home; }, &ss);
      std::vector<std::vector<waypoints::MissionItem>> cut;
      for (const auto& s : pieces) {
        auto its = waypoints::mission_items(plan, uav, s.parts);  // the sortie's, without a copy of the plan
        for (auto& it : its)
          if (it.waypoint >= 0) it.waypoint += s.first_waypoint;
        cut.push_back(std::move(its));
      }
      ss = std::move(pieces);
      items = std::move(cut);
    } catch (const InputError&) {
      // one leg's mission alone is over the capacity: the upload refuses it (alert "capacity")
    }
  }
  for (std::size_t k = 0; k < ss.size() && k < items.size(); ++k) {
    MissionSpec m = make_mission(uav, std::move(items[k]));
    m.kind = from_waypoint < 0 ? "sortie" : "resume";
    m.index = ss[k].index;
    m.first_waypoint = ss[k].first_waypoint;
    m.last_waypoint = ss[k].last_waypoint;
    m.from_waypoint = from_waypoint;
    m.k = static_cast<int>(k);
    out.push_back(std::move(m));
  }
  return out;
}

// ---- reassignment ----

MissionSpec Flight::Impl::reassigned_mission(const ReassignmentRt& r, const ReassignedWork& w,
                                             std::size_t k) const {
  MissionSpec m = make_mission(w.index, w.missions.at(k));
  m.kind = "reassigned";
  m.reassignment = r.id;
  m.k = static_cast<int>(k);
  m.index = static_cast<int>(k);
  // without sorties (a leg longer than a battery) the work is one mission
  m.first_waypoint = k < w.sorties.size() ? w.sorties[k].first_waypoint : 0;
  m.last_waypoint = k < w.sorties.size() ? w.sorties[k].last_waypoint : w.waypoints - 1;
  m.waypoints.assign(static_cast<std::size_t>(std::max(0, m.last_waypoint - m.first_waypoint + 1)), 'P');
  return m;
}

void Flight::Impl::requeue(UavRt& u, std::vector<MissionSpec> first) {
  if (u.missions.size() > 1000) throw CommandRefused("too many missions for UAV " + u.binding.uav);
  std::vector<MissionSpec> rest = own_missions(u.index, last_reached(u));
  // kept: the missions flown and the current one; then `first`, the rest of its own coverage (it replaces
  // the own missions not flown), then the reassigned work still queued
  std::vector<MissionSpec> next(u.missions.begin(), u.missions.begin() + static_cast<long>(u.current) + 1);
  for (auto& m : first) next.push_back(std::move(m));
  for (auto& m : rest) next.push_back(std::move(m));
  for (std::size_t j = u.current + 1; j < u.missions.size(); ++j)
    if (u.missions[j].kind == "reassigned" && u.missions[j].state == "pending") next.push_back(u.missions[j]);
  u.missions = std::move(next);
  ++u.current;
  u.interrupted = false;
}

void Flight::Impl::apply_reassignment(ReassignmentRt& r) {
  if (!r.result) throw CommandRefused("reassignment " + std::to_string(r.id) + " has no result");
  for (const auto& w : r.result->work) {
    auto it = std::find_if(uavs.begin(), uavs.end(), [&](const UavRt& h) { return h.index == w.index; });
    if (it == uavs.end()) continue;
    std::vector<MissionSpec> work;
    for (std::size_t k = 0; k < w.missions.size(); ++k) work.push_back(reassigned_mission(r, w, k));
    const auto h =
        std::find_if(r.helpers.begin(), r.helpers.end(), [&](const Helper& x) { return x.index == w.index; });
    if (h != r.helpers.end() && h->depot && divertable(*it)) {
      // from the air: its own sortie is interrupted where it is, the work uploaded and started now, and
      // its own rest resumed after it from its last reached waypoint
      MissionSpec& own = it->missions[it->current];
      own.state = coverage_done(*it, own) ? "done" : "interrupted";
      record(it->binding.uav, "sortie",
             {{"mission", it->current},
              {"kind", own.kind},
              {"index", own.index},
              {"state", own.state},
              {"reassignment", r.id}});
      requeue(*it, std::move(work));
      it->actions.clear();
      queue_upload_and_start(*it);
      continue;
    }
    for (auto& m : work) it->missions.push_back(std::move(m));
    if (it->phase == "done") set_phase(*it, "landed");
  }
  auto failed = std::find_if(uavs.begin(), uavs.end(), [&](const UavRt& h) { return h.index == r.failed; });
  if (failed != uavs.end()) {
    for (std::size_t k = failed->current; k < failed->missions.size(); ++k) {
      MissionSpec& m = failed->missions[k];
      if (m.state == "done") continue;
      for (int g = m.first_waypoint; m.kind == "reassigned" && g <= m.last_waypoint; ++g)
        set_waypoint(*failed, m, g, 'S');
      m.state = "skipped";
    }
    MissionSpec own;  // the UAV's own waypoints
    own.kind = "sortie";
    for (std::size_t g = 0; g < failed->waypoints.size(); ++g)
      if (failed->waypoints[g] == 'P' || failed->waypoints[g] == 'C')
        set_waypoint(*failed, own, static_cast<int>(g), 'S');
    failed->current = failed->missions.size();
    failed->interrupted = false;
    failed->actions.clear();
    if (failed->phase == "landed") set_phase(*failed, "done");
  }
  r.state = "applied";
  record(r.failed_uav, "reassignment", {{"id", r.id}, {"state", "applied"}});
}

}  // namespace uavcover::flight
