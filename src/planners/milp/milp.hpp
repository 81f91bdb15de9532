// The MILP sweep planner (Hong et al. 2021, "Autonomous Mission of Multi-UAV for Optimal Area Coverage"):
// virtual lines along the longest boundary edge, their segments inside the free area as waypoint pairs, and
// the assignment of the segments to the UAVs (order and direction included) by a mixed-integer linear
// program solved with COIN-OR CBC. Large instances are clustered by share and contracted into blocks
// of neighbouring lines; see docs/planners/milp.md.
#pragma once

#include "planners/planner.hpp"

namespace uavcover::planners {

PlannerInfo milp_planner_info();

}  // namespace uavcover::planners
