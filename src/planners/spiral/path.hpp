// The spiral waypoint list of one sub-area (Balampanis et al. 2017, Algorithm 1) and its flight path:
// triangles visited level by level from the border inwards, nearest neighbour within a level, far
// steps deferred by the valley rule; legs between non-adjacent triangles routed inside the sub-area;
// collinear runs merged. No CGAL.
#pragma once

#include <array>
#include <vector>

#include "planners/spiral/mesh.hpp"
#include "uavcover/context.hpp"

namespace uavcover::planners::spiral {

struct SpiralOrder {
  std::vector<int> order;     ///< every triangle of the sub-area once, in visiting order
  double step_bound_m = 0.0;  ///< S_m = S_s * the largest distance between neighbouring centroids
  int deferred = 0;           ///< steps the valley rule deferred
};

/// Algorithm 1 over the triangles owned by `uav`: start at the border triangle nearest `start`; visit
/// the current level by nearest neighbour; a step longer than S_m to the next triangle of the level is
/// deferred (kept for later) and the walk goes one level inwards instead; when the inner levels are
/// done, the nearest deferred triangle resumes its level.
SpiralOrder spiral_order(const Mesh& mesh, const std::vector<Point>& centroid, const std::vector<int>& owner,
                         const std::vector<int>& level, int uav, Point start, double valley_sensitivity,
                         const Context& ctx);

/// The flight path through the centroids in `order`: consecutive triangles that do not share an edge
/// are joined through the sub-area (shortest chain of neighbouring triangles, pulled straight where
/// the line stays inside the chain); a triangle unreachable inside the sub-area starts a new part.
/// Collinear runs are merged so that only turning waypoints remain.
std::vector<std::vector<Point>> route(const Mesh& mesh, const std::vector<Point>& centroid,
                                      const std::vector<int>& owner, int uav, const std::vector<int>& order,
                                      const Context& ctx);

/// Drops interior points where the path goes straight on (turn below `tol_deg`); reversals stay.
std::vector<Point> merge_collinear(const std::vector<Point>& pts, double tol_deg = 0.5);

/// The angle at b of the path a-b-c in degrees: 180 straight on, 0 a full reversal.
double turn_angle_deg(Point a, Point b, Point c);

/// The optional smoothing pass (beyond the paper): where the path through the centroids in `order`
/// turns by an angle below `reversal_deg` (a reversal), reverses a run of 2-4 consecutive triangles of
/// one level around it when that leaves fewer reversals among the turns it touches and the local
/// path at most 25 % longer; up to three passes. The order stays a permutation of the same triangles
/// and border levels keep their place. Returns the runs reversed; 0 when reversal_deg <= 0.
int smooth_order(const std::vector<Point>& centroid, const std::vector<int>& level, std::vector<int>& order,
                 double reversal_deg, const Context& ctx);

/// The paper's path metrics (Tables I-III).
struct PathStats {
  double length_m = 0.0;
  double min_step_m = 0.0, max_step_m = 0.0;                              ///< between consecutive waypoints
  double min_angle_deg = 0.0, max_angle_deg = 0.0, mean_angle_deg = 0.0;  ///< at waypoints, 180 = straight
  std::array<int, 6> angle_bins{};                                        ///< 30-degree bins of those angles
  int waypoints = 0;
};
PathStats path_stats(const std::vector<std::vector<Point>>& parts);

/// The union of the triangles owned by `uav`, traced along their boundary edges (corrected polygons
/// with holes; sub-areas that touch themselves at a vertex give rings that share that vertex).
MultiPolygon region_of(const Mesh& mesh, const std::vector<int>& owner, int uav);

}  // namespace uavcover::planners::spiral
