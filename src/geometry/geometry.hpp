// Polygon operations on the local frame (Boost.Geometry): conversion, free space,
// containment checks with tolerance, and obstacle-avoiding routes.
#pragma once

#include <vector>

#include "geodesy/local_frame.hpp"
#include "uavcover/geometry.hpp"

namespace uavcover::geometry {

Polygon to_local(const GeoPolygon& poly, const geodesy::LocalFrame& frame);
MultiPolygon to_local(const std::vector<GeoPolygon>& polys, const geodesy::LocalFrame& frame);

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

/// Shortest polyline from a to b that does not enter `obstacles` (visibility graph over the
/// obstacles' vertices offset outward by `clearance`). Returns {a, b} when the straight line
/// is clear, and the straight line when no route exists (a or b inside an obstacle).
std::vector<Point> route_around(const MultiPolygon& obstacles, Point a, Point b, double clearance = 2.0);

/// Polyline length in metres.
double length(const std::vector<Point>& pts);

/// Number of interior vertices where the direction changes by more than `angle_tol_deg`.
int count_turns(const std::vector<Point>& pts, double angle_tol_deg = 1.0);

}  // namespace uavcover::geometry
