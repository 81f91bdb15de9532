// Region polygons of a grid division: the boundary of the cells a UAV owns, traced along the cell
// edges, so that downstream code (render, separation, export fences) never needs the grid.
#pragma once

#include <functional>
#include <vector>

#include "uavcover/geometry.hpp"

namespace uavcover::darp {

/// The cells with owner[r * cols + c] == uav as polygons (outer rings and holes, corrected).
/// `corner(c, r)` maps the grid corner (column c, row r) to the local frame. Cells that touch only
/// at a corner become separate polygons.
MultiPolygon cells_to_polygons(int rows, int cols, const std::vector<int>& owner, int uav,
                               const std::function<Point(int c, int r)>& corner);

}  // namespace uavcover::darp
