// A mission's geometry in the local ENU frame, shared by the facade and the evaluation.
#pragma once

#include <random>

#include "geodesy/local_frame.hpp"
#include "uavcover/mission.hpp"

namespace uavcover::engine {

struct LocalMission {
  geodesy::LocalFrame frame;
  MultiPolygon area;    ///< union of the area polygons (holes kept)
  MultiPolygon no_fly;  ///< union of the no-fly zones
  MultiPolygon free;    ///< area - no-fly zones
};

/// Builds the local geometry, origin at the area's centroid.
LocalMission to_local(const Mission& mission);

/// Local polygons back in WGS84, rings in GeoJSON's order (RFC 7946: counter-clockwise outer rings,
/// clockwise holes; Boost's are the reverse).
std::vector<GeoPolygon> to_wgs84(const MultiPolygon& mp, const geodesy::LocalFrame& frame);

/// Uniform random point inside `free` (rejection sampling on the bounding box).
Point random_free_point(const MultiPolygon& free, std::mt19937_64& rng);

}  // namespace uavcover::engine
