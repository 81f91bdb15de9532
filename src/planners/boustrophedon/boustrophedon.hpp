// The boustrophedon planner (the lawnmower of QGroundControl's Survey, Fields2Cover and ETHZ
// polygon_coverage_planning): the free area is divided among the UAVs by share, each UAV's part is
// decomposed into monotone cells (boustrophedon cellular decomposition), each cell is swept in
// its own direction with the fewest legs, and the cells are ordered into a short tour.
#pragma once

#include "planners/planner.hpp"

namespace uavcover::planners {

PlannerInfo boustrophedon_planner_info();

}  // namespace uavcover::planners
