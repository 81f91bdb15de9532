// MAVLink-style mission items for one UAV of a plan: the common model behind the QGroundControl
// .plan, Mission Planner WPL, and the MAVLink upload. Altitudes follow Hong et al. 2021 §2.3:
// take-off, climb to the UAV's own transition altitude, fly to the region, descend to mission
// altitude, cover, climb back, return, RTL/land.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "uavcover/plan.hpp"

namespace uavcover::waypoints {

/// MAV_CMD numbers used here.
enum MavCmd : std::uint16_t {
  kNavWaypoint = 16,
  kNavReturnToLaunch = 20,
  kNavLand = 21,
  kNavTakeoff = 22,
  kDoChangeSpeed = 178,
  kDoSetCamTriggDist = 206,
  kDoGimbalManagerPitchyaw = 1000,
  kImageStartCapture = 2000,
};
/// MAV_FRAME numbers used here.
enum MavFrame : std::uint8_t { kFrameGlobal = 0, kFrameMission = 2, kFrameGlobalRelativeAlt = 3 };

struct MissionItem {
  std::uint16_t command = kNavWaypoint;
  std::uint8_t frame = kFrameGlobalRelativeAlt;
  /// On positioned items (take-off, waypoint, land) param4 is the yaw: NaN = keep the vehicle's heading
  /// mode (MAVLink MAV_CMD_NAV_WAYPOINT/TAKEOFF/LAND param4; ArduPilot accepts NaN there, PX4 treats it
  /// as "no yaw set"). Every format writes it so: null in .plan, NaN in .waypoints, the CSV and MAVLink.
  float param1 = 0, param2 = 0, param3 = 0, param4 = 0;
  double lat = 0, lon = 0;  ///< degrees (0 for commands without a position)
  float alt = 0;            ///< metres, relative to home in frame 3, above mean sea level in frame 0
  bool autocontinue = true;
  /// "takeoff", "transition", "coverage", "transit", "speed", "gimbal", "camera" (a trigger command),
  /// "capture" (a hover-and-capture stop between coverage waypoints), "terrain" (a waypoint inside a
  /// coverage leg where terrain following changes the height), "rtl", "land"
  std::string role;
  int part = -1;  ///< index into UavPlan::parts the item comes from; -1 for virtual/command items
  /// On "coverage" items: the index of the coverage waypoint among the UAV's coverage waypoints (the
  /// vertices of its coverage parts in flight order, as Sortie::first_waypoint counts them); -1 otherwise.
  int waypoint = -1;
};

struct AltitudeOptions {
  /// First UAV's transition altitude; 0 = automatic: the larger of 60 m and mission altitude + 20 m.
  double transition_base_m = 0.0;
  double transition_step_m = 10.0;  ///< added per UAV index
  /// No transition altitude above this (metres above take-off; 120 m is the usual legal limit for
  /// open-category flights). 0 = no ceiling.
  double transition_ceiling_m = 120.0;
  /// When the top UAV would fly above the ceiling, the step is compressed to fit as long as it stays
  /// at least this large; below it the altitudes are refused.
  double min_vertical_separation_m = 5.0;
  bool land_instead_of_rtl = false;
};

/// Altitude layers (Mission::transition_altitudes "layers", docs/mission-format.md): the number of
/// transition altitudes the plan's UAVs share (Plan::separation "layers"); with "hong", one per UAV.
/// Pass it to resolve_altitudes() as the count.
std::size_t altitude_slots(const Plan& plan);
/// The transition altitude index of UAV `index`: its layer, or with "hong" the UAV's own index. Pass it
/// to transition_altitude() and flight_transit_altitude().
std::size_t altitude_slot(const Plan& plan, std::size_t index);

/// Transition altitude of UAV `index` (base + index * step) for a mission flown at
/// `mission_altitude_m` (which sets the automatic base). No ceiling: see resolve_altitudes().
double transition_altitude(const AltitudeOptions& opt, std::size_t index, double mission_altitude_m);

/// The options with an explicit base and a step that keeps `uav_count` UAVs under the ceiling:
/// the step is compressed (with a warning into `warnings` when given) when that keeps it at least
/// min_vertical_separation_m. Throws InputError (naming the option and what to change) when the UAVs
/// cannot be separated under the ceiling. Resolving resolved options changes nothing.
AltitudeOptions resolve_altitudes(const AltitudeOptions& opt, std::size_t uav_count,
                                  double mission_altitude_m, std::vector<std::string>* warnings = nullptr);

/// UAV `index`'s (the plan's UAV; its layer is looked up) transit altitude with `resolved` options: its
/// transition altitude, relative to take-off; with a DEM (Mission::terrain), above mean sea level: the
/// transition altitude over the highest ground of the mission's extent (HeightGrid::max_m), so that every
/// transit leg clears the ground under it by at least the transition altitude and the UAVs stay apart by the
/// step.
double flight_transit_altitude(const Plan& plan, const AltitudeOptions& resolved, std::size_t index);

/// Mission items for UAV `index` of `plan` (home = the UAV's start, not included as an item), with the
/// transition altitudes of resolve_altitudes() for the plan's UAVs. With a DEM every altitude is above
/// mean sea level (frame 0, MAV_FRAME_GLOBAL); in follow mode each coverage waypoint flies at the
/// mission altitude above the ground under it, and "terrain" waypoints inside the coverage legs keep
/// the height above ground within terrain.tolerance_m between them (docs/photogrammetry.md).
std::vector<MissionItem> mission_items(const Plan& plan, std::size_t index, const AltitudeOptions& opt = {});

/// Ground and flight heights along one coverage leg (the picture of docs/terrain-profile.png).
struct LegProfile {
  std::string uav;
  int first_waypoint = -1;  ///< the leg's first coverage waypoint (UavPlan's global index)
  double length_m = 0.0;
  std::vector<std::pair<double, double>> ground;  ///< (distance from the leg's start m, ground m AMSL)
  std::vector<std::pair<double, double>> flight;  ///< (distance, altitude m AMSL) of the waypoints flown
  int terrain_waypoints = 0;                      ///< waypoints terrain following added inside the leg
  double altitude_m = 0.0;                        ///< the camera's height above ground
  double tolerance_m = 0.0;                       ///< terrain.tolerance_m (0 when not following)
};

/// The profile of UAV `index`'s coverage leg with the most terrain waypoints (ties: the longer), from
/// its mission items; std::nullopt without a DEM or without coverage.
std::optional<LegProfile> leg_profile(const Plan& plan, std::size_t index, const AltitudeOptions& opt = {});

}  // namespace uavcover::waypoints
