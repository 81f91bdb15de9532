#include "evaluation/evaluate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "geometry/geometry.hpp"
#include "json/strict.hpp"
#include "photo/oblique.hpp"
#include "terrain/terrain.hpp"
#include "uavcover/error.hpp"

namespace uavcover::evaluation {

using nlohmann::json;

double footprint_for(const Mission& m) {
  if (m.footprint_m && *m.footprint_m > 0.0) return *m.footprint_m;
  if (m.camera) {
    const Camera& c = *m.camera;
    const double h = c.altitude_m > 0.0 ? c.altitude_m : m.altitude_m;
    if (c.hfov_deg && *c.hfov_deg > 0.0 && h > 0.0)
      return 2.0 * h * std::tan(*c.hfov_deg * std::numbers::pi / 360.0);
    if (c.image_width_px && m.gsd_m && *m.gsd_m > 0.0) return *c.image_width_px * *m.gsd_m;
    if (c.sensor_width_mm && c.focal_length_mm && *c.focal_length_mm > 0.0 && h > 0.0)
      return *c.sensor_width_mm / *c.focal_length_mm * h;
  }
  return 1.5 * m.spacing_m;
}

double footprint_for(const Mission& m, std::size_t uav) {
  if (uav < m.uavs.size() && m.uavs[uav].camera_geometry && m.uavs[uav].camera_geometry->footprint_m > 0.0)
    return m.uavs[uav].camera_geometry->footprint_m;
  return footprint_for(m);
}

void set_uav_footprints(const Mission& mission, std::size_t uavs, double w, CoverageOptions& coverage) {
  if (coverage.footprint_m > 0.0 || !coverage.uav_footprint_m.empty()) return;
  bool differs = false;
  for (std::size_t i = 0; i < uavs; ++i) {
    coverage.uav_footprint_m.push_back(footprint_for(mission, i));
    differs = differs || coverage.uav_footprint_m.back() != w;
  }
  if (!differs) coverage.uav_footprint_m.clear();
}

MultiPolygon free_area(const Mission& mission, const geodesy::LocalFrame& frame) {
  const MultiPolygon area = geometry::unite(geometry::to_local(mission.area, frame));
  const MultiPolygon nfz = geometry::unite(geometry::to_local(mission.no_fly_zones, frame));
  return geometry::free_space(area, nfz);
}

GeoBounds lattice_bounds(const CoverageResult& cov, const geodesy::LocalFrame& frame) {
  const double half = 0.5 * cov.lattice_m;
  const double x0 = cov.lattice_origin.x() - half, y0 = cov.lattice_origin.y() - half;
  const double x1 = x0 + cov.lattice_cols * cov.lattice_m, y1 = y0 + cov.lattice_rows * cov.lattice_m;
  GeoBounds b{90, 180, -90, -180};
  for (const Point& p : {Point(x0, y0), Point(x1, y0), Point(x1, y1), Point(x0, y1)}) {
    const LonLat g = frame.to_wgs84(p);
    b.south = std::min(b.south, g.lat), b.north = std::max(b.north, g.lat);
    b.west = std::min(b.west, g.lon), b.east = std::max(b.east, g.lon);
  }
  return b;
}

Evaluation evaluate_flights(const MultiPolygon& free, const std::vector<Flight>& flights,
                            const std::vector<Uav>& uavs, double footprint_m,
                            const EvaluateOptions& options) {
  if (uavs.size() != flights.size()) throw InputError("uavs", "one UAV per flight is needed");
  Evaluation ev;
  ev.free = free;
  ev.footprint_m = footprint_m;
  for (const auto& u : uavs) ev.uav_ids.push_back(u.id);
  CoverageOptions co = options.coverage;
  co.footprint_m = footprint_m;
  if (options.compute_coverage) {
    ev.coverage = evaluate_coverage(free, flights, co);
  } else {
    // lengths and turns only: an empty set skips the lattice
    ev.coverage = evaluate_coverage(MultiPolygon{}, flights, co);
    ev.coverage.total.area_m2 = free.empty() ? 0.0 : std::abs(bg::area(free));
  }
  std::vector<double> lengths;
  std::vector<int> turns;
  for (std::size_t i = 0; i < ev.coverage.uavs.size(); ++i) {
    const auto& u = ev.coverage.uavs[i];
    double len = u.stats.length_m;
    if (options.cost.wind && options.cost.wind->speed_mps > 0.0 && i < flights.size()) {
      // eq. 15 in wind (issue 32): every leg at its ground speed, i.e. the air distance at the airspeed
      len = 0.0;
      for (const auto& part : flights[i])
        len += air_length_m(part.local, uavs[i].speed_mps, options.cost.wind);
    }
    lengths.push_back(len);
    turns.push_back(u.stats.turns);
  }
  ev.cost = evaluate_cost(lengths, turns, uavs, ev.coverage.total.area_m2, options.cost);
  return ev;
}

std::vector<double> heights_above_ground(const Plan& plan, std::size_t uav, Point a, Point b,
                                         std::size_t pieces) {
  const HeightGrid* ground = terrain::grid(plan.mission);
  std::vector<double> out;
  if (ground == nullptr || pieces == 0) return out;
  const geodesy::LocalFrame frame(plan.origin);
  const double agl = plan.mission.altitude_m;
  const double len = std::hypot(b.x() - a.x(), b.y() - a.y());
  std::vector<terrain::Sample> wps;  // follow mode: the waypoints along the leg, flown at agl above them
  if (plan.mission.terrain->follow())
    wps = terrain::follow_points(*ground, frame, a, b, plan.mission.terrain->tolerance_m);
  const double flat = terrain::home_ground(plan.mission, uav) + agl;
  std::size_t seg = 0;
  for (std::size_t i = 0; i < pieces; ++i) {
    const double t = (static_cast<double>(i) + 0.5) / static_cast<double>(pieces);
    const Point p{a.x() + t * (b.x() - a.x()), a.y() + t * (b.y() - a.y())};
    double flight = flat;
    if (wps.size() >= 2) {
      const double s = t * len;
      while (seg + 2 < wps.size() && wps[seg + 1].s < s) ++seg;
      const auto& w0 = wps[seg];
      const auto& w1 = wps[seg + 1];
      const double f = w1.s > w0.s ? std::clamp((s - w0.s) / (w1.s - w0.s), 0.0, 1.0) : 0.0;
      flight = agl + w0.ground + f * (w1.ground - w0.ground);
    }
    out.push_back(flight - ground->at(frame.to_wgs84(p)));
  }
  return out;
}

void set_oblique_camera(const Mission& mission, CoverageOptions& coverage) {
  // oblique parts sweep the tilted footprint of the mission's camera
  if (coverage.hfov_deg > 0.0 || !mission.camera || !mission.along_track_footprint_m ||
      !(mission.altitude_m > 0.0))
    return;
  coverage.altitude_m = mission.altitude_m;
  coverage.hfov_deg = photo::fov_deg(footprint_for(mission), mission.altitude_m);
  coverage.vfov_deg = photo::fov_deg(*mission.along_track_footprint_m, mission.altitude_m);
}

Evaluation evaluate_plan(const Plan& plan, const EvaluateOptions& options) {
  const geodesy::LocalFrame frame(plan.origin);
  const MultiPolygon free = free_area(plan.mission, frame);
  std::vector<Flight> flights;
  std::vector<Uav> uavs;
  for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
    flights.push_back(plan.uavs[i].parts);
    Uav u = i < plan.mission.uavs.size() ? plan.mission.uavs[i] : Uav{};
    u.id = plan.uavs[i].id;
    uavs.push_back(u);
  }
  const double w =
      options.coverage.footprint_m > 0.0 ? options.coverage.footprint_m : footprint_for(plan.mission);
  EvaluateOptions opt = options;
  set_oblique_camera(plan.mission, opt.coverage);
  if (!opt.cost.wind) opt.cost.wind = plan.mission.wind;  // the time model in the mission's wind
  // heterogeneous cameras: each UAV's legs sweep its own footprint (a --footprint override sweeps one w)
  set_uav_footprints(plan.mission, plan.uavs.size(), w, opt.coverage);
  std::optional<Evaluation::TerrainFootprints> tf;
  if (terrain::grid(plan.mission) != nullptr) {
    // each piece of a coverage leg as wide as the UAV's camera sees from its height above the ground there
    const double agl = plan.mission.altitude_m;
    opt.coverage.piece_m = std::max(1.0, std::min(terrain::grid(plan.mission)->step_m, w / 4.0));
    opt.coverage.widths = [&plan, &tf, w, agl, own = opt.coverage.uav_footprint_m](
                              std::size_t u, PartKind kind, Point a, Point b, std::size_t n) {
      const double wu = u < own.size() ? own[u] : w;
      if (kind != PartKind::Coverage) return std::vector<double>(n, wu);
      std::vector<double> ws = heights_above_ground(plan, u, a, b, n);
      for (double& h : ws) {
        if (!tf) tf = Evaluation::TerrainFootprints{1e300, -1e300, 1e300, -1e300};
        tf->height_min_m = std::min(tf->height_min_m, h), tf->height_max_m = std::max(tf->height_max_m, h);
        h = std::max(0.0, wu * h / agl);  // a leg into the ground sees nothing
        tf->footprint_min_m = std::min(tf->footprint_min_m, h),
        tf->footprint_max_m = std::max(tf->footprint_max_m, h);
      }
      return ws;
    };
  }
  Evaluation ev = evaluate_flights(free, flights, uavs, w, opt);
  ev.terrain = tf;
  // with sorties (docs/sorties.md), a UAV needs one battery per sortie; UAVs without them (a leg longer
  // than one battery) keep eq. 16
  bool with_sorties = false;
  std::vector<int> batteries;
  for (const auto& u : plan.uavs) {
    with_sorties = with_sorties || !u.sorties.empty();
    batteries.push_back(u.sorties.empty() ? -1 : static_cast<int>(u.sorties.size()));
  }
  if (with_sorties) {
    std::vector<double> durations;
    for (const auto& c : ev.cost.uavs) durations.push_back(c.flight_duration_min);
    ev.cost = evaluate_cost_from_durations(durations, uavs, ev.coverage.total.area_m2, opt.cost, &batteries);
  }
  ev.images = photo::estimate(plan);
  ev.facade = evaluate_facade(plan);
  return ev;
}

