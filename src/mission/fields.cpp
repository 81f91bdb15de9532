// Field readers of the mission formats: numbers, strings, positions, GeoJSON polygons and their
// ring checks. Every refusal is an InputError naming the field.
#include <cmath>
#include <numbers>

#include "geometry/geometry.hpp"
#include "mission/mission_json.hpp"
#include "mission/parse_internal.hpp"
#include "uavcover/error.hpp"

namespace uavcover::mission::detail {

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

double in_range(const json& j, const std::string& field, double lo, double hi, bool hi_open) {
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

namespace {

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

}  // namespace

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

}  // namespace uavcover::mission::detail
