// Boustrophedon cellular decomposition (Choset 2000): sweep a line X = const across the area (in the
// frame of a sweep direction) and cut it at every vertex where the number of intervals of the line
// inside the area changes (split, merge, start, end events). Each cell is cut by every line
// X = const in one interval, so it can be covered by legs along Y without leaving it.
#pragma once

#include <vector>

#include "planners/boustrophedon/geom.hpp"
#include "uavcover/context.hpp"

namespace uavcover::planners::boustro {

struct Decomposition {
  Frame frame;
  std::vector<Monotone> cells;  ///< in the frame
  /// Per cell: X of the lines through its reflex vertices (where the cell may be cut in two to
  /// sweep each side its own way), increasing, strictly inside the cell.
  std::vector<std::vector<double>> cuts;
  /// Cell `left` touches cell `right` along the line X = x (left's right end, right's left end).
  struct Link {
    int left = 0, right = 0;
    double x = 0.0;
  };
  std::vector<Link> links;
};

/// Decomposes `world` (local metres) into cells monotone along the frame's X. With `reflex_cuts`,
/// the lines through reflex vertices are returned as optional cuts of each cell.
Decomposition decompose(const MultiPolygon& world, const Frame& frame, const Context& ctx,
                        bool reflex_cuts = false);

/// The part of a monotone cell between X = x0 and X = x1 (x0 < x1, clamped to the cell).
Monotone clip(const Monotone& m, double x0, double x1);

/// Area of a monotone cell (frame units, m^2).
double area(const Monotone& m);

}  // namespace uavcover::planners::boustro