json to_json(const CoverageStats& s) {
  return json{{"poc", s.poc},
              {"pooc", s.pooc},
              {"max_scans", s.max_scans},
              {"histogram", s.histogram},
              {"turns", s.turns},
              {"length_m", s.length_m},
              {"length_km", s.length_m / 1000.0},
              {"area_m2", s.area_m2},
              {"turns_per_1000m2", s.turns_per_1000m2},
              {"length_per_1000m2", s.length_per_1000m2}};
}

namespace {
/// The oblique block (docs/patterns.md "Obliques"): the nadir parts' PoC and each direction's.
json oblique_json(const CoverageResult& c) {
  json dirs = json::array();
  for (const auto& d : c.oblique)
    dirs.push_back({{"heading_deg", d.heading_deg},
                    {"gimbal_pitch_deg", d.gimbal_pitch_deg},
                    {"poc", d.poc},
                    {"parts", d.parts}});
  return {{"nadir_poc", *c.nadir_poc}, {"directions", std::move(dirs)}};
}
}  // namespace

json to_json(const CoverageResult& c, double footprint_m) {
  json j = to_json(c.total);
  if (c.nadir_poc) j["oblique"] = oblique_json(c);
  j["footprint_m"] = footprint_m;
  j["lattice_m"] = c.lattice_m;
  j["samples"] = c.samples;
  json uavs = json::array();
  for (const auto& u : c.uavs) {
    json ju = to_json(u.stats);
    ju["area_share"] = u.area_share;
    ju["footprint_m"] = u.footprint_m;
    uavs.push_back(std::move(ju));
  }
  j["uavs"] = std::move(uavs);
  return j;
}

