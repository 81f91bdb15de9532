// What the autopilots accept (issue 34, "make this class impossible"): the rules ArduPilot and PX4 apply
// to a mission when it is uploaded, re-implemented from their sources, in one place for the exporters'
// checks (export_artifacts), the tests that run them over every planner and capture mode, and the
// simulator's side of the mission protocol (src/sim/sim_vehicle.cpp), which answers what ArduPilot answers.
// The rules and their sources are listed in docs/exports.md ("What the autopilots accept").
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mavlink/messages.hpp"
#include "uavcover/geometry.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::autopilot {

using waypoints::MissionItem;

/// MAV_MISSION_INVALID_PARAM1 (+ n - 1 for param n, up to PARAM7 = 12); PARAM5_X and PARAM6_Y by name.
inline constexpr std::uint8_t kMissionInvalidParam1 = 6;
inline constexpr std::uint8_t kMissionInvalidParam5X = 10;
inline constexpr std::uint8_t kMissionInvalidParam6Y = 11;
inline constexpr std::uint8_t kMissionInvalidParam7 = 12;

/// One rule an item or a mission breaks.
struct Problem {
  bool fatal = true;    ///< the autopilot refuses the mission (false: it warns, or a configurable limit)
  long item = -1;       ///< index into the items checked (no home), -1 for the whole mission
  std::string rule;     ///< where the rule comes from, e.g. "ArduPilot AP_Mission::sanity_check_params"
  std::string message;  ///< what is wrong
};

/// ArduPilot's answer to one MISSION_ITEM_INT of an upload (libraries/AP_Mission/AP_Mission.cpp,
/// AP_Mission::mavlink_int_to_mission_cmd): first AP_Mission::sanity_check_params (NaN only in param 4 of
/// NAV_WAYPOINT, NAV_LAND, NAV_TAKEOFF, NAV_VTOL_TAKEOFF and in params 3-4 of NAV_VTOL_LAND; no infinity
/// anywhere: MAV_MISSION_INVALID_PARAMn), then the command must be one it converts
/// (MAV_MISSION_UNSUPPORTED otherwise), then for commands stored with a location (stored_in_location)
/// check_lat/check_lng on x/y (INVALID_PARAM5_X / PARAM6_Y), a finite z below LOCATION_ALT_MAX_M
/// (83 000 m, INVALID_PARAM7) and a global or mission frame (MAV_MISSION_UNSUPPORTED_FRAME).
/// Returns mavlink::kMissionAccepted when ArduPilot stores the item.
std::uint8_t ardupilot_item_result(const mavlink::MissionItemInt& item);

struct ArduPilotLimits {
  /// Mission items the board stores, home included (AP_Mission::num_commands_max(): storage-dependent,
  /// about 700 on common boards; issue 31).
  std::size_t max_items = 700;
};

/// Every ArduPilot rule `items` (as exported, without home) break when uploaded with home as item 0
/// (the .waypoints row 0 and `uavcover upload`): ardupilot_item_result() per item; the item count against
/// max_items (MAV_MISSION_NO_SPACE, not fatal: configurable); a mission that does not start with a
/// take-off (ArduCopter/mode_auto.cpp ModeAuto::init with AP_Mission::starts_with_takeoff_cmd: "Auto:
/// Missing Takeoff Cmd"); and the camera commands' meaning (AP_Camera): IMAGE_START_CAPTURE param1 is
/// the camera instance and must be 0 (all cameras), param3 1 (one image); DO_SET_CAM_TRIGG_DIST param3
/// (shoot now) 0 or 1.
std::vector<Problem> ardupilot_problems(const std::vector<MissionItem>& items,
                                        const ArduPilotLimits& limits = {});

/// PX4's mission parameters the feasibility checks read (defaults: PX4's own).
struct Px4Params {
  std::size_t max_items = 500;  ///< dataman mission items on NuttX boards (DM_KEY_WAYPOINTS_OFFBOARD_x_MAX)
  double nav_acc_rad_m = 10.0;  ///< NAV_ACC_RAD
  double mis_dist_1wp_m = 900;  ///< MIS_DIST_1WP (<= 0 disables)
  double mis_dist_wps_m = 900;  ///< MIS_DIST_WPS (<= 0 disables; gone in newer releases)
};

/// Every PX4 rule `items` break (src/modules/navigator/MissionFeasibility/FeasibilityChecker.cpp and
/// src/modules/mavlink/mavlink_mission.cpp): supported commands (checkMissionItemValidity); take-off at
/// least NAV_ACC_RAD + 1 m above home and the first positioned item (checkTakeoff); the first waypoint
/// within MIS_DIST_1WP of home (checkDistanceToFirstWaypoint) and consecutive positioned items within
/// MIS_DIST_WPS (checkDistancesBetweenWaypoints), both not fatal (warnings in newer releases); not below
/// home (checkIfBelowHomeAltitude, a warning); global frames on positioned items and finite coordinates
/// (parse_mavlink_mission_item); the item count (not fatal). `home_amsl_m` is the home's height above
/// mean sea level, for items in frame 0.
std::vector<Problem> px4_problems(const std::vector<MissionItem>& items, LonLat home, double home_amsl_m,
                                  const Px4Params& params = {});

/// "item 3 (MAV_CMD 1000): ..." for messages.
std::string describe(const Problem& p, const std::vector<MissionItem>& items);

}  // namespace uavcover::autopilot
