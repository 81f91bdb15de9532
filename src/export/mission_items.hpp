// MAVLink-style mission items for one UAV of a plan: the common model behind the QGroundControl
// .plan, Mission Planner WPL, and the MAVLink upload. Altitudes follow Hong et al. 2021 §2.3:
// take-off, climb to the UAV's own transition altitude, fly to the region, descend to mission
// altitude, cover, climb back, return, RTL/land.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "uavcover/plan.hpp"

namespace uavcover::exporting {

/// MAV_CMD numbers used here.
enum MavCmd : std::uint16_t {
  kNavWaypoint = 16,
  kNavReturnToLaunch = 20,
  kNavLand = 21,
  kNavTakeoff = 22,
  kDoChangeSpeed = 178,
  kDoSetCamTriggDist = 206,
};
/// MAV_FRAME numbers used here.
enum MavFrame : std::uint8_t { kFrameGlobal = 0, kFrameMission = 2, kFrameGlobalRelativeAlt = 3 };

struct MissionItem {
  std::uint16_t command = kNavWaypoint;
  std::uint8_t frame = kFrameGlobalRelativeAlt;
  float param1 = 0, param2 = 0, param3 = 0, param4 = 0;
  double lat = 0, lon = 0;  ///< degrees (0 for commands without a position)
  float alt = 0;            ///< metres, relative to home in frame 3
  bool autocontinue = true;
  std::string role;  ///< "takeoff", "transition", "coverage", "transit", "speed", "camera", "rtl", "land"
  int part = -1;     ///< index into UavPlan::parts the item comes from; -1 for virtual/command items
};

struct AltitudeOptions {
  /// First UAV's transition altitude; 0 = automatic: the larger of 60 m and mission altitude + 20 m.
  double transition_base_m = 0.0;
  double transition_step_m = 10.0;  ///< added per UAV index
  bool land_instead_of_rtl = false;
};

/// Transition altitude of UAV `index` (base + index * step) for a mission flown at
/// `mission_altitude_m` (which sets the automatic base).
double transition_altitude(const AltitudeOptions& opt, std::size_t index, double mission_altitude_m);

/// Mission items for UAV `index` of `plan` (home = the UAV's start, not included as an item).
std::vector<MissionItem> mission_items(const Plan& plan, std::size_t index, const AltitudeOptions& opt = {});

}  // namespace uavcover::exporting
