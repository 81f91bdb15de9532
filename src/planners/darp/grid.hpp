// Grid representation of the free space (Apostolidis et al. 2022 §2.1) and the placement index J
// (§2.2, eq. 7-10).
//
// Frames: the grid frame q is the local ENU frame rotated by -theta and shifted by (sx, sy):
//   q = R(-theta) * p + s,     p = R(theta) * (q - s).
// Mega-cells (size dn = 2*ds) are axis-aligned in q; mega-cell (r, c) spans
// [x0 + c*dn, x0 + (c+1)*dn] x [y0 + r*dn, y0 + (r+1)*dn]. Each holds 2x2 sub-cells of size ds; the
// coverage path runs through sub-cell centres. Sub-cell (i, j) (column i, row j) has its centre at
// q = (x0 + (i+0.5)*ds, y0 + (j+0.5)*ds), and belongs to mega-cell (j/2, i/2).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "uavcover/geometry.hpp"
#include "uavcover/mission.hpp"

namespace uavcover::grid {

/// The closest a path segment may come to a no-fly zone's edge, metres: five times the rounding of
/// exported coordinates (1e-7 degrees, about 1 cm), so that a path skirting a thin no-fly zone cannot
/// land inside it once written as WGS84 (PX4's check has no tolerance). 0.2 m changed the grid placement
/// of the paper's region 11 (137 -> 157 turns); 0.05 m keeps it.
inline constexpr double kClearance = 0.05;

struct Edge {
  Point a, b;
};

/// The free space and no-fly zones prepared once for many rasterisations.
struct Prepared {
  std::vector<Edge> free_edges;  ///< all ring edges of the free space (local frame)
  std::vector<Edge> nfz_edges;   ///< all ring edges of the no-fly zones (local frame)
  double free_area = 0.0;
  int free_parts = 0;  ///< polygons in the free multipolygon
  double ds = 0.0;
  Mode mode = Mode::Strict;
  bool estimate_coverage = true;  ///< rasterize() also fills Grid::coverage_estimate
  int estimate_samples = 8;       ///< samples per mega-cell side for that estimate (<= 16)
};

Prepared prepare(const MultiPolygon& free, const MultiPolygon& no_fly, double ds, Mode mode);

struct Grid {
  double ds = 0.0, dn = 0.0;
  double sx = 0.0, sy = 0.0, theta_deg = 0.0;
  double cos_t = 1.0, sin_t = 0.0;
  double x0 = 0.0, y0 = 0.0;  ///< q-frame lower-left corner of mega-cell (0,0)
  int rows = 0, cols = 0;
  double px0 = 0.0, px1 = 0.0, py0 = 0.0, py1 = 0.0;  ///< q-frame bounding box of the free space
  int fr0 = 0, fr1 = -1, fc0 = 0, fc1 = -1;           ///< rows/cols spanned by the free cells
  std::vector<std::uint8_t> free;                     ///< rows*cols, row-major
  /// bit 0: linked to the right neighbour (c+1), bit 1: linked to the upper neighbour (r+1).
  /// A link exists when both cells are free and the path segments joining them are clear.
  std::vector<std::uint8_t> link;
  int free_cells = 0;
  /// Share of the free area a w = 1.5 ds footprint swept along the STC path would cover, sampled
  /// on Prepared::estimate_samples^2 points per mega-cell (coverage_proxy gives finer versions).
  double coverage_estimate = 0.0;

  [[nodiscard]] int idx(int r, int c) const { return r * cols + c; }
  /// Whether (r, c) is a cell of the grid and free.
  [[nodiscard]] bool free_at(int r, int c) const {
    return r >= 0 && c >= 0 && r < rows && c < cols && free[idx(r, c)];
  }
  [[nodiscard]] Point q_to_local(double qx, double qy) const {
    const double x = qx - sx, y = qy - sy;
    return {cos_t * x - sin_t * y, sin_t * x + cos_t * y};
  }
  [[nodiscard]] Point local_to_q(Point p) const {
    return {cos_t * p.x() + sin_t * p.y() + sx, -sin_t * p.x() + cos_t * p.y() + sy};
  }
  /// Local position of sub-cell centre (i, j).
  [[nodiscard]] Point sub_centre(int i, int j) const {
    return q_to_local(x0 + (i + 0.5) * ds, y0 + (j + 0.5) * ds);
  }
  /// Local position of mega-cell (r, c)'s centre.
  [[nodiscard]] Point cell_centre(int r, int c) const {
    return q_to_local(x0 + (c + 0.5) * dn, y0 + (r + 0.5) * dn);
  }
  /// Neighbours of cell k reachable through links (up to 4), returns count.
  int neighbours(int k, std::array<int, 4>& out) const;
};

/// Rasterises the prepared free space for placement (sx, sy, theta): classification row by row
/// (scanline crossings), then blocking of cells/links whose path segments cross an obstacle edge.
Grid rasterize(const Prepared& prep, double sx, double sy, double theta_deg);

struct Score {
  double J = 0.0, J1 = 0.0, J2 = 0.0, J3 = 0.0;
  int free_cells = 0;
  int components = 0;
  double coverage = 0.0;  ///< coverage_proxy at a coarse lattice (ds/4), when weighted
  double key = 0.0;       ///< what the search maximises: J + coverage_weight * coverage - length_weight * J1
};

struct Weights {
  double a = 0.68, b = 0.32, c = 0.25, disconnected_penalty = 0.5;
  /// Weight of the swept-footprint coverage estimate added to J in the search (0: the paper's J).
  double coverage_weight = 9.0;
  /// Weight of J1 (the path length, proportional to the free cells) subtracted in the search.
  double length_weight = 3.6;
};

/// Placement index of eq. 7-10 for a rasterised grid. J1 = s*dn^2/Ap; J2 = Ap / area of the free
/// space's bounding box snapped outward to the grid lines; J3 (eq. 10) measures how unequal the
/// margins are between the free space's bounding box and the extent of the free cells (so that the
/// outermost lanes sit equally far from the borders). The penalty applies when the free grid has
/// more connected components than the free space has polygons.
Score score(const Prepared& prep, const Grid& g, const Weights& w = {});

/// Share of the free area within Chebyshev distance 0.75 ds of a path sub-cell centre: what a
/// square footprint of width w = 1.5 ds swept along the STC path covers (legs join neighbouring
/// sub-cell centres). Sampled on `samples_per_cell`^2 points per mega-cell (<= 16), aligned with the grid.
double coverage_proxy(const Prepared& prep, const Grid& g, int samples_per_cell = 16);

/// Connected components of the free cells over links: label per cell (-1 blocked), returns count.
int components(const Grid& g, std::vector<int>& label);

}  // namespace uavcover::grid
