// Mission file parsing and validation: uavcover v1 (GeoJSON conventions) and the
// mCPP-optimized-DARP input format. Every refusal is an InputError naming the field.
#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <set>

#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "json/strict.hpp"
#include "mission/mission_json.hpp"
#include "mission/pattern.hpp"
#include "planners/planner.hpp"
#include "uavcover/error.hpp"
#include "uavcover/mission.hpp"

namespace uavcover {

namespace {

using nlohmann::json;

/// Along-track footprint over across-track footprint when the camera block gives no height (4:3, the
/// image format of most survey cameras, in landscape across the flight direction).
constexpr double kDefaultAspect = 0.75;

std::string idx(const std::string& base, std::size_t i) { return base + "[" + std::to_string(i) + "]"; }

// A large non-negative count for a message: digits up to 10^15, else like 3.2e+21.
std::string count_text(double v) {
  if (v >= 0 && v < 1e15) return std::to_string(static_cast<long long>(v));
  return std::isfinite(v) ? json(v).dump() : "more than 1e308";
}

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

// An edge whose longitude changes by more than 180°. GeoJSON edges are straight in longitude and
// latitude (RFC 7946 §3.1.9), so such an edge does not cross the antimeridian: it runs the long way
// round the Earth. It is what a ring meant to cross the antimeridian looks like, so say both.
void check_long_edges(const GeoRing& ring, const std::string& field) {
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const LonLat& a = ring[i];
    const LonLat& b = ring[(i + 1) % ring.size()];
    if (std::fabs(b.lon - a.lon) > 180.0)
      throw InputError(field, "the edge from longitude " + json(a.lon).dump() + " to " + json(b.lon).dump() +
                                  " spans " + json(std::fabs(b.lon - a.lon)).dump() +
                                  "° of longitude: GeoJSON edges run straight in longitude, so it goes the "
                                  "long way round the Earth; an area across the antimeridian (180°) must be "
                                  "split into polygons on either side of it");
  }
}

// Whether all vertices of a ring lie on one line in longitude/latitude degrees (longitudes scaled
// by cos(latitude)): GeoJSON's own plane, in which edges are straight.
bool collinear(const GeoRing& ring) {
  if (ring.size() < 3) return true;
  const double k = std::cos(ring.front().lat * std::numbers::pi / 180.0);
  auto at = [&](std::size_t i) {
    return std::pair{(ring[i].lon - ring.front().lon) * k, ring[i].lat - ring.front().lat};
  };
  std::size_t far = 0;
  double far_len = 0;
  for (std::size_t i = 1; i < ring.size(); ++i) {
    const auto [x, y] = at(i);
    if (std::hypot(x, y) > far_len) far = i, far_len = std::hypot(x, y);
  }
  const auto [fx, fy] = at(far);
  for (std::size_t i = 1; i < ring.size(); ++i) {
    const auto [x, y] = at(i);
    if (std::fabs(fx * y - fy * x) / far_len > 1e-9 * far_len) return false;
  }
  return true;
}

// Great-circle distance in metres (spherical Earth: precise enough for a limit).
double great_circle_m(LonLat a, LonLat b) {
  constexpr double kRad = std::numbers::pi / 180.0;
  const double h =
      std::pow(std::sin((b.lat - a.lat) * kRad / 2), 2) +
      std::cos(a.lat * kRad) * std::cos(b.lat * kRad) * std::pow(std::sin((b.lon - a.lon) * kRad / 2), 2);
  return 2 * 6'371'008.8 * std::asin(std::min(1.0, std::sqrt(h)));
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

// Normalises every ring and checks it (>= 3 distinct vertices, no edge spanning more than 180° of
// longitude, not all on one line).
void normalise_polygon(NamedPolygon& np) {
  for (std::size_t r = 0; r < np.poly.size(); ++r) {
    const std::string f = idx(np.field, r);
    check_long_edges(np.poly[r], f);
    if (mission::normalise_ring(np.poly[r], r == 0) < 3)
      throw InputError(f, "a ring needs at least 3 distinct vertices");
    if (collinear(np.poly[r])) throw InputError(f, "the ring has no area: its vertices lie on one line");
  }
}

// Every vertex within kMaxExtentM of the area's centre: beyond, the local flat frame distorts.
constexpr double kMaxExtentM = 500'000.0;
void check_extent(const NamedPolygon& np, LonLat centre) {
  for (std::size_t r = 0; r < np.poly.size(); ++r) {
    double d = 0;
    for (const LonLat& p : np.poly[r]) d = std::max(d, great_circle_m(centre, p));
    if (d > kMaxExtentM)
      throw InputError(idx(np.field, r),
                       "reaches " + std::to_string(static_cast<long long>(d / 1000)) +
                           " km from the centre of the area; uavcover plans areas that reach "
                           "at most " +
                           std::to_string(static_cast<long long>(kMaxExtentM / 1000)) +
                           " km from their centre (see docs/limits.md)");
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

// UAV ids name output files: [A-Za-z0-9_-][A-Za-z0-9_.-]{0,63} (so never "." or "..").
void check_id(const std::string& id, const std::string& field) {
  if (id.empty() || id.size() > 64) throw InputError(field, "must have 1 to 64 characters");
  for (char ch : id)
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_' || ch == '.'))
      throw InputError(field, "may contain only letters, digits, '-', '_' and '.' (it names output files)");
  if (id.front() == '.') throw InputError(field, "must not start with '.' (it names output files)");
}

// Free-text names: at most 256 bytes, no control characters (U+0000-U+001F, U+007F-U+009F), which
// would end up in file contents, pictures and terminals.
std::string checked_name(const std::string& name, const std::string& field) {
  if (name.size() > 256) throw InputError(field, "must have at most 256 bytes");
  for (std::size_t i = 0; i < name.size(); ++i) {
    const auto c = static_cast<unsigned char>(name[i]);
    const bool c1 = c == 0xC2 && i + 1 < name.size() && static_cast<unsigned char>(name[i + 1]) >= 0x80 &&
                    static_cast<unsigned char>(name[i + 1]) <= 0x9F;  // UTF-8 of U+0080-U+009F
    if (c < 0x20 || c == 0x7F || c1)
      throw InputError(field, "must not contain control characters (U+0000-U+001F, U+007F-U+009F)");
  }
  return name;
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
  json planner_params;  ///< as given; validated against the planner's schema at the end
  std::uint64_t seed = 1;
  double battery_reserve = kDefaultBatteryReserve;
  std::string format = "uavcover-v1";
  std::optional<Terrain> terrain;
  std::optional<Corridor> corridor;
  std::optional<Pattern> pattern;
};

// A camera block at `field` ("camera", or "uavs[i].camera" for a UAV's own).
Camera parse_camera(const json& j, const std::string& field) {
  if (!j.is_object()) throw InputError(field, "expected an object");
  reject_unknown(j,
                 {"altitude_m", "hfov_deg", "overlap", "sensor_width_mm", "focal_length_mm", "image_width_px",
                  "side_overlap", "front_overlap", "vfov_deg", "sensor_height_mm", "image_height_px",
                  "min_trigger_interval_s", "gimbal_pitch_deg", "capture", "image_size_mb"},
                 field + ".");
  if (!j.contains("altitude_m")) throw InputError(field + ".altitude_m", "missing");
  Camera c;
  c.altitude_m = positive(j["altitude_m"], field + ".altitude_m");
  const bool fov = j.contains("hfov_deg") || j.contains("overlap") || j.contains("vfov_deg");
  const bool qgc = j.contains("sensor_width_mm") || j.contains("focal_length_mm") ||
                   j.contains("image_width_px") || j.contains("side_overlap") ||
                   j.contains("sensor_height_mm") || j.contains("image_height_px");
  if (fov == qgc)
    throw InputError(field,
                     "give either hfov_deg and overlap, or sensor_width_mm, focal_length_mm, "
                     "image_width_px and side_overlap");
  auto need = [&](const char* k) -> const json& {
    if (!j.contains(k)) throw InputError(field + "." + k, "missing");
    return j[k];
  };
  if (fov) {
    c.hfov_deg = number(need("hfov_deg"), field + ".hfov_deg");
    if (*c.hfov_deg <= 0 || *c.hfov_deg >= 180) throw InputError(field + ".hfov_deg", "must be in (0, 180)");
    c.overlap = in_range(need("overlap"), field + ".overlap", 0.0, 1.0, true);
    if (j.contains("vfov_deg")) {
      c.vfov_deg = number(j["vfov_deg"], field + ".vfov_deg");
      if (*c.vfov_deg <= 0 || *c.vfov_deg >= 180)
        throw InputError(field + ".vfov_deg", "must be in (0, 180)");
    }
  } else {
    c.sensor_width_mm = positive(need("sensor_width_mm"), field + ".sensor_width_mm");
    c.focal_length_mm = positive(need("focal_length_mm"), field + ".focal_length_mm");
    c.image_width_px = positive(need("image_width_px"), field + ".image_width_px");
    c.side_overlap = in_range(need("side_overlap"), field + ".side_overlap", 0.0, 1.0, true);
    if (j.contains("sensor_height_mm"))
      c.sensor_height_mm = positive(j["sensor_height_mm"], field + ".sensor_height_mm");
    if (j.contains("image_height_px"))
      c.image_height_px = positive(j["image_height_px"], field + ".image_height_px");
  }
  if (j.contains("front_overlap"))
    c.front_overlap = in_range(j["front_overlap"], field + ".front_overlap", 0.0, 0.95);
  if (j.contains("min_trigger_interval_s"))
    c.min_trigger_interval_s = positive(j["min_trigger_interval_s"], field + ".min_trigger_interval_s");
  if (j.contains("gimbal_pitch_deg"))
    c.gimbal_pitch_deg = in_range(j["gimbal_pitch_deg"], field + ".gimbal_pitch_deg", -90.0, 0.0);
  if (j.contains("capture")) {
    const json& cap = j["capture"];
    if (!cap.is_string() || (cap != "distance" && cap != "hover"))
      throw InputError(field + ".capture", "must be \"distance\" or \"hover\", got " + cap.dump());
    c.capture = cap.get<std::string>();
  }
  if (j.contains("image_size_mb"))
    c.image_size_mb = in_range(j["image_size_mb"], field + ".image_size_mb", 1e-3, 1e4);
  return c;
}

// The terrain block: a DEM file name (read later by io::load_terrain), the mode and the tolerance.
Terrain parse_terrain(const json& j) {
  if (!j.is_object()) throw InputError("terrain", std::string("expected an object, got ") + type_name(j));
  reject_unknown(j, {"dem", "mode", "tolerance_m"}, "terrain.");
  if (!j.contains("dem")) throw InputError("terrain.dem", "missing: name the GeoTIFF elevation model");
  Terrain t;
  t.dem = str(j["dem"], "terrain.dem");
  if (t.dem.empty() || t.dem.size() > 4096)
    throw InputError("terrain.dem", "must name a file (1 to 4096 bytes)");
  if (t.dem.find('\0') != std::string::npos)
    throw InputError("terrain.dem", "must not contain NUL characters");
  if (j.contains("mode")) {
    const json& m = j["mode"];
    if (!m.is_string() || (m != "follow" && m != "off"))
      throw InputError("terrain.mode", "must be \"follow\" or \"off\", got " + m.dump());
    t.mode = m.get<std::string>();
  }
  if (j.contains("tolerance_m"))
    t.tolerance_m = in_range(j["tolerance_m"], "terrain.tolerance_m", 0.1, 100.0);
  return t;
}

// The ground geometry of camera `c` at `field` (paper eq. 14, or QGroundControl's formulas).
CameraGeometry camera_geometry(const Camera& c, const std::string& field) {
  CameraGeometry g;
  if (c.hfov_deg) {
    const double t = std::tan(*c.hfov_deg * std::numbers::pi / 360.0);
    g.footprint_m = 2.0 * c.altitude_m * t;
    g.spacing_m = (2.0 - *c.overlap) * c.altitude_m * t;  // paper eq. 14
    g.along_track_footprint_m = c.vfov_deg
                                    ? 2.0 * c.altitude_m * std::tan(*c.vfov_deg * std::numbers::pi / 360.0)
                                    : g.footprint_m * kDefaultAspect;
  } else {
    g.gsd_m = c.altitude_m * *c.sensor_width_mm / (*c.focal_length_mm * *c.image_width_px);
    g.footprint_m = *c.image_width_px * *g.gsd_m;
    g.spacing_m = g.footprint_m * (1.0 - *c.side_overlap);
    // QGroundControl: image height * GSD, or the sensor height's ground extent
    if (c.image_height_px)
      g.along_track_footprint_m = *c.image_height_px * *g.gsd_m;
    else if (c.sensor_height_mm)
      g.along_track_footprint_m = c.altitude_m * *c.sensor_height_mm / *c.focal_length_mm;
    else
      g.along_track_footprint_m = g.footprint_m * kDefaultAspect;
  }
  g.trigger_distance_m = g.along_track_footprint_m * (1.0 - c.front_overlap);
  if (!(g.trigger_distance_m > 0) || !std::isfinite(g.trigger_distance_m))
    throw InputError(field + ".front_overlap", "gives a non-positive trigger distance");
  if (!(g.spacing_m > 0) || !std::isfinite(g.spacing_m))
    throw InputError(field, "gives a non-positive line spacing");
  return g;
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
    reject_unknown(ju,
                   {"id", "start", "share", "speed_mps", "max_accel_mps2", "endurance_min", "turn_c1",
                    "turn_c2", "camera"},
                   f + ".");
    Uav u;
    u.id = ju.contains("id") ? str(ju["id"], f + ".id") : "uav" + std::to_string(i + 1);
    check_id(u.id, f + ".id");
    std::string folded = u.id;
    for (char& ch : folded) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (!ids.insert(folded).second)
      throw InputError(f + ".id",
                       "duplicate id \"" + u.id +
                           "\" (ids name output files, so they must differ in more than letter case)");
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
    if (ju.contains("camera")) {
      u.camera = parse_camera(ju["camera"], f + ".camera");
      u.camera_geometry = camera_geometry(*u.camera, f + ".camera");
    }
    raw.uavs.push_back(u);
    raw.shares.push_back(share);
  }
  raw.uav_count = raw.uavs.size();
}

// A share below this fraction of the largest is refused: no grid could give it a cell.
constexpr double kMinShareRatio = 1e-6;

// Resolves shares: none given -> equal; some given -> fractions of 1, the others split what is left;
// all given -> weights, normalised by first dividing by the largest (no overflow for 1e308, no
// underflow to 0 for 5e-324; a share below kMinShareRatio of the largest is refused).
void resolve_shares(Raw& raw) {
  const std::size_t n = raw.uavs.size();
  const bool v1 = raw.format == "uavcover-v1";
  const std::string all_field = v1 ? "uavs" : "rPortions";
  auto field = [&](std::size_t i) { return v1 ? idx("uavs", i) + ".share" : idx("rPortions", i); };
  std::size_t given = 0;
  double largest = 0;
  for (const auto& s : raw.shares)
    if (s) ++given, largest = std::max(largest, *s);
  if (given == 0) {
    for (auto& u : raw.uavs) u.share = 1.0 / static_cast<double>(n);
    return;
  }
  if (given == n && largest <= 0) throw InputError(all_field, "all shares are zero");
  for (std::size_t i = 0; i < n; ++i)
    if (raw.shares[i] && *raw.shares[i] == 0)
      throw InputError(field(i), "must be positive (leave the UAV out instead)");
  if (given < n) {
    // fractions of the whole (the sum of at most 200 finite values overflows only to +inf)
    double sum = 0;
    for (const auto& s : raw.shares)
      if (s) sum += *s;
    if (!(sum < 1.0))
      throw InputError(all_field,
                       "the given shares already add up to " +
                           (std::isfinite(sum) ? json(sum).dump() : std::string("more than 1e308")) +
                           ", leaving nothing for the UAVs without a share");
    const double rest = (1.0 - sum) / static_cast<double>(n - given);
    for (std::size_t i = 0; i < n; ++i) raw.uavs[i].share = raw.shares[i] ? *raw.shares[i] : rest;
  } else {
    // share / sum, as always; when the sum overflows (shares near 1e308), the same with every share
    // first divided by the largest (weights in (0, 1], sum between 1 and n)
    double sum = 0;
    for (const auto& s : raw.shares) sum += *s;
    if (std::isfinite(sum) && sum > 0) {
      for (std::size_t i = 0; i < n; ++i) raw.uavs[i].share = *raw.shares[i] / sum;
    } else {
      sum = 0;
      for (const auto& s : raw.shares) sum += *s / largest;
      for (std::size_t i = 0; i < n; ++i) raw.uavs[i].share = *raw.shares[i] / largest / sum;
    }
  }
  double top = 0;
  for (const auto& u : raw.uavs) top = std::max(top, u.share);
  for (std::size_t i = 0; i < n; ++i)
    if (raw.shares[i] && !(raw.uavs[i].share >= kMinShareRatio * top))
      throw InputError(field(i), "is " + json(*raw.shares[i]).dump() +
                                     ", less than a millionth of the largest share: no grid could give "
                                     "this UAV a cell (leave it out or give it a larger share)");
}

Raw parse_v1(const json& j) {
  Raw raw;
  reject_unknown(
      j,
      {"name", "area", "no_fly_zones", "spacing_m", "camera", "altitude_m", "uavs", "mode", "planner",
       "planner_params", "seed", "battery_reserve", "terrain", "version", "$schema", "corridor", "pattern"},
      "");
  if (j.contains("version") && j["version"] != 1) throw InputError("version", "only version 1 is supported");
  if (j.contains("name")) raw.name = checked_name(str(j["name"], "name"), "name");
  // a corridor (docs/patterns.md) is given instead of the area: its buffered line is the area
  if (j.contains("corridor") && j.contains("area"))
    throw InputError("corridor", "give either area or corridor, not both");
  if (j.contains("corridor")) {
    raw.corridor = mission::parse_corridor(j["corridor"]);
    raw.area.push_back({mission::corridor_polygon(*raw.corridor), "corridor.line"});
  }
  if (j.contains("pattern")) raw.pattern = mission::parse_pattern(j["pattern"]);
  if (!j.contains("area") && !raw.corridor) throw InputError("area", "missing (or give a corridor)");
  if (!raw.corridor)
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
  if (j.contains("camera")) raw.camera = parse_camera(j["camera"], "camera");
  if (!raw.spacing && !raw.camera) throw InputError("spacing_m", "missing: give spacing_m or a camera block");
  if (j.contains("altitude_m")) raw.altitude = in_range(j["altitude_m"], "altitude_m", 1.0, 10000.0);
  if (j.contains("terrain")) raw.terrain = parse_terrain(j["terrain"]);
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
  }
  (void)planners::require(raw.planner);
  if (j.contains("planner_params")) raw.planner_params = j["planner_params"];
  if (j.contains("seed")) {
    // nlohmann stores every non-negative JSON integer as unsigned
    if (!j["seed"].is_number_unsigned()) throw InputError("seed", "expected a non-negative integer");
    raw.seed = j["seed"].get<std::uint64_t>();
  }
  // a sortie keeps at least 10 % of a battery for flying (docs/sorties.md)
  if (j.contains("battery_reserve"))
    raw.battery_reserve = in_range(j["battery_reserve"], "battery_reserve", 0.0, 0.9);
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
  for (const auto& np : raw.area) check_extent(np, frame.origin());
  for (const auto& np : raw.nfz) check_extent(np, frame.origin());
  for (const auto& np : raw.area) check_valid(np, frame);
  for (const auto& np : raw.nfz) check_valid(np, frame);

  Mission m;
  m.name = raw.name;
  m.source_format = raw.format;
  m.mode = raw.mode;
  m.planner = raw.planner;
  m.planner_params = planners::validate_params(planners::require(raw.planner), raw.planner_params);
  m.seed = raw.seed;
  m.battery_reserve = raw.battery_reserve;
  m.terrain = raw.terrain;
  m.corridor = raw.corridor;
  m.pattern = raw.pattern;
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
    const CameraGeometry g = camera_geometry(c, "camera");
    m.footprint_m = g.footprint_m;
    m.along_track_footprint_m = g.along_track_footprint_m;
    m.spacing_m = g.spacing_m;
    m.trigger_distance_m = g.trigger_distance_m;
    m.gsd_m = g.gsd_m;
    if (raw.altitude && std::fabs(*raw.altitude - c.altitude_m) > 1e-9)
      throw InputError("altitude_m", "differs from camera.altitude_m; give the altitude once");
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
  const double max_cells = static_cast<double>(std::max<std::size_t>(options.max_cells, 1));
  if (!(needed <= max_cells)) {
    // (diag / s + 4)^2 <= max_cells  <=>  s >= diag / (sqrt(max_cells) - 4), with a margin for rounding
    const double side = std::sqrt(max_cells) - 5;
    const std::string fit =
        side >= 1 ? "use a spacing of at least " + count_text(std::ceil(diag / side * 1.01)) + " m or " : "";
    throw InputError(spacing_field,
                     "the grid would need " + count_text(needed) + " cells, more than the limit of " +
                         std::to_string(options.max_cells) + "; " + fit + "raise the cell limit");
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
  // a UAV's own camera (heterogeneous cameras): the mission's camera is the others' default, and every
  // UAV flies the mission's altitude (the exports and the transition altitudes use it)
  for (std::size_t i = 0; i < raw.uavs.size(); ++i) {
    const Uav& u = raw.uavs[i];
    if (!u.camera) continue;
    if (!m.camera)
      throw InputError(
          idx("uavs", i) + ".camera",
          "needs the mission's camera block (the default of the other UAVs) instead of spacing_m");
    if (std::fabs(u.camera->altitude_m - m.camera->altitude_m) > 1e-9)
      throw InputError(idx("uavs", i) + ".camera.altitude_m",
                       "must equal camera.altitude_m (" + json(m.camera->altitude_m).dump() +
                           "): every UAV flies the mission's altitude");
  }
  // each camera must be able to shoot at the trigger interval its UAV's speed gives
  for (std::size_t i = 0; i < raw.uavs.size(); ++i) {
    const Uav& u = raw.uavs[i];
    const Camera* cam = u.camera ? &*u.camera : (m.camera ? &*m.camera : nullptr);
    const std::optional<double> trigger =
        u.camera_geometry ? u.camera_geometry->trigger_distance_m : m.trigger_distance_m;
    if (cam == nullptr || !cam->min_trigger_interval_s || !trigger) continue;
    const std::string cam_field = u.camera ? idx("uavs", i) + ".camera" : std::string("camera");
    const double fastest = *trigger / *cam->min_trigger_interval_s;
    if (u.speed_mps > fastest * (1 + 1e-9))
      throw InputError(
          idx("uavs", i) + ".speed_mps",
          fmt::format("at {:.3g} m/s the camera would shoot every {:.3g} s ({:.3g} m apart), faster "
                      "than {}.min_trigger_interval_s {:.3g} s; fly at most {:.3g} m/s, or "
                      "lower {}.front_overlap",
                      u.speed_mps, *trigger / u.speed_mps, *trigger, cam_field, *cam->min_trigger_interval_s,
                      std::floor(fastest * 1000) / 1000, cam_field));
  }
  m.uavs = raw.uavs;
  return m;
}

}  // namespace uavcover
