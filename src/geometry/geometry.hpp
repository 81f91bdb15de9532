// Polygon operations on the local frame (Boost.Geometry): conversion, free space,
// containment checks with tolerance, and obstacle-avoiding routes.
#pragma once

#include <memory>
#include <vector>

#include "geodesy/local_frame.hpp"
#include "uavcover/geometry.hpp"

namespace uavcover::geometry {

/// Edges are straight in longitude/latitude in GeoJSON but straight in the local plane here. Where the two
/// differ by more than this (long edges, high latitudes), conversions insert vertices.
inline constexpr double kDensifyTolM = 0.5;

/// Local polygon of a WGS84 one; an edge whose lon/lat midpoint lies more than kDensifyTolM from its local
/// chord gets that midpoint as a vertex (recursively).
Polygon to_local(const GeoPolygon& poly, const geodesy::LocalFrame& frame);
/// WGS84 positions of a local polyline; a segment whose local midpoint lies more than kDensifyTolM from
/// the lon/lat chord's midpoint gets it as a vertex (recursively). `dense_local`: the local points.
std::vector<LonLat> to_wgs84_dense(const std::vector<Point>& local, const geodesy::LocalFrame& frame,
                                   std::vector<Point>* dense_local = nullptr);
MultiPolygon to_local(const std::vector<GeoPolygon>& polys, const geodesy::LocalFrame& frame);

/// The axis-aligned rectangle [x0, x1] x [y0, y1] as a corrected polygon.
Polygon box_polygon(double x0, double y0, double x1, double y1);

/// Union of the given polygons (each corrected); empty input gives an empty set.
MultiPolygon unite(const MultiPolygon& polys);

/// area minus no-fly zones.
MultiPolygon free_space(const MultiPolygon& area, const MultiPolygon& no_fly);

/// Distance from p to the set (0 inside).
double distance(const MultiPolygon& set, Point p);

/// True when segment a-b stays within `set` up to `tol` metres.
bool segment_within(const MultiPolygon& set, Point a, Point b, double tol);

/// True when segment a-b enters the interior of any of the `obstacles` deeper than `tol`.
bool segment_enters(const MultiPolygon& obstacles, Point a, Point b, double tol);
/// The same for one polygon.
bool segment_enters(const Polygon& obstacle, Point a, Point b, double tol);

/// Shortest polyline from a to b that does not enter `obstacles` (visibility graph over the
/// obstacles' vertices offset outward by `clearance`). Returns {a, b} when the straight line
/// is clear, and the straight line when no route exists (a or b inside an obstacle).
std::vector<Point> route_around(const MultiPolygon& obstacles, Point a, Point b, double clearance = 2.0);

/// Routes transit legs around a fixed set of obstacles. Built once per plan: it keeps an R-tree of the
/// obstacles' boxes and every obstacle's visibility-graph nodes (its vertices pushed outward by
/// `clearance`). A route is searched over the obstacles in the way only: those the straight line
/// enters, then those that the best route among them enters, until the route is clear of all. Up to
/// kFullGraph obstacles, the graph holds all of them from the start (the shortest route of the full
/// visibility graph).
class Router {
 public:
  static constexpr std::size_t kFullGraph = 64;

  explicit Router(MultiPolygon obstacles, double clearance = 2.0);
  ~Router();
  Router(const Router&) = delete;
  Router& operator=(const Router&) = delete;

  /// Same contract as route_around().
  std::vector<Point> route(Point a, Point b) const;
  /// True when segment a-b enters no obstacle (touching is fine).
  bool clear(Point a, Point b) const;

 private:
  struct Index;
  bool clear_of(Point a, Point b, const std::vector<char>* only, std::vector<std::size_t>* entered) const;
  MultiPolygon obstacles_;
  std::vector<std::vector<Point>> nodes_;  // per obstacle
  std::unique_ptr<Index> index_;
};

/// Polyline length in metres.
double length(const std::vector<Point>& pts);

/// Number of interior vertices where the direction changes by more than `angle_tol_deg`.
int count_turns(const std::vector<Point>& pts, double angle_tol_deg = 1.0);

}  // namespace uavcover::geometry