json to_json(const CostResult& c) {
  json uavs = json::array();
  for (const auto& u : c.uavs)
    uavs.push_back({{"flight_duration_min", u.flight_duration_min},
                    {"batteries", u.batteries},
                    {"change_battery_delay_min", u.change_battery_delay_min}});
  return json{{"n_uavs", c.n_uavs},
              {"batteries_per_uav", c.batteries_per_uav},
              {"flight_time_min", c.flight_time_min},
              {"deployment_time_min", c.deployment_time_min},
              {"change_battery_delay_min", c.change_battery_delay_min},
              {"total_time_min", c.total_time_min},
              {"flight_cost_eur", c.flight_cost_eur},
              {"single_battery", c.single_battery},
              {"uavs", std::move(uavs)}};
}

namespace {
json terrain_json(const Evaluation::TerrainFootprints& t) {
  return {{"footprint_min_m", t.footprint_min_m},
          {"footprint_max_m", t.footprint_max_m},
          {"height_above_ground_min_m", t.height_min_m},
          {"height_above_ground_max_m", t.height_max_m}};
}
}  // namespace

json to_json(const Evaluation& e) {
  json cov = to_json(e.coverage, e.footprint_m);
  for (std::size_t i = 0; i < e.uav_ids.size() && i < cov["uavs"].size(); ++i)
    cov["uavs"][i]["id"] = e.uav_ids[i];
  json j{{"coverage", std::move(cov)}, {"cost", to_json(e.cost)}};
  if (e.images) j["images"] = photo::to_json(*e.images);
  if (e.terrain) j["terrain_footprints"] = terrain_json(*e.terrain);
  if (e.facade) j["facade"] = to_json(*e.facade);
  return j;
}

