// The DARP planner module (Apostolidis et al. 2022): grid placement by simulated annealing, DARP
// division, STC coverage loops. Registered as "darp".
#pragma once

#include "planners/planner.hpp"

namespace uavcover::planners {

PlannerInfo darp_planner_info();

}  // namespace uavcover::planners
