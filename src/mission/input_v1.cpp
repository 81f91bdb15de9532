// The uavcover v1 input format (GeoJSON conventions): its members, the UAV list and the terrain block.
#include <fmt/format.h>

#include <cctype>

#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "mission/parse_internal.hpp"
#include "mission/pattern.hpp"
#include "planners/planner.hpp"
#include "uavcover/error.hpp"
#include "uavcover/vehicle.hpp"

namespace uavcover::mission::detail {

namespace {

constexpr std::size_t kMaxRallyPoints = 100;

/// A vehicle profile's name (issue 31, include/uavcover/vehicle.hpp).
std::string autopilot_name(const json& j, const std::string& field) {
  const std::string name = str(j, field);
  if (vehicle_profile(name) == nullptr)
    throw InputError(field,
                     "expected one of " + vehicle_profile_names() + ", got \"" + name.substr(0, 64) + "\"");
  return name;
}

// The terrain block: a DEM file name (read later by io::load_terrain), the mode and the tolerance.
Terrain parse_terrain(const json& j) {
  if (!j.is_object()) throw InputError("terrain", std::string("expected an object, got ") + type_name(j));
  reject_unknown(
      j, {"dem", "dem_id", "source", "mode", "tolerance_m", "max_climb_mps", "max_descent_mps", "max_grade"},
      "terrain.");
  // where the heights come from (issue 31): a file (the CLI), a DEM stored in the server, or the
  // server's tile folder; exactly one
  const int given =
      (j.contains("dem") ? 1 : 0) + (j.contains("dem_id") ? 1 : 0) + (j.contains("source") ? 1 : 0);
  if (given == 0)
    throw InputError("terrain.dem",
                     "missing: name the GeoTIFF elevation model (dem), a stored one (dem_id) or "
                     "\"source\": \"server\"");
  if (given > 1) throw InputError("terrain", "give one of dem, dem_id or source");
  Terrain t;
  if (j.contains("dem")) {
    t.dem = str(j["dem"], "terrain.dem");
    if (t.dem.empty() || t.dem.size() > 4096)
      throw InputError("terrain.dem", "must name a file (1 to 4096 bytes)");
    if (t.dem.find('\0') != std::string::npos)
      throw InputError("terrain.dem", "must not contain NUL characters");
  }
  if (j.contains("dem_id")) {
    const json& d = j["dem_id"];
    if (!d.is_number_integer() || d.get<long long>() <= 0)
      throw InputError("terrain.dem_id", "expected the positive id of a DEM stored with POST /api/v1/dems");
    t.dem_id = d.get<long long>();
  }
  if (j.contains("source")) {
    if (j["source"] != "server")
      throw InputError("terrain.source",
                       "expected \"server\" (the tiles of `serve --dem-dir`), got " + j["source"].dump());
    t.source = "server";
  }
  if (j.contains("max_climb_mps"))
    t.max_climb_mps = in_range(j["max_climb_mps"], "terrain.max_climb_mps", 0.1, 50.0);
  if (j.contains("max_descent_mps"))
    t.max_descent_mps = in_range(j["max_descent_mps"], "terrain.max_descent_mps", 0.1, 50.0);
  if (j.contains("max_grade")) t.max_grade = in_range(j["max_grade"], "terrain.max_grade", 0.01, 10.0);
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

}  // namespace

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
                    "turn_c2", "climb_mps", "descent_mps", "camera", "autopilot"},
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
    if (ju.contains("share") && ju["share"].is_string()) {
      // shares from capabilities (issue 32, docs/wind.md): derived from the UAV's area rate
      if (ju["share"] != "auto")
        throw InputError(f + ".share", "expected a number or \"auto\", got " + ju["share"].dump());
      u.share_auto = true;
    } else if (ju.contains("share")) {
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
    if (ju.contains("climb_mps")) u.climb_mps = in_range(ju["climb_mps"], f + ".climb_mps", 0.1, 30.0);
    if (ju.contains("descent_mps"))
      u.descent_mps = in_range(ju["descent_mps"], f + ".descent_mps", 0.1, 30.0);
    if (ju.contains("camera")) {
      u.camera = parse_camera(ju["camera"], f + ".camera");
      u.camera_geometry = camera_geometry(*u.camera, f + ".camera");
    }
    if (ju.contains("autopilot")) u.autopilot = autopilot_name(ju["autopilot"], f + ".autopilot");
    raw.uavs.push_back(u);
    raw.shares.push_back(share);
  }
  raw.uav_count = raw.uavs.size();
}

