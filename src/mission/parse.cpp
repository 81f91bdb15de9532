// Mission file parsing and validation: uavcover v1 (GeoJSON conventions) and the
// mCPP-optimized-DARP input format. Every refusal is an InputError naming the field.
#include <cmath>
#include <limits>
#include <numbers>
#include <set>

#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "json/strict.hpp"
#include "mission/mission_json.hpp"
#include "uavcover/error.hpp"
#include "uavcover/mission.hpp"

namespace uavcover {

namespace {

using nlohmann::json;

std::string idx(const std::string& base, std::size_t i) { return base + "[" + std::to_string(i) + "]"; }

const char* type_name(const json& j) { return j.type_name(); }

// The "type" member of a GeoJSON object, or "" when it is missing or not a string.
std::string geojson_type(const json& j) {
  if (!j.is_object()) return "";
  const auto it = j.find("type");
  return it != j.end() && it->is_string() ? it->get<std::string>() : "";
}

double number(const json& j, const std::string& field) {
  if (!j.is_number()) throw InputError(field, std::string("expected a number, got ") + type_name(j));
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw InputError(field, "must be a finite number");
  return v;
}

double positive(const json& j, const std::string& field) {
  const double v = number(j, field);
  if (v <= 0) throw InputError(field, "must be positive, got " + j.dump());
  return v;
}

double in_range(const json& j, const std::string& field, double lo, double hi, bool hi_open = false) {
  const double v = number(j, field);
  if (v < lo || v > hi || (hi_open && v >= hi))
    throw InputError(field, "must be in [" + json(lo).dump() + ", " + json(hi).dump() +
                                (hi_open ? ")" : "]") + ", got " + j.dump());
  return v;
}

LonLat position(const json& j, const std::string& field) {
  if (!j.is_array() || j.size() < 2 || j.size() > 3)
    throw InputError(field, "expected a position [longitude, latitude]");
  const double lon = number(j[0], field + "[0]");
  const double lat = number(j[1], field + "[1]");
  if (lon < -180 || lon > 180)
    throw InputError(field, "longitude " + j[0].dump() + " is out of range [-180, 180]");
  if (lat < -90 || lat > 90)
    throw InputError(field, "latitude " + j[1].dump() + " is out of range [-90, 90]");
  return {lon, lat};
}

LonLat latlong_object(const json& j, const std::string& field) {
  if (!j.is_object() || !j.contains("lat") || !(j.contains("long") || j.contains("lng") || j.contains("lon")))
    throw InputError(field, "expected an object {\"lat\": ..., \"long\": ...}");
  const json& jl = j.contains("long") ? j["long"] : (j.contains("lng") ? j["lng"] : j["lon"]);
  return position(json::array({jl, j["lat"]}), field);
}

void check_antimeridian(const GeoRing& ring, const std::string& field) {
  for (std::size_t i = 1; i < ring.size(); ++i)
    if (std::fabs(ring[i].lon - ring[i - 1].lon) > 180.0)
      throw InputError(field, "the ring crosses the antimeridian (longitude jumps from " +
                                  json(ring[i - 1].lon).dump() + " to " + json(ring[i].lon).dump() +
                                  "); split the area into polygons on either side of 180°");
}

GeoRing ring_of(const json& j, const std::string& field) {
  if (!j.is_array())
    throw InputError(field, std::string("expected an array of positions, got ") + type_name(j));
  GeoRing ring;
  for (std::size_t i = 0; i < j.size(); ++i) ring.push_back(position(j[i], idx(field, i)));
  return ring;
}

// Parses a GeoJSON Polygon's coordinates.
GeoPolygon polygon_coords(const json& j, const std::string& field) {
  if (!j.is_array() || j.empty()) throw InputError(field, "expected an array of linear rings");
  GeoPolygon poly;
  for (std::size_t r = 0; r < j.size(); ++r) poly.push_back(ring_of(j[r], idx(field, r)));
  return poly;
}

// Accepts a Polygon or MultiPolygon geometry (or a Feature wrapping one).
std::vector<GeoPolygon> polygons_of(const json& j, const std::string& field) {
  if (!j.is_object())
    throw InputError(field,
                     std::string("expected a GeoJSON Polygon or MultiPolygon object, got ") + type_name(j));
  if (geojson_type(j) == "Feature") {
    if (!j.contains("geometry")) throw InputError(field + ".geometry", "missing");
    return polygons_of(j["geometry"], field + ".geometry");
  }
  if (!j.contains("type") || !j["type"].is_string()) throw InputError(field + ".type", "missing");
  const std::string type = j["type"];
  if (!j.contains("coordinates")) throw InputError(field + ".coordinates", "missing");
  const json& c = j["coordinates"];
  if (type == "Polygon") return {polygon_coords(c, field + ".coordinates")};
  if (type == "MultiPolygon") {
    if (!c.is_array() || c.empty()) throw InputError(field + ".coordinates", "expected an array of polygons");
    std::vector<GeoPolygon> out;
    for (std::size_t i = 0; i < c.size(); ++i)
      out.push_back(polygon_coords(c[i], idx(field + ".coordinates", i)));
    return out;
  }
  throw InputError(field + ".type", "expected \"Polygon\" or \"MultiPolygon\", got \"" + type + "\"");
}

struct NamedPolygon {
  GeoPolygon poly;
  std::string field;  // JSON path of its coordinates
};

// Normalises every ring and checks it (>= 3 distinct vertices, no antimeridian crossing).
void normalise_polygon(NamedPolygon& np) {
  for (std::size_t r = 0; r < np.poly.size(); ++r) {
    const std::string f = idx(np.field, r);
    check_antimeridian(np.poly[r], f);
    if (mission::normalise_ring(np.poly[r], r == 0) < 3)
      throw InputError(f, "a ring needs at least 3 distinct vertices");
  }
}

void check_valid(const NamedPolygon& np, const geodesy::LocalFrame& frame) {
  for (std::size_t r = 0; r < np.poly.size(); ++r) {
    Polygon ring_only = geometry::to_local(GeoPolygon{np.poly[r]}, frame);
    if (bg::intersects(ring_only.outer())) throw InputError(idx(np.field, r), "the ring intersects itself");
    if (std::fabs(bg::area(ring_only)) < 1e-6) throw InputError(idx(np.field, r), "the ring has no area");
  }
  const Polygon p = geometry::to_local(np.poly, frame);
  bg::validity_failure_type failure{};
  if (!bg::is_valid(p, failure)) {
    std::string why = "invalid polygon (" + std::string(bg::validity_failure_type_message(failure)) + ")";
    if (failure == bg::failure_interior_rings_outside) why = "a hole lies outside its outer ring";
    if (failure == bg::failure_self_intersections) why = "rings of the polygon cross each other";
    if (failure == bg::failure_nested_interior_rings) why = "holes are nested inside each other";
    throw InputError(np.field, why);
  }
}

std::string str(const json& j, const std::string& field) {
  if (!j.is_string()) throw InputError(field, std::string("expected a string, got ") + type_name(j));
  return j.get<std::string>();
}

void reject_unknown(const json& obj, const std::set<std::string>& known, const std::string& prefix) {
  for (auto it = obj.begin(); it != obj.end(); ++it)
    if (!known.contains(it.key()))
      throw InputError(prefix + it.key(), "unknown field (check the spelling; see docs/mission-format.md)");
}

struct Raw {
  std::string name = "mission";
  std::vector<NamedPolygon> area;
  std::vector<NamedPolygon> nfz;
  std::optional<double> spacing;
  std::optional<Camera> camera;
  std::optional<double> altitude;
  std::vector<Uav> uavs;
  std::vector<std::optional<double>> shares;
  std::size_t uav_count = 0;
  Mode mode = Mode::Strict;
  std::string planner = "darp";
  std::uint64_t seed = 1;
  std::string format = "uavcover-v1";
};

Camera parse_camera(const json& j) {
  if (!j.is_object()) throw InputError("camera", "expected an object");
  reject_unknown(j,
                 {"altitude_m", "hfov_deg", "overlap", "sensor_width_mm", "focal_length_mm", "image_width_px",
                  "side_overlap"},
                 "camera.");
  if (!j.contains("altitude_m")) throw InputError("camera.altitude_m", "missing");
  Camera c;
  c.altitude_m = positive(j["altitude_m"], "camera.altitude_m");
  const bool fov = j.contains("hfov_deg") || j.contains("overlap");
  const bool qgc = j.contains("sensor_width_mm") || j.contains("focal_length_mm") ||
                   j.contains("image_width_px") || j.contains("side_overlap");
  if (fov == qgc)
    throw InputError("camera",
                     "give either hfov_deg and overlap, or sensor_width_mm, focal_length_mm, "
                     "image_width_px and side_overlap");
  auto need = [&](const char* k) -> const json& {
    if (!j.contains(k)) throw InputError(std::string("camera.") + k, "missing");
    return j[k];
  };
  if (fov) {
    c.hfov_deg = number(need("hfov_deg"), "camera.hfov_deg");
    if (*c.hfov_deg <= 0 || *c.hfov_deg >= 180) throw InputError("camera.hfov_deg", "must be in (0, 180)");
    c.overlap = in_range(need("overlap"), "camera.overlap", 0.0, 1.0, true);
  } else {
    c.sensor_width_mm = positive(need("sensor_width_mm"), "camera.sensor_width_mm");
    c.focal_length_mm = positive(need("focal_length_mm"), "camera.focal_length_mm");
    c.image_width_px = positive(need("image_width_px"), "camera.image_width_px");
    c.side_overlap = in_range(need("side_overlap"), "camera.side_overlap", 0.0, 1.0, true);
  }
  return c;
}

void parse_uavs(const json& j, Raw& raw) {
  if (j.is_number_integer() || j.is_number_unsigned()) {
    const auto n = j.get<long long>();
    if (n <= 0) throw InputError("uavs", "at least one UAV is needed");
    if (n > 200) throw InputError("uavs", "at most 200 UAVs are supported, got " + std::to_string(n));
    raw.uav_count = static_cast<std::size_t>(n);
    for (std::size_t i = 0; i < raw.uav_count; ++i) {
      Uav u;
      u.id = "uav" + std::to_string(i + 1);
      raw.uavs.push_back(u);
      raw.shares.emplace_back();
    }
    return;
  }
  if (!j.is_array())
    throw InputError("uavs", std::string("expected a count or an array of UAVs, got ") + type_name(j));
  if (j.empty()) throw InputError("uavs", "at least one UAV is needed");
  if (j.size() > 200) throw InputError("uavs", "at most 200 UAVs are supported");
  std::set<std::string> ids;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string f = idx("uavs", i);
    const json& ju = j[i];
    if (!ju.is_object()) throw InputError(f, std::string("expected an object, got ") + type_name(ju));
    reject_unknown(
        ju, {"id", "start", "share", "speed_mps", "max_accel_mps2", "endurance_min", "turn_c1", "turn_c2"},
        f + ".");
    Uav u;
    u.id = ju.contains("id") ? str(ju["id"], f + ".id") : "uav" + std::to_string(i + 1);
    if (u.id.empty() || u.id.size() > 64) throw InputError(f + ".id", "must have 1 to 64 characters");
    for (char ch : u.id)
      if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_' || ch == '.'))
        throw InputError(f + ".id",
                         "may contain only letters, digits, '-', '_' and '.' (it names output files)");
    if (!ids.insert(u.id).second) throw InputError(f + ".id", "duplicate id \"" + u.id + "\"");
    if (ju.contains("start")) u.start = position(ju["start"], f + ".start");
    std::optional<double> share;
    if (ju.contains("share")) {
      share = number(ju["share"], f + ".share");
      if (*share < 0) throw InputError(f + ".share", "must not be negative, got " + ju["share"].dump());
    }
    if (ju.contains("speed_mps")) u.speed_mps = in_range(ju["speed_mps"], f + ".speed_mps", 1e-3, 100.0);
    if (ju.contains("max_accel_mps2"))
      u.max_accel_mps2 = in_range(ju["max_accel_mps2"], f + ".max_accel_mps2", 1e-3, 100.0);
    if (ju.contains("endurance_min"))
      u.endurance_min = in_range(ju["endurance_min"], f + ".endurance_min", 0.1, 10000.0);
    if (ju.contains("turn_c1")) u.turn_c1 = in_range(ju["turn_c1"], f + ".turn_c1", 0.0, 1000.0);
    if (ju.contains("turn_c2")) u.turn_c2 = in_range(ju["turn_c2"], f + ".turn_c2", 1e-6, 1000.0);
    raw.uavs.push_back(u);
    raw.shares.push_back(share);
  }
  raw.uav_count = raw.uavs.size();
}

// Resolves shares: none given -> equal; some given -> the rest share what is left; all given ->
// normalised weights.
void resolve_shares(Raw& raw) {
  const std::size_t n = raw.uavs.size();
  double given_sum = 0;
  std::size_t given = 0;
  for (const auto& s : raw.shares)
    if (s) given_sum += *s, ++given;
  if (given == 0) {
    for (auto& u : raw.uavs) u.share = 1.0 / static_cast<double>(n);
    return;
  }
  if (given == n && given_sum <= 0) throw InputError("uavs", "all shares are zero");
  for (std::size_t i = 0; i < n; ++i)
    if (raw.shares[i] && *raw.shares[i] == 0)
      throw InputError(idx("uavs", i) + ".share", "must be positive (leave the UAV out instead)");
  if (given < n) {
    if (given_sum >= 1.0)
      throw InputError("uavs", "the given shares already add up to " + json(given_sum).dump() +
                                   ", leaving nothing for the UAVs without a share");
    const double rest = (1.0 - given_sum) / static_cast<double>(n - given);
    for (std::size_t i = 0; i < n; ++i) raw.uavs[i].share = raw.shares[i] ? *raw.shares[i] : rest;
    return;
  }
  for (std::size_t i = 0; i < n; ++i) raw.uavs[i].share = *raw.shares[i] / given_sum;
}

Raw parse_v1(const json& j) {
  Raw raw;
  reject_unknown(j,
                 {"name", "area", "no_fly_zones", "spacing_m", "camera", "altitude_m", "uavs", "mode",
                  "planner", "seed", "version", "$schema"},
                 "");
  if (j.contains("version") && j["version"] != 1) throw InputError("version", "only version 1 is supported");
  if (j.contains("name")) raw.name = str(j["name"], "name");
  if (!j.contains("area")) throw InputError("area", "missing");
  for (auto& p : polygons_of(j["area"], "area"))
    raw.area.push_back({std::move(p), raw.area.empty() && geojson_type(j["area"]) != "MultiPolygon"
                                          ? "area.coordinates"
                                          : idx("area.coordinates", raw.area.size())});
  if (j.contains("no_fly_zones")) {
    const json& nz = j["no_fly_zones"];
    if (!nz.is_array()) throw InputError("no_fly_zones", "expected an array of Polygon objects");
    for (std::size_t i = 0; i < nz.size(); ++i) {
      const std::string f = idx("no_fly_zones", i);
      auto polys = polygons_of(nz[i], f);
      for (std::size_t k = 0; k < polys.size(); ++k)
        raw.nfz.push_back(
            {std::move(polys[k]), polys.size() == 1 ? f + ".coordinates" : idx(f + ".coordinates", k)});
    }
  }
  if (j.contains("spacing_m") && j.contains("camera"))
    throw InputError("spacing_m", "give either spacing_m or camera, not both");
  if (j.contains("spacing_m")) raw.spacing = positive(j["spacing_m"], "spacing_m");
  if (j.contains("camera")) raw.camera = parse_camera(j["camera"]);
  if (!raw.spacing && !raw.camera) throw InputError("spacing_m", "missing: give spacing_m or a camera block");
  if (j.contains("altitude_m")) raw.altitude = in_range(j["altitude_m"], "altitude_m", 1.0, 10000.0);
  if (!j.contains("uavs")) throw InputError("uavs", "missing");
  parse_uavs(j["uavs"], raw);
  if (j.contains("mode")) {
    const std::string m = str(j["mode"], "mode");
    if (m == "strict")
      raw.mode = Mode::Strict;
    else if (m == "coverage")
      raw.mode = Mode::Coverage;
    else
      throw InputError("mode", "expected \"strict\" or \"coverage\", got \"" + m + "\"");
  }
  if (j.contains("planner")) {
    raw.planner = str(j["planner"], "planner");
    if (raw.planner != "darp")
      throw InputError("planner", "unknown planner \"" + raw.planner + "\" (available: darp)");
  }
  if (j.contains("seed")) {
    // nlohmann stores every non-negative JSON integer as unsigned
    if (!j["seed"].is_number_unsigned()) throw InputError("seed", "expected a non-negative integer");
    raw.seed = j["seed"].get<std::uint64_t>();
  }
  return raw;
}

// mCPP-optimized-DARP input (droneNo, scanningDensity, polygon [{lat,long}], obstacles,
// pathsStrictlyInPoly, initialPos, rPortions).
Raw parse_mcpp(const json& j) {
  Raw raw;
  raw.format = "mcpp-optimized-darp";
  raw.name = "imported mCPP-optimized-DARP mission";
  auto latlong_ring = [](const json& arr, const std::string& f) {
    if (!arr.is_array()) throw InputError(f, "expected an array of {lat, long} points");
    GeoRing ring;
    for (std::size_t i = 0; i < arr.size(); ++i) ring.push_back(latlong_object(arr[i], idx(f, i)));
    return ring;
  };
  if (!j.contains("polygon")) throw InputError("polygon", "missing");
  raw.area.push_back({GeoPolygon{latlong_ring(j["polygon"], "polygon")}, "polygon"});
  if (j.contains("obstacles")) {
    if (!j["obstacles"].is_array()) throw InputError("obstacles", "expected an array of polygons");
    for (std::size_t i = 0; i < j["obstacles"].size(); ++i)
      raw.nfz.push_back(
          {GeoPolygon{latlong_ring(j["obstacles"][i], idx("obstacles", i))}, idx("obstacles", i)});
  }
  if (!j.contains("scanningDensity")) throw InputError("scanningDensity", "missing");
  raw.spacing = positive(j["scanningDensity"], "scanningDensity");
  if (!j.contains("droneNo")) throw InputError("droneNo", "missing");
  if (!j["droneNo"].is_number_integer() || j["droneNo"].get<long long>() <= 0)
    throw InputError("droneNo", "expected a positive integer");
  parse_uavs(j["droneNo"], raw);
  if (j.contains("pathsStrictlyInPoly")) {
    if (!j["pathsStrictlyInPoly"].is_boolean())
      throw InputError("pathsStrictlyInPoly", "expected true or false");
    raw.mode = j["pathsStrictlyInPoly"].get<bool>() ? Mode::Strict : Mode::Coverage;
  }
  if (j.contains("initialPos") && !(j["initialPos"].is_array() && j["initialPos"].empty())) {
    const json& ip = j["initialPos"];
    if (!ip.is_array() || ip.size() != raw.uavs.size())
      throw InputError("initialPos", "expected one {lat, long} per drone (droneNo = " +
                                         std::to_string(raw.uavs.size()) + ")");
    for (std::size_t i = 0; i < ip.size(); ++i)
      raw.uavs[i].start = latlong_object(ip[i], idx("initialPos", i));
  }
  if (j.contains("rPortions") && !(j["rPortions"].is_array() && j["rPortions"].empty())) {
    const json& rp = j["rPortions"];
    if (!rp.is_array() || rp.size() != raw.uavs.size())
      throw InputError("rPortions",
                       "expected one portion per drone (droneNo = " + std::to_string(raw.uavs.size()) + ")");
    for (std::size_t i = 0; i < rp.size(); ++i) {
      const double s = number(rp[i], idx("rPortions", i));
      if (s < 0) throw InputError(idx("rPortions", i), "must not be negative");
      raw.shares[i] = s;
    }
  }
  return raw;
}

}  // namespace

