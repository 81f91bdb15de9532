// The order of a UAV's cells and each cell's entry: a short tour from the start through every cell
// and back (straight-line distances; the engine routes the transit legs around no-fly zones).
#pragma once

#include <array>
#include <vector>

#include "uavcover/context.hpp"
#include "uavcover/geometry.hpp"

namespace uavcover::planners::boustro {

/// Entry and exit of a cell for each of its four ways of being flown.
struct CellEnds {
  std::array<Point, 4> entry, exit;
};

struct Tour {
  std::vector<int> order;    ///< cell indices in flight order
  std::vector<int> variant;  ///< per position in `order`: which of the cell's four ways
  double transit_m = 0.0;    ///< straight-line transit, start and return included
};

/// Greedy tour improved by 2-opt and or-opt moves, the ways chosen optimally for each order.
Tour order_cells(const std::vector<CellEnds>& cells, Point start, const Context& ctx);
/// From `start` to `home`, the first leg counted `first_weight` times: with a large weight the tour
/// enters at the cell corner nearest `start` (a pattern's fixed entry) whatever it costs later.
Tour order_cells(const std::vector<CellEnds>& cells, Point start, Point home, double first_weight,
                 const Context& ctx);

}  // namespace uavcover::planners::boustro