Structure parse_structure(const json& j) {
  if (!j.is_object())
    throw InputError("structure", "expected an object {\"footprint\": Polygon, \"height_m\": ...}");
  reject_unknown(j, {"footprint", "height_m", "standoff_m", "top", "safe_height_m"}, "structure.");
  for (const char* f : {"footprint", "height_m", "standoff_m"})
    if (!j.contains(f)) throw InputError(std::string("structure.") + f, "missing");
  Structure s;
  s.height_m = in_range(j["height_m"], "structure.height_m", 0, 1000);
  if (!(s.height_m > 0)) throw InputError("structure.height_m", "must be > 0");
  s.standoff_m = in_range(j["standoff_m"], "structure.standoff_m", 0, 500);
  if (!(s.standoff_m > 0)) throw InputError("structure.standoff_m", "must be > 0");
  if (j.contains("safe_height_m"))
    s.safe_height_m = in_range(j["safe_height_m"], "structure.safe_height_m", 0, 1000);
  if (j.contains("top")) {
    if (!j["top"].is_boolean()) throw InputError("structure.top", "must be true or false");
    s.top = j["top"].get<bool>();
  }
  if (geojson_type(j["footprint"]) != "Polygon")
    throw InputError("structure.footprint", "expected a GeoJSON Polygon");
  NamedPolygon np{polygons_of(j["footprint"], "structure.footprint").front(),
                  "structure.footprint.coordinates"};
  if (np.poly.size() > 1) throw InputError("structure.footprint.coordinates", "a footprint has no holes");
  normalise_polygon(np);
  const geodesy::LocalFrame frame(geodesy::centroid(std::vector<GeoPolygon>{np.poly}));
  check_extent(np, frame.origin());
  check_valid(np, frame);
  s.footprint = np.poly;
  return s;
}

GeoPolygon structure_area(const Structure& s) {
  const geodesy::LocalFrame frame(geodesy::centroid(std::vector<GeoPolygon>{s.footprint}));
  const MultiPolygon local = geometry::to_local(std::vector<GeoPolygon>{s.footprint}, frame);
  bg::strategy::buffer::distance_symmetric<double> distance(s.standoff_m);
  bg::strategy::buffer::side_straight side;
  bg::strategy::buffer::join_round join(72);  // 5 degree steps at convex corners
  bg::strategy::buffer::end_flat end;
  bg::strategy::buffer::point_circle point(72);
  MultiPolygon buf;
  bg::buffer(local, buf, distance, side, join, end, point);
  if (buf.size() != 1) throw InputError("structure.footprint", "its buffer by standoff_m is not one polygon");
  GeoRing ring;
  for (const auto& p : buf.front().outer()) ring.push_back(frame.to_wgs84(p));
  return {ring};
}