Mission parse_mission(std::string_view text, const ParseOptions& options) {
  const json j = strict::parse_json(text, "mission");
  if (!j.is_object())
    throw InputError("mission", std::string("expected a JSON object, got ") + j.type_name());
  const bool mcpp = j.contains("droneNo") || (j.contains("polygon") && !j.contains("area"));
  Raw raw;
  try {
    raw = mcpp ? parse_mcpp(j) : parse_v1(j);
  } catch (const json::exception& e) {
    // every field is type-checked above; this is a safety net so that no input can escape as a crash
    throw InputError("mission", std::string("unexpected structure: ") + e.what());
  }
  resolve_shares(raw);

  // normalise rings; holes of the area become no-fly zones
  for (auto& np : raw.area) normalise_polygon(np);
  for (auto& np : raw.nfz) normalise_polygon(np);
  std::vector<GeoPolygon> outer_only;
  for (const auto& np : raw.area) outer_only.push_back({np.poly.front()});
  const geodesy::LocalFrame frame(geodesy::centroid(outer_only));
  for (const auto& np : raw.area) check_valid(np, frame);
  for (const auto& np : raw.nfz) check_valid(np, frame);

  Mission m;
  m.name = raw.name;
  m.source_format = raw.format;
  m.mode = raw.mode;
  m.planner = raw.planner;
  m.seed = raw.seed;
  for (const auto& np : raw.area) {
    m.area.push_back({np.poly.front()});
    for (std::size_t r = 1; r < np.poly.size(); ++r) {
      GeoRing hole = np.poly[r];
      mission::normalise_ring(hole, true);
      m.no_fly_zones.push_back({hole});
    }
  }
  for (const auto& np : raw.nfz) m.no_fly_zones.push_back(np.poly);

  // the area polygons must not overlap each other
  const MultiPolygon area_local = geometry::to_local(m.area, frame);
  double area_sum = 0;
  for (const auto& p : area_local) area_sum += bg::area(p);
  const MultiPolygon area_union = geometry::unite(area_local);
  if (std::fabs(bg::area(area_union) - area_sum) > 1e-6 * area_sum + 1e-3)
    throw InputError("area.coordinates", "the polygons of the MultiPolygon overlap");
  const MultiPolygon no_fly = geometry::unite(geometry::to_local(m.no_fly_zones, frame));
  const MultiPolygon free = geometry::free_space(area_union, no_fly);
  const double free_area = bg::area(free);
  if (free.empty() || free_area < 1e-6 * area_sum || free_area < 1.0)
    throw InputError("no_fly_zones", "the no-fly zones remove the whole area");

  // spacing, camera, altitude
  if (raw.camera) {
    const Camera& c = *raw.camera;
    m.camera = c;
    m.altitude_m = c.altitude_m;
    m.altitude_source = "camera";
    if (c.hfov_deg) {
      const double t = std::tan(*c.hfov_deg * std::numbers::pi / 360.0);
      m.footprint_m = 2.0 * c.altitude_m * t;
      m.spacing_m = (2.0 - *c.overlap) * c.altitude_m * t;  // paper eq. 14
    } else {
      m.gsd_m = c.altitude_m * *c.sensor_width_mm / (*c.focal_length_mm * *c.image_width_px);
      m.footprint_m = *c.image_width_px * *m.gsd_m;
      m.spacing_m = *m.footprint_m * (1.0 - *c.side_overlap);
    }
    if (raw.altitude && std::fabs(*raw.altitude - c.altitude_m) > 1e-9)
      throw InputError("altitude_m", "differs from camera.altitude_m; give the altitude once");
    if (!(m.spacing_m > 0) || !std::isfinite(m.spacing_m))
      throw InputError("camera", "gives a non-positive line spacing");
  } else {
    m.spacing_m = *raw.spacing;
    if (raw.altitude) {
      m.altitude_m = *raw.altitude;
      m.altitude_source = "altitude_m";
    }
  }
  const std::string spacing_field =
      raw.camera ? "camera" : (raw.format == "uavcover-v1" ? "spacing_m" : "scanningDensity");

  // grid size guard: sub-cells of size ds over the bounding box of the free area (any rotation)
  bg::model::box<Point> box;
  bg::envelope(free, box);
  const double w = box.max_corner().x() - box.min_corner().x();
  const double h = box.max_corner().y() - box.min_corner().y();
  const double diag = std::hypot(w, h);
  const double needed = std::ceil(diag / m.spacing_m + 4) * std::ceil(diag / m.spacing_m + 4);
  if (needed > static_cast<double>(options.max_cells)) {
    const double fit = m.spacing_m * std::sqrt(needed / static_cast<double>(options.max_cells)) * 1.01;
    throw InputError(spacing_field, "the grid would need " + std::to_string(static_cast<long long>(needed)) +
                                        " cells, more than the limit of " +
                                        std::to_string(options.max_cells) + "; use a spacing of at least " +
                                        std::to_string(static_cast<long long>(std::ceil(fit))) +
                                        " m or raise the cell limit");
  }
  if (m.spacing_m * 2 > diag * 4)
    throw InputError(spacing_field, "is far larger than the area; no grid cell would fit");

  // UAV starts: not inside a no-fly zone
  for (std::size_t i = 0; i < raw.uavs.size(); ++i) {
    Uav& u = raw.uavs[i];
    if (u.start) {
      const Point p = frame.to_local(*u.start);
      if (!no_fly.empty() && bg::within(p, no_fly))
        throw InputError(raw.format == "uavcover-v1" ? idx("uavs", i) + ".start" : idx("initialPos", i),
                         "the start lies inside a no-fly zone");
      const double far = geometry::distance(area_union, p);
      if (far > 100000.0)
        throw InputError(raw.format == "uavcover-v1" ? idx("uavs", i) + ".start" : idx("initialPos", i),
                         "the start is " + std::to_string(static_cast<int>(far / 1000)) +
                             " km from the area (more than 100 km)");
      u.start_resolved = *u.start;
    }
  }
  m.uavs = raw.uavs;
  return m;
}

}  // namespace uavcover
