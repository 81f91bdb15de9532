// The spiral planner's graph work on the mesh (no CGAL): triangle measures, the division of the
// triangle adjacency graph into one connected sub-area per UAV sized by share, and each triangle's
// border-to-centre level (Balampanis et al. 2017 §III and §V).
#pragma once

#include <vector>

#include "planners/spiral/mesh.hpp"
#include "uavcover/context.hpp"

namespace uavcover::planners::spiral {

std::vector<Point> centroids(const Mesh& mesh);
std::vector<double> areas(const Mesh& mesh);

struct Partition {
  std::vector<int> owner;      ///< per triangle: the UAV
  std::vector<int> seed;       ///< per UAV: the triangle its sub-area grew from
  std::vector<double> share;   ///< per UAV: its triangles' area over the whole mesh's
  double max_deviation = 0.0;  ///< max |share - requested| / requested
  int moves = 0;               ///< triangles moved while balancing
  int extra_seeds = 0;         ///< components no UAV's growth reached, given to the neediest UAV
};

/// Grows one sub-area per UAV from the triangle under (or nearest) its start, the UAV with the
/// smallest fill (area over target) taking its nearest frontier triangle next, then moves border
/// triangles from over- to under-filled neighbours, keeping every sub-area connected, until every
/// share is within `tolerance` of itself (0.01: 1 % of the share) or no move helps. Each sub-area is
/// connected over shared edges when the mesh is (per component otherwise).
Partition partition(const Mesh& mesh, const std::vector<Point>& centroid, const std::vector<double>& area,
                    const std::vector<Point>& starts, const std::vector<double>& shares, double tolerance,
                    const Context& ctx);

/// Per triangle: its graph distance (over shared edges inside its own sub-area) from the sub-area's
/// border; 0 for triangles with an edge on the border.
std::vector<int> levels(const Mesh& mesh, const std::vector<int>& owner);

}  // namespace uavcover::planners::spiral