Raw parse_v1(const json& j) {
  Raw raw;
  reject_unknown(j,
                 {"name",
                  "area",
                  "no_fly_zones",
                  "spacing_m",
                  "camera",
                  "altitude_m",
                  "uavs",
                  "mode",
                  "planner",
                  "planner_params",
                  "seed",
                  "battery_reserve",
                  "terrain",
                  "version",
                  "$schema",
                  "corridor",
                  "pattern",
                  "structure",
                  "objective",
                  "transition_altitudes",
                  "wind",
                  "shares",
                  "rally",
                  "propose_rally",
                  "resume_backoff_m",
                  "autopilot",
                  "max_mission_items"},
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
  // a structure (docs/patterns.md) is given instead of the area: its footprint buffered by standoff_m
  // (round convex corners) is the area the orbits fly over
  if (j.contains("structure")) {
    if (j.contains("area") || raw.corridor)
      throw InputError("structure", "give one of area, corridor or structure");
    if (!j.contains("camera"))
      throw InputError("camera", "a structure scan needs a camera block (its field of view and overlaps)");
    raw.structure = parse_structure(j["structure"]);
    raw.area.push_back({structure_area(*raw.structure), "structure.footprint"});
  }
  if (!j.contains("area") && !raw.corridor && !raw.structure)
    throw InputError("area", "missing (or give a corridor or a structure)");
  if (!raw.corridor && !raw.structure)
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
  // "shares": "capability" (issue 32, docs/wind.md): every UAV's share is "auto"
  if (j.contains("shares")) {
    if (j["shares"] != "capability")
      throw InputError("shares",
                       "expected \"capability\" (or give the UAVs their shares), got " + j["shares"].dump());
    for (std::size_t i = 0; i < raw.uavs.size(); ++i) {
      if (raw.shares[i])
        throw InputError(idx("uavs", i) + ".share",
                         "\"shares\": \"capability\" derives every UAV's share; give none (or \"auto\")");
      raw.uavs[i].share_auto = true;
    }
  }
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
  // "auto" (docs/planners.md): every planner that supports the mission, the best by the objective
  if (raw.planner != "auto") (void)planners::require(raw.planner);
  if (j.contains("objective")) {
    raw.objective = str(j["objective"], "objective");
    if (raw.objective != "time" && raw.objective != "poc" && raw.objective != "turns" &&
        raw.objective != "length")
      throw InputError("objective",
                       "expected \"time\", \"poc\", \"turns\" or \"length\", got \"" + raw.objective + "\"");
  }
  if (j.contains("transition_altitudes")) {
    raw.transition_altitudes = str(j["transition_altitudes"], "transition_altitudes");
    if (raw.transition_altitudes != "hong" && raw.transition_altitudes != "layers")
      throw InputError("transition_altitudes",
                       "expected \"hong\" or \"layers\", got \"" + raw.transition_altitudes + "\"");
  }
  if (j.contains("planner_params")) raw.planner_params = j["planner_params"];
  if (j.contains("seed")) {
    // nlohmann stores every non-negative JSON integer as unsigned
    if (!j["seed"].is_number_unsigned()) throw InputError("seed", "expected a non-negative integer");
    raw.seed = j["seed"].get<std::uint64_t>();
  }
  // a sortie keeps at least 10 % of a battery for flying (docs/sorties.md)
  if (j.contains("battery_reserve"))
    raw.battery_reserve = in_range(j["battery_reserve"], "battery_reserve", 0.0, 0.9);
  // a steady wind (issue 32, docs/mission-format.md): speed in m/s, the direction it blows from
  if (j.contains("wind")) {
    const json& w = j["wind"];
    if (!w.is_object())
      throw InputError("wind", "expected an object {\"speed_mps\": ..., \"from_deg\": ...}");
    reject_unknown(w, {"speed_mps", "from_deg"}, "wind.");
    if (!w.contains("speed_mps")) throw InputError("wind.speed_mps", "missing");
    Wind wind;
    wind.speed_mps = in_range(w["speed_mps"], "wind.speed_mps", 0.0, 100.0);
    if (w.contains("from_deg")) wind.from_deg = in_range(w["from_deg"], "wind.from_deg", 0.0, 360.0, true);
    raw.wind = wind;
  }
  // rally points (issue 31, docs/fence-rally.md): [[lon, lat], ...]
  if (j.contains("rally")) {
    const json& r = j["rally"];
    if (!r.is_array()) throw InputError("rally", "expected an array of [lon, lat] positions");
    if (r.size() > kMaxRallyPoints)
      throw InputError("rally", fmt::format("at most {} rally points, got {}", kMaxRallyPoints, r.size()));
    for (std::size_t i = 0; i < r.size(); ++i) raw.rally.push_back(position(r[i], idx("rally", i)));
  }
  if (j.contains("propose_rally")) {
    if (!j["propose_rally"].is_boolean()) throw InputError("propose_rally", "expected true or false");
    raw.propose_rally = j["propose_rally"].get<bool>();
    if (raw.propose_rally && !raw.rally.empty())
      throw InputError("propose_rally", "give rally points or ask for a proposal, not both");
  }
  if (j.contains("resume_backoff_m"))
    raw.resume_backoff = in_range(j["resume_backoff_m"], "resume_backoff_m", 0.0, 10000.0);
  if (j.contains("autopilot")) raw.autopilot = autopilot_name(j["autopilot"], "autopilot");
  if (j.contains("max_mission_items")) {
    const json& v = j["max_mission_items"];
    if (!v.is_number_integer() || v.get<long long>() < 8 || v.get<long long>() > 65535)
      throw InputError("max_mission_items",
                       "expected an integer in [8, 65535] (MAVLink counts items in 16 bits)");
    raw.max_mission_items = static_cast<int>(v.get<long long>());
  }
  return raw;
}

}  // namespace uavcover::mission::detail