json evaluation_json(const Evaluation& e) {
  const auto& t = e.coverage.total;
  const auto& c = e.cost;
  json j{{"poc", t.poc},
         {"pooc", t.pooc},
         {"max_scans", t.max_scans},
         {"histogram", t.histogram},
         {"turns", t.turns},
         {"turns_per_1000m2", t.turns_per_1000m2},
         {"length_m", t.length_m},
         {"length_per_1000m2", t.length_per_1000m2},
         {"area_m2", t.area_m2},
         {"footprint_m", e.footprint_m},
         {"lattice_m", e.coverage.lattice_m},
         {"samples", e.coverage.samples},
         {"batteries_per_uav", c.batteries_per_uav},
         {"flight_time_min", c.flight_time_min},
         {"deployment_time_min", c.deployment_time_min},
         {"change_battery_delay_min", c.change_battery_delay_min},
         {"total_time_min", c.total_time_min},
         {"cost_eur", c.flight_cost_eur}};
  json uavs = json::array();
  for (std::size_t i = 0; i < e.coverage.uavs.size(); ++i) {
    const auto& u = e.coverage.uavs[i];
    json ju = to_json(u.stats);
    ju["id"] = i < e.uav_ids.size() ? e.uav_ids[i] : "uav-" + std::to_string(i + 1);
    ju["area_share"] = u.area_share;
    ju["footprint_m"] = u.footprint_m;
    if (i < c.uavs.size()) {
      ju["flight_duration_min"] = c.uavs[i].flight_duration_min;
      ju["batteries"] = c.uavs[i].batteries;
    }
    uavs.push_back(std::move(ju));
  }
  j["uavs"] = std::move(uavs);
  if (e.coverage.nadir_poc) j["oblique"] = oblique_json(e.coverage);
  if (e.images) j["images"] = photo::to_json(*e.images);
  if (e.terrain) j["terrain_footprints"] = terrain_json(*e.terrain);
  if (e.facade) j["facade"] = to_json(*e.facade);
  return j;
}

