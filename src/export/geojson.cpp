#include "export/export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "codec/plan_codec.hpp"
#include "export/support.hpp"
#include "uavcover/error.hpp"

namespace uavcover::exporting {

using namespace waypoints;  // the waypoint model the formats write
using nlohmann::json;

namespace {

// signed area of a lon/lat ring (shoelace), positive when counter-clockwise
double signed_area(const json& ring) {
  double s = 0;
  for (std::size_t i = 0; i + 1 < ring.size(); ++i)
    s += ring[i][0].get<double>() * ring[i + 1][1].get<double>() -
         ring[i + 1][0].get<double>() * ring[i][1].get<double>();
  return s / 2.0;
}

void check_position(const json& p, const std::string& where, std::vector<std::string>& problems) {
  if (!p.is_array() || p.size() < 2 || p.size() > 3 || !p[0].is_number() || !p[1].is_number()) {
    problems.push_back(where + ": a position must be [lon, lat] or [lon, lat, alt]");
    return;
  }
  const double lon = p[0].get<double>(), lat = p[1].get<double>();
  if (!(lon >= -180 && lon <= 180)) problems.push_back(where + ": longitude out of range");
  if (!(lat >= -90 && lat <= 90)) problems.push_back(where + ": latitude out of range");
}

void check_geometry(const json& g, const std::string& where, std::vector<std::string>& problems) {
  if (!g.is_object() || !g.contains("type") || !g.contains("coordinates")) {
    problems.push_back(where + ": geometry needs type and coordinates");
    return;
  }
  const std::string type = g["type"].get<std::string>();
  const json& c = g["coordinates"];
  auto check_polygon = [&](const json& rings, const std::string& w) {
    if (!rings.is_array() || rings.empty()) {
      problems.push_back(w + ": a polygon needs at least one ring");
      return;
    }
    for (std::size_t r = 0; r < rings.size(); ++r) {
      const json& ring = rings[r];
      const std::string rw = fmt::format("{} ring {}", w, r);
      if (!ring.is_array() || ring.size() < 4) {
        problems.push_back(rw + ": a linear ring needs at least 4 positions");
        continue;
      }
      std::size_t bad = problems.size();
      for (std::size_t k = 0; k < ring.size(); ++k)
        check_position(ring[k], fmt::format("{} position {}", rw, k), problems);
      if (problems.size() != bad) continue;
      if (ring.front()[0] != ring.back()[0] || ring.front()[1] != ring.back()[1])
        problems.push_back(rw + ": ring is not closed");
      const double a = signed_area(ring);
      if (r == 0 && !(a > 0)) problems.push_back(rw + ": exterior ring is not counter-clockwise");
      if (r > 0 && !(a < 0)) problems.push_back(rw + ": hole is not clockwise");
    }
  };
  if (type == "Polygon") {
    check_polygon(c, where);
  } else if (type == "MultiPolygon") {
    for (std::size_t i = 0; i < c.size(); ++i) check_polygon(c[i], fmt::format("{} polygon {}", where, i));
  } else if (type == "LineString") {
    if (!c.is_array() || c.size() < 2)
      problems.push_back(where + ": a LineString needs at least 2 positions");
    else
      for (std::size_t k = 0; k < c.size(); ++k)
        check_position(c[k], fmt::format("{} position {}", where, k), problems);
  } else if (type == "MultiLineString") {
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (!c[i].is_array() || c[i].size() < 2)
        problems.push_back(where + ": a LineString needs at least 2 positions");
      else
        for (std::size_t k = 0; k < c[i].size(); ++k)
          check_position(c[i][k], fmt::format("{} line {} position {}", where, i, k), problems);
    }
  } else if (type == "Point") {
    check_position(c, where, problems);
  } else if (type == "MultiPoint") {
    for (std::size_t k = 0; k < c.size(); ++k)
      check_position(c[k], fmt::format("{} position {}", where, k), problems);
  } else {
    problems.push_back(where + ": unknown geometry type '" + type + "'");
  }
}
}  // namespace

json uav_geojson(const Plan& plan, std::size_t index) {
  if (index >= plan.uavs.size())
    throw std::out_of_range("uav_geojson: no UAV with index " + std::to_string(index));
  return codec::paths_geojson(plan, index);
}

std::vector<std::string> validate_geojson(const json& doc) {
  std::vector<std::string> problems;
  if (!doc.is_object() || doc.value("type", "") != "FeatureCollection" || !doc.contains("features") ||
      !doc["features"].is_array()) {
    problems.emplace_back("not a FeatureCollection with a features array");
    return problems;
  }
  const json& features = doc["features"];
  for (std::size_t i = 0; i < features.size(); ++i) {
    const json& f = features[i];
    const std::string where = fmt::format("features[{}]", i);
    if (!f.is_object() || f.value("type", "") != "Feature" || !f.contains("geometry")) {
      problems.push_back(where + ": not a Feature with a geometry");
      continue;
    }
    if (f["geometry"].is_null()) continue;
    check_geometry(f["geometry"], where + ".geometry", problems);
  }
  return problems;
}

}  // namespace uavcover::exporting
