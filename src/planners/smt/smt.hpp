// The SMT route planner (POPCORN, Shah et al. 2020, public code k2shah/wadl): a lattice of capture
// points at the mission's spacing, split into small subgraphs whose closed covering walks z3 finds and
// shortens by tightening a pseudo-Boolean length bound, stitched into cyclic routes from each UAV's
// home point under the UAV's flight-time limit. Registered as "smt" (CMake option UAVCOVER_SMT).
#pragma once

#include "planners/planner.hpp"

namespace uavcover::planners {

PlannerInfo smt_planner_info();

}  // namespace uavcover::planners
