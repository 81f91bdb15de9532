// Polygon overlays on integer millimetres. Boost.Geometry 1.74's overlay on doubles without its
// rescaling (BOOST_GEOMETRY_NO_ROBUSTNESS, which the core is built with) loses whole polygons when
// rectangles overlap along collinear edges (a union of 8 footprint rectangles came out empty on the olive
// grove) and leaves rings crossing themselves when thin zones cut a polygon at a slant (1 m hedges at
// 45 degrees across DARP's cells). On integer coordinates its predicates are exact (its side tests run
// on doubles, exact while coordinate products stay under 2^53: fields up to ~90 km across). Its
// intersection points are truncated to whole millimetres, not rounded (segment start + integer
// division): a clip shifts each cut edge by under 1 mm, and two clips of polygons that share an edge may
// round a crossing of it differently (slivers under 1 mm wide).
#pragma once

#include <cstdint>

#include "uavcover/geometry.hpp"

namespace uavcover::geometry {

using MmPoint = bg::model::d2::point_xy<std::int64_t>;
using MmPolygon = bg::model::polygon<MmPoint>;
using MmMultiPolygon = bg::model::multi_polygon<MmPolygon>;
inline constexpr double kMmPerM = 1000.0;

/// The point rounded to the nearest millimetre, and back to metres.
MmPoint to_mm(Point p);
Point from_mm(MmPoint p);
/// The polygons with every vertex rounded to millimetres (corrected), and back to metres (corrected).
MmMultiPolygon to_mm(const MultiPolygon& mp);
MultiPolygon from_mm(const MmMultiPolygon& mp);

/// a ∩ b, computed on the polygons rounded to millimetres (vertices of the result are whole millimetres).
MultiPolygon intersection_mm(const MultiPolygon& a, const MultiPolygon& b);

}  // namespace uavcover::geometry
