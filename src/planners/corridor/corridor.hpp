// Corridor sweeps (docs/patterns.md), shared by the planners that support corridors (boustrophedon,
// milp): lanes parallel to the centre line at the spacing, ceil(width / spacing) of them, mitred joints
// (round on the outside of bends sharper than 120 degrees) that keep the spacing on bends; the
// corridor cut across into consecutive pieces by share, one per UAV, each flying every lane of its
// piece from the end nearest its start; no-fly zones cut the lanes (the engine routes the transit
// around them); the pattern options (crosshatch, turnaround_m, entry, alternate_transects,
// capture_in_turnaround) on the lanes.
#pragma once

#include "planners/planner.hpp"

namespace uavcover::planners::corridor {

/// Number of lanes of a corridor: ceil(width / spacing), at least 1.
int lane_count(double width_m, double spacing_m);

/// The lane at `offset_m` to the left of `line` (negative: right) between arc lengths `from_m` and `to_m`
/// of the line (0 <= from < to <= length): the parallel polyline, mitred at joints.
std::vector<Point> offset_lane(const std::vector<Point>& line, double offset_m, double from_m, double to_m);

/// Plans a corridor mission (Problem::corridor_line non-empty).
Assignment plan(const Problem& problem, const Context& ctx);

}  // namespace uavcover::planners::corridor
