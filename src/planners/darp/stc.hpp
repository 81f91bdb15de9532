// Spanning Tree Coverage on the mega-cell grid (Apostolidis et al. 2022 §2.3.2): a spanning tree
// per region, circumnavigated on the sub-cells. Several tree orientations are tried and the path
// with the fewest turns is kept.
#pragma once

#include <vector>

#include "planners/darp/grid.hpp"
#include "uavcover/geometry.hpp"

namespace uavcover::stc {

struct Loop {
  /// Closed loop (last == first) of turning waypoints, local frame, starting at the loop's
  /// turning vertex nearest the entry point.
  std::vector<Point> points;
  int turns = 0;        ///< turning vertices (points.size() - 1)
  int orientation = 0;  ///< index of the tree orientation kept
};

/// Number of tree orientations plan_loop tries by default.
inline constexpr int kOrientations = 8;

/// Plans the coverage loop of one region: `cells` are mega-cell indices of `g`, connected over
/// the grid's links. The first `orientations` (1..kOrientations) tree orientations are tried and the
/// loop with the fewest turns kept (the paper's turn reduction, Fig. 8-9); 1 is the tree without it
/// (rows joined by vertical links, ascending). Deterministic.
Loop plan_loop(const grid::Grid& g, const std::vector<int>& cells, Point entry,
               int orientations = kOrientations);

}  // namespace uavcover::stc
