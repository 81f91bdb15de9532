// The whole flight's vertical time (issue 32, docs/wind.md#the-whole-flight): what a UAV spends climbing or
// descending beyond its horizontal flight along its mission items (the take-off climb, the descents to the
// coverage height, the climbs back to the transition altitude, the landing), at its climb_mps and
// descent_mps. eq. 15 is the paper's horizontal model; this is the rest of arming to touchdown.
#pragma once

#include <cstddef>
#include <vector>

#include "uavcover/plan.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::waypoints {

/// Per item of `items` (UAV `index` of `plan`, flown from its start on the ground): the seconds of the leg
/// that arrives at that item which its height change takes beyond its horizontal flight,
/// max(0, climb or descent / vertical speed - air distance / speed) in the mission's wind. A take-off climbs
/// on the spot from the ground; a land item flies there and descends to its height; RTL flies home at its
/// height and descends to the ground at home. 0 for items without a position.
std::vector<double> vertical_extra_s(const Plan& plan, std::size_t index,
                                     const std::vector<MissionItem>& items);

/// The sum of vertical_extra_s().
double vertical_time_s(const Plan& plan, std::size_t index, const std::vector<MissionItem>& items);

/// The transition altitudes the whole-flight time is computed at: the exports' defaults for the plan's
/// altitude slots (resolve_altitudes()), without the ceiling when its UAVs cannot be separated under it.
AltitudeOptions whole_flight_altitudes(const Plan& plan);

/// UAV `index`'s vertical time over all its missions: each battery sortie's items (one mission when it has
/// no sorties), with the transition altitudes of `opt`. 0 for a UAV with nothing to fly.
double uav_vertical_time_s(const Plan& plan, std::size_t index, const AltitudeOptions& opt = {});

}  // namespace uavcover::waypoints
