// JSON form of the normalised mission (used by plan.json and the store).
#pragma once

#include <nlohmann/json.hpp>

#include "uavcover/mission.hpp"

namespace uavcover::mission {

nlohmann::json to_json(const Mission& m);
nlohmann::json geo_polygon_json(const GeoPolygon& poly);

/// Normalise a ring: drop repeated consecutive vertices, close it, orient it (ccw = true for
/// counter-clockwise). Returns the number of distinct vertices.
std::size_t normalise_ring(GeoRing& ring, bool ccw);

}  // namespace uavcover::mission
