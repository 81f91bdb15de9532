// The corridor and pattern blocks (docs/patterns.md).
#include "mission/pattern.hpp"

#include <fmt/format.h>

#include <cmath>
#include <set>

#include "geodesy/local_frame.hpp"
#include "uavcover/error.hpp"

namespace uavcover::mission {

namespace {

using nlohmann::json;

void known_fields(const json& j, const std::set<std::string>& known, const std::string& prefix) {
  for (auto it = j.begin(); it != j.end(); ++it)
    if (!known.contains(it.key()))
      throw InputError(prefix + it.key(), "unknown field (check the spelling; see docs/patterns.md)");
}

double finite_number(const json& j, const std::string& field) {
  if (!j.is_number()) throw InputError(field, std::string("expected a number, got ") + j.type_name());
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw InputError(field, "must be finite");
  return v;
}

bool boolean(const json& j, const std::string& field) {
  if (!j.is_boolean()) throw InputError(field, "must be true or false");
  return j.get<bool>();
}

constexpr double kMaxWidthM = 5000.0;  ///< wider than this is an area, not a corridor

}  // namespace

Corridor parse_corridor(const json& j) {
  if (!j.is_object())
    throw InputError("corridor", "expected an object {\"line\": LineString, \"width_m\": ...}");
  known_fields(j, {"line", "width_m"}, "corridor.");
  if (!j.contains("line")) throw InputError("corridor.line", "missing");
  if (!j.contains("width_m")) throw InputError("corridor.width_m", "missing");
  Corridor c;
  c.width_m = finite_number(j["width_m"], "corridor.width_m");
  if (!(c.width_m > 0.0) || c.width_m > kMaxWidthM)
    throw InputError("corridor.width_m",
                     fmt::format("must be > 0 and at most {} m, got {}", kMaxWidthM, j["width_m"].dump()));
  const json& line = j["line"];
  if (!line.is_object() || !line.contains("type") || line["type"] != "LineString")
    throw InputError("corridor.line.type", "must be \"LineString\"");
  known_fields(line, {"type", "coordinates"}, "corridor.line.");
  if (!line.contains("coordinates") || !line["coordinates"].is_array())
    throw InputError("corridor.line.coordinates", "expected an array of positions [longitude, latitude]");
  const json& co = line["coordinates"];
  if (co.size() > 10000) throw InputError("corridor.line.coordinates", "more than 10000 vertices");
  for (std::size_t i = 0; i < co.size(); ++i) {
    const std::string f = "corridor.line.coordinates[" + std::to_string(i) + "]";
    if (!co[i].is_array() || co[i].size() < 2 || co[i].size() > 3)
      throw InputError(f, "expected a position [longitude, latitude]");
    const double lon = finite_number(co[i][0], f + "[0]");
    const double lat = finite_number(co[i][1], f + "[1]");
    if (lon < -180 || lon > 180) throw InputError(f, "longitude " + co[i][0].dump() + " is out of range");
    if (lat < -85 || lat > 85)
      throw InputError(f, "latitude " + co[i][1].dump() + " is out of range [-85, 85]");
    const LonLat p{lon, lat};
    if (!c.line.empty() && std::abs(c.line.back().lon - lon) < 1e-12 &&
        std::abs(c.line.back().lat - lat) < 1e-12)
      continue;  // a repeated vertex
    c.line.push_back(p);
  }
  if (c.line.size() < 2)
    throw InputError("corridor.line.coordinates", "needs at least two distinct positions");
  return c;
}

GeoPolygon corridor_polygon(const Corridor& c) {
  LonLat mean{0, 0};
  for (const auto& p : c.line)
    mean.lon += p.lon / static_cast<double>(c.line.size()),
        mean.lat += p.lat / static_cast<double>(c.line.size());
  const geodesy::LocalFrame frame(mean);
  bg::model::linestring<Point> ls;
  for (const auto& p : c.line) ls.push_back(frame.to_local(p));
  for (std::size_t i = 1; i < ls.size(); ++i)
    if (bg::distance(ls[i - 1], ls[i]) < 0.01)
      throw InputError("corridor.line.coordinates[" + std::to_string(i) + "]",
                       "lies within 1 cm of the previous vertex");
  bg::strategy::buffer::distance_symmetric<double> distance(0.5 * c.width_m);
  bg::strategy::buffer::side_straight side;
  bg::strategy::buffer::join_miter join(2.0);  // mitres up to twice the half-width, bevelled beyond
  bg::strategy::buffer::end_flat end;
  bg::strategy::buffer::point_square point;
  MultiPolygon buf;
  bg::buffer(ls, buf, distance, side, join, end, point);
  if (buf.size() != 1)
    throw InputError("corridor.line",
                     fmt::format("its buffer of {} m is {} polygons, not one", c.width_m, buf.size()));
  GeoPolygon out;
  auto ring_of = [&](const auto& r) {
    GeoRing g;
    for (const auto& p : r) g.push_back(frame.to_wgs84(p));
    return g;
  };
  out.push_back(ring_of(buf.front().outer()));
  for (const auto& in : buf.front().inners()) out.push_back(ring_of(in));
  return out;
}

Oblique parse_oblique(const json& j) {
  if (!j.is_object())
    throw InputError("pattern.oblique",
                     "expected an object {\"gimbal_pitch_deg\": -45, \"directions\": 4, \"nadir\": true}");
  known_fields(j, {"gimbal_pitch_deg", "directions", "nadir"}, "pattern.oblique.");
  Oblique o;
  if (j.contains("gimbal_pitch_deg")) {
    o.gimbal_pitch_deg = finite_number(j["gimbal_pitch_deg"], "pattern.oblique.gimbal_pitch_deg");
    if (o.gimbal_pitch_deg < kMinObliquePitchDeg || o.gimbal_pitch_deg > kMaxObliquePitchDeg)
      throw InputError("pattern.oblique.gimbal_pitch_deg",
                       fmt::format("must be in [{}, {}] degrees (-90 is nadir: use nadir: true), got {}",
                                   kMinObliquePitchDeg, kMaxObliquePitchDeg, j["gimbal_pitch_deg"].dump()));
  }
  if (j.contains("directions")) {
    const json& d = j["directions"];
    if (!d.is_number_integer() || d.get<long long>() < 1 || d.get<long long>() > kMaxObliqueDirections)
      throw InputError(
          "pattern.oblique.directions",
          fmt::format("must be a whole number from 1 to {}, got {}", kMaxObliqueDirections, d.dump()));
    o.directions = static_cast<int>(d.get<long long>());
  }
  if (j.contains("nadir")) o.nadir = boolean(j["nadir"], "pattern.oblique.nadir");
  return o;
}

Pattern parse_pattern(const json& j) {
  if (!j.is_object()) throw InputError("pattern", "expected an object");
  known_fields(
      j, {"crosshatch", "turnaround_m", "entry", "alternate_transects", "capture_in_turnaround", "oblique"},
      "pattern.");
  Pattern p;
  if (j.contains("oblique")) p.oblique = parse_oblique(j["oblique"]);
  if (j.contains("crosshatch")) p.crosshatch = boolean(j["crosshatch"], "pattern.crosshatch");
  if (j.contains("turnaround_m")) {
    p.turnaround_m = finite_number(j["turnaround_m"], "pattern.turnaround_m");
    if (p.turnaround_m < 0 || p.turnaround_m > 500)
      throw InputError("pattern.turnaround_m", "must be in [0, 500] m, got " + j["turnaround_m"].dump());
  }
  if (j.contains("entry")) {
    if (!j["entry"].is_string()) throw InputError("pattern.entry", "must be a string");
    p.entry = j["entry"].get<std::string>();
    if (p.entry != "auto" && p.entry != "nw" && p.entry != "ne" && p.entry != "sw" && p.entry != "se")
      throw InputError("pattern.entry", "must be one of auto, nw, ne, sw, se, got \"" + p.entry + "\"");
  }
  if (j.contains("alternate_transects"))
    p.alternate_transects = boolean(j["alternate_transects"], "pattern.alternate_transects");
  if (j.contains("capture_in_turnaround"))
    p.capture_in_turnaround = boolean(j["capture_in_turnaround"], "pattern.capture_in_turnaround");
  return p;
}

json corridor_json(const Corridor& c) {
  json co = json::array();
  for (const auto& p : c.line) co.push_back({p.lon, p.lat});
  return {{"line", {{"type", "LineString"}, {"coordinates", std::move(co)}}}, {"width_m", c.width_m}};
}

json pattern_json(const Pattern& p) {
  json j = {{"crosshatch", p.crosshatch},
            {"turnaround_m", p.turnaround_m},
            {"entry", p.entry},
            {"alternate_transects", p.alternate_transects},
            {"capture_in_turnaround", p.capture_in_turnaround}};
  if (p.oblique)
    j["oblique"] = {{"gimbal_pitch_deg", p.oblique->gimbal_pitch_deg},
                    {"directions", p.oblique->directions},
                    {"nadir", p.oblique->nadir}};
  return j;
}

}  // namespace uavcover::mission
