// The waypoint model's variant for ArduPilot (issue 30, docs/exports.md "Attitude"): ArduCopter turns to
// a heading on MAV_CMD_CONDITION_YAW, not on NAV_WAYPOINT param4, and PX4 refuses CONDITION_YAW in a
// mission, so only the exports for ArduPilot carry it.
#pragma once

#include <cstdint>
#include <vector>

#include "waypoints/waypoints.hpp"

namespace uavcover::waypoints {

/// MAV_CMD numbers of the attitude items (PathPart::attitude), besides those of waypoints.hpp.
inline constexpr std::uint16_t kConditionYaw = 115;  ///< role "heading" (ArduPilot exports)
inline constexpr std::uint16_t kDoSetRoi = 201;  ///< role "roi": param1 3 MAV_ROI_LOCATION, 0 MAV_ROI_NONE

/// mission_items() with a MAV_CMD_CONDITION_YAW (param1 the heading, param2 0 default rate, param3 0 the
/// short way, param4 0 absolute) just before every waypoint that has a heading of its own, in parts
/// without a region of interest.
std::vector<MissionItem> ardupilot_mission_items(const Plan& plan, std::size_t index,
                                                 const AltitudeOptions& opt = {});

}  // namespace uavcover::waypoints
