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
enum MavFrame : std::uint8_t {
  kFrameGlobal = 0,
  kFrameMission = 2,
  kFrameGlobalRelativeAlt = 3,
  kFrameGlobalTerrainAlt = 10,  ///< height above the terrain under the item (issue 31, ArduPilot)
};

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
  /// coverage leg where terrain following changes the height), "lead_in" (a sortie's re-flown stretch
  /// before its first waypoint, issue 31), "rtl", "land"
  std::string role;
  int part = -1;  ///< index into UavPlan::parts the item comes from; -1 for virtual/command items
  /// On "coverage" items: the index of the coverage waypoint among the UAV's coverage waypoints (the
  /// vertices of its coverage parts in flight order, as Sortie::first_waypoint counts them); -1 otherwise.
  int waypoint = -1;
};

/// True for the items with a position: take-off, waypoint, land.
[[nodiscard]] inline bool has_position(const MissionItem& it) {
  return it.command == kNavWaypoint || it.command == kNavTakeoff || it.command == kNavLand;
}

/// True for an item on a coverage leg: a "coverage" waypoint or one the leg holds ("terrain", "capture",
/// "lead_in"). Two such items of the same part are ends of a leg that sweeps (not a transit).
[[nodiscard]] inline bool in_coverage_leg(const MissionItem& it) {
  return it.role == "coverage" || it.role == "terrain" || it.role == "lead_in" || it.role == "capture";
}

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
  /// Terrain frame (issue 31, docs/photogrammetry.md): with a DEM and terrain following, the coverage
  /// waypoints carry their height above the ground in MAV_FRAME_GLOBAL_TERRAIN_ALT (10) and the vehicle
  /// follows the ground itself from its own terrain data: no "terrain" waypoints between them. Take-off,
  /// transit and landing stay above mean sea level. ArduPilot only (PX4 refuses the frame).
  bool terrain_frame = false;
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

/// A coverage leg whose ground is too steep for the terrain block's limits (issue 31): climbing or
/// descending faster than max_climb_mps / max_descent_mps at cruise speed (flown slower: speed_mps), or
/// steeper than max_grade (said, not changed: no speed makes a grade smaller).
struct SteepLeg {
  std::size_t from_item = 0, to_item = 0;  ///< indices into the items
  LonLat from, to;
  double length_m = 0, dz_m = 0;
  double cruise_mps = 0, speed_mps = 0;  ///< the UAV's speed, and the leg's (lower when slowed)
  bool over_grade = false;
};
/// The steep legs of UAV `index`'s items (empty without a limit or without terrain following).
std::vector<SteepLeg> steep_legs(const Plan& plan, std::size_t index, const std::vector<MissionItem>& items);
/// "the leg from (lon, lat) to (lon, lat) climbs 12.0 m over 30.0 m, ...: flown at 2.50 m/s".
std::string describe(const SteepLeg& leg, const Plan& plan);

/// Mission items for UAV `index` of `plan` (home = the UAV's start, not included as an item), with the
/// transition altitudes of resolve_altitudes() for the plan's UAVs. With a DEM every altitude is above
/// mean sea level (frame 0, MAV_FRAME_GLOBAL); in follow mode each coverage waypoint flies at the
/// mission altitude above the ground under it, and "terrain" waypoints inside the coverage legs keep
/// the height above ground within terrain.tolerance_m between them (docs/photogrammetry.md).
std::vector<MissionItem> mission_items(const Plan& plan, std::size_t index, const AltitudeOptions& opt = {});
/// The same for UAV `index` flying `parts` instead of its own (one sortie's, Sortie::parts), without a copy
/// of the plan.
std::vector<MissionItem> mission_items(const Plan& plan, std::size_t index,
                                       const std::vector<PathPart>& parts, const AltitudeOptions& opt = {});

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

/// The ground under UAV `index`'s whole flight (issue 31, the web app's ground profile): its mission
/// items' path from take-off to landing sampled at most `max_samples` times (evenly by distance, and at
/// every positioned item), with the ground and the flight's height AMSL (linear between the items), and
/// the band of heights above ground over its coverage legs. std::nullopt without a DEM.
struct PathProfile {
  std::string uav;
  double length_m = 0.0;
  struct Sample {
    double s_m = 0, ground_m = 0, flight_m = 0;
    bool coverage = false;  ///< on a coverage leg
  };
  std::vector<Sample> samples;
  double agl_min_m = 0.0, agl_max_m = 0.0;  ///< height above ground over the coverage legs
  double altitude_m = 0.0, tolerance_m = 0.0;
};
std::optional<PathProfile> path_profile(const Plan& plan, std::size_t index, std::size_t max_samples = 1000,
                                        const AltitudeOptions& opt = {});

}  // namespace uavcover::waypoints