namespace {

/// A finite number in [lo, hi].
double number_in(const json& j, const std::string& field, double lo, double hi, const char* unit) {
  if (!j.is_number() || !std::isfinite(j.get<double>()) || j.get<double>() < lo || j.get<double>() > hi)
    throw InputError(field, fmt::format("expected a number in [{}, {}] {}", lo, hi, unit));
  return j.get<double>();
}

Attitude read_attitude(const json& j, const std::string& f, std::size_t vertices, const ToLocal& to_local) {
  if (!j.is_object()) throw InputError(f, "expected an object");
  for (auto it = j.begin(); it != j.end(); ++it)
    if (it.key() != "altitude_m" && it.key() != "heading_deg" && it.key() != "gimbal_pitch_deg" &&
        it.key() != "roi" && it.key() != "trigger_distance_m")
      throw InputError(f + "." + it.key(),
                       "unknown field (expected altitude_m, heading_deg, gimbal_pitch_deg, roi, "
                       "trigger_distance_m)");
  Attitude a;
  if (j.contains("altitude_m"))
    a.altitude_m = number_in(j["altitude_m"], f + ".altitude_m", 0.0, 10000.0, "m");
  if (j.contains("heading_deg")) {
    const json& h = j["heading_deg"];
    if (!h.is_array() || h.size() != vertices)
      throw InputError(f + ".heading_deg",
                       fmt::format("expected one heading per vertex of the part ({} numbers)", vertices));
    for (std::size_t k = 0; k < h.size(); ++k)
      a.heading_deg.push_back(number_in(h[k], fmt::format("{}.heading_deg[{}]", f, k), -360.0, 360.0, "deg"));
  }
  if (j.contains("gimbal_pitch_deg"))
    a.gimbal_pitch_deg = number_in(j["gimbal_pitch_deg"], f + ".gimbal_pitch_deg", -90.0, 90.0, "deg");
  if (j.contains("roi")) a.roi = to_local(read_position(j["roi"], f + ".roi"), f + ".roi");
  if (j.contains("trigger_distance_m"))
    a.trigger_distance_m = number_in(j["trigger_distance_m"], f + ".trigger_distance_m", 0.01, 10000.0, "m");
  return a;
}

}  // namespace

LonLat read_position(const json& c, const std::string& field) {
  if (!c.is_array() || c.size() < 2 || !c[0].is_number() || !c[1].is_number())
    throw InputError(field, "expected [longitude, latitude]");
  const LonLat ll{c[0].get<double>(), c[1].get<double>()};
  if (!std::isfinite(ll.lon) || !std::isfinite(ll.lat) || std::fabs(ll.lon) > 180.0 ||
      std::fabs(ll.lat) > 90.0)
    throw InputError(field, "not a WGS84 position");
  return ll;
}

void read_camera_properties(const json& props, const std::string& field, PathPart& part,
                            const ToLocal& to_local) {
  if (!props.is_object()) return;
  if (props.contains("camera_off")) {
    const auto& off = props.at("camera_off");
    if (!off.is_array()) throw InputError(field + ".camera_off", "expected an array of segment indices");
    part.camera_off.assign(part.local.size() - 1, 0);
    for (const auto& k : off) {
      if (!k.is_number_unsigned() || k.get<std::size_t>() >= part.camera_off.size())
        throw InputError(field + ".camera_off",
                         "expected segment indices below " + std::to_string(part.camera_off.size()));
      part.camera_off[k.get<std::size_t>()] = 1;
    }
  }
  if (props.contains("attitude"))
    part.attitude = read_attitude(props.at("attitude"), field + ".attitude", part.local.size(), to_local);
}

namespace {

std::vector<Point> read_line(const json& coords, const std::string& field, const geodesy::LocalFrame& frame,
                             std::vector<LonLat>& wgs) {
  if (!coords.is_array()) throw InputError(field, "must be an array of [longitude, latitude] positions");
  if (coords.size() < 2) throw InputError(field, "a LineString needs at least 2 positions");
  std::vector<Point> pts;
  for (std::size_t k = 0; k < coords.size(); ++k) {
    const json& p = coords[k];
    const std::string f = field + "[" + std::to_string(k) + "]";
    if (!p.is_array() || p.size() < 2 || !p[0].is_number() || !p[1].is_number())
      throw InputError(f, "must be a position [longitude, latitude]");
    const double lon = p[0].get<double>(), lat = p[1].get<double>();
    if (!std::isfinite(lon) || lon < -180.0 || lon > 180.0) throw InputError(f, "longitude out of range");
    if (!std::isfinite(lat) || lat < -90.0 || lat > 90.0) throw InputError(f, "latitude out of range");
    wgs.push_back({lon, lat});
    pts.push_back(frame.to_local({lon, lat}));
  }
  return pts;
}

}  // namespace

