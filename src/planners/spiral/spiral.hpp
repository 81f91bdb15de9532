// The spiral planner (Balampanis et al. 2017): a constrained Delaunay triangulation of the free area
// with triangles sized by the camera's footprint, Lloyd-optimised; the triangle graph divided into
// one connected sub-area per UAV by share; each sub-area flown from its border to its centre, level
// by level, with the valley rule. CGAL is private to this module's target (mesh.cpp).
#pragma once

#include "planners/planner.hpp"

namespace uavcover::planners {

PlannerInfo spiral_planner_info();

}  // namespace uavcover::planners
