// Public geometry types. Local coordinates are metres in an East-North-Up frame
// whose origin is the area's centroid (see uavcover::LocalFrame).
#pragma once

#include <boost/geometry.hpp>
#include <boost/geometry/geometries/linestring.hpp>
#include <boost/geometry/geometries/multi_polygon.hpp>
#include <boost/geometry/geometries/point_xy.hpp>
#include <boost/geometry/geometries/polygon.hpp>
#include <vector>

namespace uavcover {

namespace bg = boost::geometry;

/// A WGS84 position in degrees (GeoJSON order: longitude first).
struct LonLat {
  double lon = 0.0;
  double lat = 0.0;
  friend bool operator==(const LonLat&, const LonLat&) = default;
};

/// A point in the local ENU frame, metres (x = east, y = north).
using Point = bg::model::d2::point_xy<double>;
/// Polygon in local metres: clockwise outer ring, counter-clockwise holes, closed
/// (Boost.Geometry defaults). Always bg::correct()ed by the code that builds it.
using Polygon = bg::model::polygon<Point>;
using MultiPolygon = bg::model::multi_polygon<Polygon>;
using Polyline = bg::model::linestring<Point>;

/// WGS84 polygon as GeoJSON rings: ring 0 outer, others holes; each ring closed.
using GeoRing = std::vector<LonLat>;
using GeoPolygon = std::vector<GeoRing>;

}  // namespace uavcover