GeoPaths parse_paths_geojson(std::string_view text, const geodesy::LocalFrame& frame) {
  const json doc = strict::parse_json(text, "paths");
  if (!doc.is_object()) throw InputError("type", "GeoJSON must be an object");
  if (!doc.contains("type") || !doc["type"].is_string())
    throw InputError("type", "missing GeoJSON type (FeatureCollection, Feature or LineString)");
  // (feature, field prefix): pointers into the document, never copies of it
  std::vector<std::pair<const json*, std::string>> features;
  json wrapped;  // a bare geometry, wrapped into a Feature
  const std::string type = doc["type"].get<std::string>();
  if (type == "FeatureCollection") {
    if (!doc.contains("features") || !doc["features"].is_array())
      throw InputError("features", "a FeatureCollection needs a 'features' array");
    for (std::size_t i = 0; i < doc["features"].size(); ++i)
      features.emplace_back(&doc["features"][i], "features[" + std::to_string(i) + "]");
  } else if (type == "Feature") {
    features.emplace_back(&doc, "");
  } else if (type == "LineString" || type == "MultiLineString") {
    wrapped = json{{"type", "Feature"}, {"properties", json::object()}, {"geometry", doc}};
    features.emplace_back(&wrapped, "");
  } else {
    throw InputError("type",
                     "unsupported GeoJSON type '" + type + "' (FeatureCollection, Feature or LineString)");
  }

  const ToLocal to_local = [&frame](const LonLat& ll, const std::string&) { return frame.to_local(ll); };
  GeoPaths out;
  std::map<std::string, std::size_t> index;
  int anonymous = 0;
  static const json no_properties = json::object();
  for (const auto& [fp, prefix] : features) {
    const json& f = *fp;
    const std::string pre = prefix.empty() ? "" : prefix + ".";
    if (!f.is_object() || !f.contains("type") || f["type"] != "Feature")
      throw InputError(pre + "type", "must be \"Feature\"");
    if (!f.contains("geometry") || !f["geometry"].is_object())
      throw InputError(pre + "geometry", "missing or not an object");
    const json& g = f["geometry"];
    if (!g.contains("type") || !g["type"].is_string())
      throw InputError(pre + "geometry.type", "missing geometry type");
    const std::string gt = g["type"].get<std::string>();
    if (gt != "LineString" && gt != "MultiLineString") continue;  // area, no-fly zones, markers
    if (!g.contains("coordinates")) throw InputError(pre + "geometry.coordinates", "missing");
    const json& props =
        f.contains("properties") && f["properties"].is_object() ? f["properties"] : no_properties;
    PartKind kind = PartKind::Coverage;
    if (props.contains("kind")) {
      if (!props["kind"].is_string()) throw InputError(pre + "properties.kind", "must be a string");
      const std::string k = props["kind"].get<std::string>();
      if (k == "transit")
        kind = PartKind::Transit;
      else if (k != "coverage")
        throw InputError(pre + "properties.kind", "must be \"coverage\" or \"transit\"");
    }
    std::string uav;
    if (props.contains("uav") && !props["uav"].is_null()) {
      if (props["uav"].is_string())
        uav = props["uav"].get<std::string>();
      else if (props["uav"].is_number_integer())
        uav = "uav-" + std::to_string(props["uav"].get<long>());
      else
        throw InputError(pre + "properties.uav", "must be a string naming the UAV");
    } else {
      uav = "uav-" + std::to_string(++anonymous);
      while (index.count(uav)) uav = "uav-" + std::to_string(++anonymous);
    }
    auto it = index.find(uav);
    if (it == index.end()) {
      it = index.emplace(uav, out.flights.size()).first;
      out.uav_ids.push_back(uav);
      out.flights.emplace_back();
    }
    const std::string cf = pre + "geometry.coordinates";
    std::vector<const json*> lines;
    if (gt == "LineString") {
      lines.push_back(&g["coordinates"]);
    } else {
      if (!g["coordinates"].is_array()) throw InputError(cf, "must be an array of LineString coordinates");
      for (const auto& l : g["coordinates"]) lines.push_back(&l);
    }
    for (std::size_t li = 0; li < lines.size(); ++li) {
      PathPart part;
      part.kind = kind;
      part.local = read_line(*lines[li], gt == "LineString" ? cf : cf + "[" + std::to_string(li) + "]", frame,
                             part.wgs84);
      read_camera_properties(props, pre + "properties", part, to_local);
      out.flights[it->second].push_back(std::move(part));
    }
  }
  if (out.flights.empty())
    throw InputError("features",
                     "no LineString found: the paths must be GeoJSON LineStrings, one or more per UAV");
  return out;
}

}  // namespace uavcover::evaluation
