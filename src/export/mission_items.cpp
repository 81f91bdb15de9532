// Mission items with transition altitudes (Hong et al. 2021 §2.3): take-off straight to the UAV's own
// transition altitude, transit legs at it, coverage at mission altitude, climb back, return, RTL/land.
#include "export/mission_items.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace uavcover::exporting {

double transition_altitude(const AltitudeOptions& opt, std::size_t index, double mission_altitude_m) {
  const double base =
      opt.transition_base_m > 0.0 ? opt.transition_base_m : std::max(60.0, mission_altitude_m + 20.0);
  return base + static_cast<double>(index) * opt.transition_step_m;
}

namespace {

MissionItem position_item(std::uint16_t command, LonLat p, double alt, std::string role) {
  MissionItem it;
  it.command = command;
  it.frame = kFrameGlobalRelativeAlt;
  it.lat = p.lat;
  it.lon = p.lon;
  it.alt = static_cast<float>(alt);
  it.role = std::move(role);
  return it;
}

MissionItem command_item(std::uint16_t command, float p1, float p2, float p3, float p4, std::string role) {
  MissionItem it;
  it.command = command;
  it.frame = kFrameMission;
  it.param1 = p1;
  it.param2 = p2;
  it.param3 = p3;
  it.param4 = p4;
  it.role = std::move(role);
  return it;
}

bool same_place(LonLat a, LonLat b) {
  return std::abs(a.lat - b.lat) < 1e-9 && std::abs(a.lon - b.lon) < 1e-9;
}

}  // namespace

std::vector<MissionItem> mission_items(const Plan& plan, std::size_t index, const AltitudeOptions& opt) {
  if (index >= plan.uavs.size() || index >= plan.mission.uavs.size())
    throw std::out_of_range("mission_items: no UAV with index " + std::to_string(index));
  const UavPlan& up = plan.uavs[index];
  const Uav& uav = plan.mission.uavs[index];
  const double mission_alt = plan.mission.altitude_m;
  const double transit_alt = transition_altitude(opt, index, mission_alt);
  const LonLat home = uav.start_resolved;
  const bool camera = plan.mission.camera.has_value() && plan.mission.spacing_m > 0.0;

  std::vector<MissionItem> items;
  // take-off: climb straight to the transition altitude above home
  items.push_back(position_item(kNavTakeoff, home, transit_alt, "takeoff"));
  // MAV_CMD_DO_CHANGE_SPEED: param1 1 = ground speed, param2 speed, param3 -1 = throttle unchanged
  items.push_back(
      command_item(kDoChangeSpeed, 1.0f, static_cast<float>(uav.speed_mps), -1.0f, 0.0f, "speed"));

  bool high = true;  // at the transition altitude
  LonLat here = home;
  for (std::size_t pi = 0; pi < up.parts.size(); ++pi) {
    const PathPart& part = up.parts[pi];
    if (part.wgs84.empty()) continue;
    const std::size_t first_new = items.size();
    if (part.kind == PartKind::Transit) {
      if (!high) {  // climb on the spot before leaving the region
        items.push_back(position_item(kNavWaypoint, here, transit_alt, "transition"));
        high = true;
      }
      for (std::size_t k = 0; k < part.wgs84.size(); ++k) {
        if (k == 0 && same_place(part.wgs84[k], here)) continue;
        items.push_back(position_item(kNavWaypoint, part.wgs84[k], transit_alt, "transit"));
        here = part.wgs84[k];
      }
    } else {
      const LonLat entry = part.wgs84.front();
      if (high && !same_place(entry, here)) {  // reach the point above the entry first
        items.push_back(position_item(kNavWaypoint, entry, transit_alt, "transit"));
        here = entry;
      }
      // the first coverage waypoint is the descent to mission altitude
      high = false;
      items.push_back(position_item(kNavWaypoint, entry, mission_alt, "coverage"));
      if (camera)
        items.push_back(command_item(kDoSetCamTriggDist, static_cast<float>(plan.mission.spacing_m), 0.0f,
                                     1.0f, 0.0f, "camera"));
      for (std::size_t k = 1; k < part.wgs84.size(); ++k)
        items.push_back(position_item(kNavWaypoint, part.wgs84[k], mission_alt, "coverage"));
      if (camera) items.push_back(command_item(kDoSetCamTriggDist, 0.0f, 0.0f, 0.0f, 0.0f, "camera"));
      here = part.wgs84.back();
    }
    for (std::size_t k = first_new; k < items.size(); ++k)
      if (items[k].role == "transit" || items[k].role == "coverage") items[k].part = static_cast<int>(pi);
  }
  if (!high) items.push_back(position_item(kNavWaypoint, here, transit_alt, "transition"));
  if (!same_place(here, home)) items.push_back(position_item(kNavWaypoint, home, transit_alt, "transit"));
  if (opt.land_instead_of_rtl) {
    items.push_back(position_item(kNavLand, home, 0.0, "land"));
  } else {
    items.push_back(command_item(kNavReturnToLaunch, 0, 0, 0, 0, "rtl"));
  }
  return items;
}

}  // namespace uavcover::exporting
