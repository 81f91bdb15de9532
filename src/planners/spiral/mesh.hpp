// The spiral planner's mesh: a constrained Delaunay triangulation of the free area (outer rings,
// holes and no-fly zones as constraints) refined to a maximum edge length, then Lloyd-optimised
// (CGAL Mesh_2). The result is plain data, so that only mesh.cpp includes CGAL.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "uavcover/context.hpp"
#include "uavcover/geometry.hpp"

namespace uavcover::planners::spiral {

/// Histogram of the triangles' interior angles (18 bins of 10 degrees) and summary statistics.
struct AngleStats {
  std::array<std::size_t, 18> bins{};
  double min_deg = 0.0;          ///< smallest interior angle
  double mean_min_deg = 0.0;     ///< mean over triangles of each triangle's smallest angle
  double within_10_of_60 = 0.0;  ///< fraction of angles in [50, 70] degrees
};

struct Mesh {
  std::vector<Point> vertices;
  std::vector<std::array<int, 3>> triangles;   ///< vertex indices, counter-clockwise
  std::vector<std::array<int, 3>> neighbours;  ///< across the edge opposite vertex i; -1: none (border)
};

/// Lloyd optimiser: CGAL's lloyd_optimize_mesh_2, or the same move (centroid of the restricted
/// Voronoi cell) applied on the triangulation by flips (linear per step).
enum class LloydMethod { Local, Cgal };

/// CGAL's lloyd_optimize_mesh_2 cannot be interrupted inside a step (no callback; its `time_limit` is
/// wall-clock, so a result would depend on the machine's load), and a step is super-linear: one step
/// took 0.10-0.13 s CPU on 16 800 triangles, 0.19 s on 20 200, 0.25 s on 24 300, 0.26-0.32 s on 28 500
/// and 0.72 s on 43 000 (docs/planners/spiral.md). `lloyd_method: cgal` is refused above this many
/// triangles, so that a stop lands within about 0.2 s CPU; `local` has no such bound.
inline constexpr std::size_t kMaxCgalLloydTriangles = 20'000;

struct MeshOptions {
  double max_edge_m = 0.0;    ///< refinement bound on every triangle edge (W_d)
  int lloyd_iterations = 10;  ///< Lloyd steps after refinement (0: none)
  LloydMethod lloyd = LloydMethod::Local;
  std::size_t max_triangles = 0;  ///< refuse (InputError on `field`) beyond this many
};

struct MeshReport {
  AngleStats before_lloyd, after_lloyd;
  double refine_s = 0.0, lloyd_s = 0.0;
  double lloyd_cpu_s = 0.0;  ///< the Lloyd steps' CPU time on this thread
  std::size_t triangles_before_lloyd = 0;
  double max_edge_m = 0.0;  ///< longest edge of the final mesh
};

/// Meshes `free` (corrected polygons). Honours ctx.check() during refinement, between Lloyd steps and
/// (local method) every 1024 vertices inside a step; reports progress "spiral" 0.05-0.4 per Lloyd step.
/// Throws InputError("spacing_m", ...) when the mesh would exceed options.max_triangles, and
/// InputError("planner_params.lloyd_method", ...) when CGAL's Lloyd would run on more than
/// kMaxCgalLloydTriangles triangles (checked on the refined mesh, before any Lloyd step).
Mesh build_mesh(const MultiPolygon& free, const MeshOptions& options, const Context& ctx, MeshReport& report);

/// Angle statistics of a mesh.
AngleStats angle_stats(const Mesh& mesh);

/// Length of the mesh's longest triangle edge.
double longest_edge(const Mesh& mesh);

}  // namespace uavcover::planners::spiral
