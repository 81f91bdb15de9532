#include "export/checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "autopilot/fence.hpp"
#include "autopilot/rules.hpp"
#include "export/separation.hpp"
#include "terrain/terrain.hpp"
#include "uavcover/error.hpp"
#include "uavcover/vehicle.hpp"
#include "waypoints/ardupilot.hpp"

namespace uavcover::exporting {

using namespace waypoints;  // the waypoint model the formats write
using autopilot::no_fly_violations;
using nlohmann::json;

/// UAV ids are used unchanged in file names: the parser's id rule, checked again here for plan
/// folders that did not come through it.
bool usable_id(const std::string& id) {
  if (id.empty() || id.size() > 64 || id.front() == '.') return false;
  return std::all_of(id.begin(), id.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  });
}

/// The autopilots' upload rules (src/autopilot/rules.hpp) on the MAVLink items of UAV `i` of `p` (what the
/// .plan, .waypoints, CSV and `uavcover upload` carry): a rule the autopilots refuse the mission for
/// refuses the export; the limits that depend on the vehicle's configuration (item capacity, PX4's
/// distance parameters) warn, for the autopilot the export is for.
void check_consumers(const Plan& p, std::size_t i, const std::vector<MissionItem>& items,
                     const std::string& autopilot, std::vector<std::string>& warnings) {
  const std::string& id = p.uavs[i].id;
  const LonLat home = p.mission.uavs[i].start_resolved;
  struct Consumer {
    const char* name;
    std::vector<autopilot::Problem> problems;
    bool warn;
  };
  // the capacities of the vehicle profiles (issue 31), with the mission's max_mission_items
  autopilot::ArduPilotLimits ap;
  ap.max_items = mission_capacity(*vehicle_profile("ardupilot"), p.mission.max_mission_items);
  autopilot::Px4Params px4;
  px4.max_items = mission_capacity(*vehicle_profile("px4"), p.mission.max_mission_items);
  const Consumer consumers[] = {
      {"ArduPilot", autopilot::ardupilot_problems(items, ap), autopilot == "ardupilot"},
      {"PX4", autopilot::px4_problems(items, home, terrain::home_ground(p.mission, i), px4),
       autopilot == "px4"}};
  // an export for ArduPilot with headings carries MAV_CMD_CONDITION_YAW (ardupilot_mission_items),
  // which PX4 does not run in a mission: those items are for ArduPilot only, and PX4's rules do not apply
  // (and one in the terrain frame, issue 31, which PX4 refuses: the export is for ArduPilot alone)
  const bool ardupilot_only = std::any_of(items.begin(), items.end(), [](const MissionItem& it) {
    return it.command == kConditionYaw || it.frame == kFrameGlobalTerrainAlt;
  });
  for (const Consumer& c : consumers)
    for (const autopilot::Problem& pr : c.problems) {
      if (ardupilot_only && std::string(c.name) == "PX4") break;
      if (pr.fatal)
        throw InputError("autopilot", fmt::format("uav '{}': {} would refuse the mission: {}", id, c.name,
                                                  autopilot::describe(pr, items)));
      if (c.warn)
        warnings.push_back(fmt::format("uav '{}': {}: {}", id, c.name, autopilot::describe(pr, items)));
    }
}

std::size_t stored_items(const Plan& p, std::size_t i, const std::string& autopilot,
                         const waypoints::AltitudeOptions& altitude) {
  if (autopilot == "ardupilot") return ardupilot_mission_items(p, i, altitude).size() + 1;  // + home, item 0
  const auto items = mission_items(p, i, altitude);
  if (autopilot == "px4") return items.size();
  // DJI and Litchi count waypoints
  return static_cast<std::size_t>(std::count_if(items.begin(), items.end(), has_position));
}

