// Dividing the free area among the UAVs by share: the cells of a decomposition are sliced into
// strips along the legs and handed out, UAV after UAV, as connected groups grown from one side of
// the area (a piece is only taken when the rest stays connected); the last piece of a group is cut
// to the exact share when the geometry allows it.
#pragma once

#include <vector>

#include "planners/boustrophedon/geom.hpp"
#include "uavcover/context.hpp"

namespace uavcover::planners::boustro {

struct Division {
  std::vector<MultiPolygon> regions;  ///< one per UAV (world), exclusive, union = the free area
  int pieces = 0;                     ///< strips handed out
  int split_failures = 0;             ///< groups that could not be cut to their exact share
};

/// `angle`: the legs' direction of the decomposition used for the strips.
Division divide(const MultiPolygon& free, const std::vector<double>& shares, const std::vector<Point>& starts,
                double angle, double spacing, const Context& ctx);

}  // namespace uavcover::planners::boustro
