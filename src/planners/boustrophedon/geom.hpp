// Geometry helpers of the boustrophedon planner: the rotated sweep frame, x-monotone chains and a
// segment index for "where does this segment first hit that boundary" queries.
#pragma once

#include <boost/geometry/index/rtree.hpp>
#include <cmath>
#include <optional>
#include <vector>

#include "uavcover/geometry.hpp"

namespace uavcover::planners::boustro {

using Ring = Polygon::ring_type;
using Box = bg::model::box<Point>;

/// The frame of a sweep direction: legs run along the frame's Y axis, i.e. along lines X = const.
/// `angle` is the legs' direction in radians, counter-clockwise from east. A rotation (no mirror),
/// so ring orientation is kept.
struct Frame {
  double c = 1.0, s = 0.0;
  Frame() = default;
  explicit Frame(double angle) : c(std::cos(angle)), s(std::sin(angle)) {}
  [[nodiscard]] Point to(Point p) const { return {-s * p.x() + c * p.y(), -c * p.x() - s * p.y()}; }
  [[nodiscard]] Point from(Point q) const { return {-s * q.x() - c * q.y(), c * q.x() - s * q.y()}; }
  /// World direction of the frame's +Y axis.
  [[nodiscard]] Point up() const { return {-c, -s}; }
};

template <typename Geometry>
Geometry to_frame(const Geometry& g, const Frame& f);

template <>
inline Ring to_frame(const Ring& r, const Frame& f) {
  Ring out;
  out.reserve(r.size());
  for (const auto& p : r) out.push_back(f.to(p));
  return out;
}
template <>
inline Polygon to_frame(const Polygon& p, const Frame& f) {
  Polygon out;
  out.outer() = to_frame(p.outer(), f);
  for (const auto& in : p.inners()) out.inners().push_back(to_frame(in, f));
  return out;
}
template <>
inline MultiPolygon to_frame(const MultiPolygon& m, const Frame& f) {
  MultiPolygon out;
  for (const auto& p : m) out.push_back(to_frame(p, f));
  return out;
}

/// Back to the world: the inverse of to_frame.
inline Ring from_frame(const Ring& r, const Frame& f) {
  Ring out;
  out.reserve(r.size());
  for (const auto& p : r) out.push_back(f.from(p));
  return out;
}

/// A polygon cut by every line X = const in one interval: its lower and upper boundary as functions
/// of X, each a polyline with non-decreasing X from the leftmost to the rightmost point.
struct Monotone {
  std::vector<Point> lower, upper;
  [[nodiscard]] double xmin() const { return lower.front().x(); }
  [[nodiscard]] double xmax() const { return lower.back().x(); }
};

/// Y of a chain (non-decreasing X) at x, clamped to its ends.
double chain_at(const std::vector<Point>& chain, double x);

/// The lower and upper chains of a simple ring that is monotone along X (up to `tol` of X
/// wobble), or nothing when it is not.
std::optional<Monotone> monotone_chains(const Ring& ring, double tol);

/// Polygon (world, corrected) of a monotone cell given in `frame`.
Polygon monotone_polygon(const Monotone& m, const Frame& frame);
/// The same polygon in the frame's own coordinates.
Polygon monotone_polygon(const Monotone& m);
/// Back to the world.
Polygon from_frame(const Polygon& p, const Frame& f);
MultiPolygon from_frame(const MultiPolygon& m, const Frame& f);

/// Removes consecutive vertices closer than `tol` (Boost's overlays fail on near-repeated ones) and
/// rings left with fewer than three corners.
void remove_near_duplicates(MultiPolygon& m, double tol = 1e-7);

/// Boundary edges of polygons, indexed for first-hit queries along segments.
class EdgeIndex {
 public:
  void add(const MultiPolygon& polys);
  void add(const Ring& ring);
  [[nodiscard]] bool empty() const { return tree_.empty(); }
  /// Smallest t in [t_min, 1] where segment a + t (b - a) meets an indexed edge, or nothing.
  [[nodiscard]] std::optional<double> first_hit(Point a, Point b, double t_min) const;

 private:
  using Seg = bg::model::segment<Point>;
  using Value = std::pair<Box, std::size_t>;
  std::vector<Seg> segs_;
  bg::index::rtree<Value, bg::index::rstar<16>> tree_;
};

inline double dist(Point a, Point b) { return std::hypot(a.x() - b.x(), a.y() - b.y()); }

}  // namespace uavcover::planners::boustro