CheckedPlan check_plan(const Plan& plan, ExportOptions& opt, std::vector<std::string>& warnings) {
  if (plan.uavs.size() != plan.mission.uavs.size())
    throw InputError("uavs", fmt::format("the plan has {} UAV plans for {} mission UAVs", plan.uavs.size(),
                                         plan.mission.uavs.size()));
  if (!std::isfinite(opt.geofence_margin_m) || opt.geofence_margin_m < 0)
    throw InputError("geofence_margin_m", "must be >= 0");
  if (!std::isfinite(opt.trajectory_step_s) || opt.trajectory_step_s < 0 ||
      (opt.trajectory_step_s > 0 && opt.trajectory_step_s < 0.001))
    throw InputError("trajectory_step_s", "must be 0 (the segment form) or a step of at least 0.001 s");
  CheckedPlan checked;
  checked.autopilot = export_autopilot(plan, opt);  // an unknown one refuses before anything
  if (opt.altitude.terrain_frame) {
    // heights relative to terrain (issue 31): ArduPilot only, and only where the plan follows a DEM
    if (checked.autopilot != "ardupilot")
      throw InputError("terrain_frame",
                       "MAV_FRAME_GLOBAL_TERRAIN_ALT is for ArduPilot (PX4 refuses it in a mission, DJI and "
                       "Litchi files have no such frame); export with autopilot ardupilot");
    if (terrain::grid(plan.mission) == nullptr || !plan.mission.terrain->follow())
      throw InputError("terrain_frame", "needs a mission whose terrain block follows a DEM");
  }
  for (std::size_t i = 0; i < plan.uavs.size(); ++i)
    if (!usable_id(plan.uavs[i].id) || plan.uavs[i].id != plan.mission.uavs[i].id)
      throw InputError(fmt::format("uavs[{}].id", i),
                       "not usable as a file name (1 to 64 of A-Z a-z 0-9 _ - ., not starting with '.')");
  opt.altitude = resolve_altitudes(opt.altitude, altitude_slots(plan), plan.mission.altitude_m, &warnings);
  if (opt.check_separation) {
    const auto problems = check_separation(plan, opt.altitude);
    if (!problems.empty()) throw InputError("separation", problems.front());
  }
  for (const auto& w : separation_warnings(plan)) warnings.push_back(w);
  // UAV i's mission items in `p` (the plan or one sortie's), refused when they fly through a no-fly zone
  auto items_clear_of_zones = [&](const Plan& p, std::size_t i) {
    // ArduCopter turns to a heading on MAV_CMD_CONDITION_YAW, not on NAV_WAYPOINT param4 (docs/exports.md)
    auto items = checked.autopilot == "ardupilot" ? ardupilot_mission_items(p, i, opt.altitude)
                                                  : mission_items(p, i, opt.altitude);
    const auto violations = no_fly_violations(p, i, items);
    if (!violations.empty()) throw InputError("no_fly_zones", violations.front() + " (re-plan the mission)");
    return items;
  };
  // idle UAVs (no coverage part) are skipped: a take-off-and-return mission is not worth flying
  for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
    if (idle(plan.uavs[i])) {
      warnings.push_back(
          fmt::format("uav '{}': no coverage parts, nothing exported for it", plan.uavs[i].id));
      continue;
    }
    checked.flown.push_back(i);
    auto items = items_clear_of_zones(plan, i);
    if (!opt.per_sortie && !opt.split_capacity) check_consumers(plan, i, items, checked.autopilot, warnings);
    checked.items[i] = std::move(items);
  }
  if (checked.flown.empty()) throw InputError("uavs", "no UAV has coverage parts: nothing to export");
  if (opt.per_sortie || opt.split_capacity)
    for (const std::size_t i : checked.flown) {
      std::vector<Sortie> list;
      if (opt.split_capacity) {
        // the vehicle's capacity (issue 31): the profile the export is for (the option), else the UAV's
        const std::string name =
            opt.autopilot.empty() ? std::string(uav_autopilot(plan.mission, i)) : opt.autopilot;
        const VehicleProfile& profile = *vehicle_profile(name);
        const std::size_t capacity = mission_capacity(profile, plan.mission.max_mission_items);
        list = sorties::capacity_sorties(plan, i, capacity, [&](const Plan& sp, std::size_t u) {
          return stored_items(sp, u, name, opt.altitude);
        });
      } else {
        list = plan.uavs[i].sorties.empty() ? sorties::cut_sorties(plan, i) : plan.uavs[i].sorties;
      }
      for (std::size_t k = 0; k < list.size(); ++k) {
        const Plan sp = sorties::sortie_plan(plan, i, list[k]);
        auto items = items_clear_of_zones(sp, i);
        check_consumers(sp, i, items, checked.autopilot, warnings);
        checked.sortie_items[{i, k}] = std::move(items);
      }
      checked.sorties[i] = std::move(list);
    }
  return checked;
}

}  // namespace uavcover::exporting
