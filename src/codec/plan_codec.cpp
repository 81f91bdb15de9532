#include "codec/plan_codec.hpp"

#include <fmt/format.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <system_error>

#include "evaluation/evaluate.hpp"
#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "mission/mission_json.hpp"
#include "photo/photo.hpp"
#include "sorties/sorties.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover::codec {

using nlohmann::json;

namespace {

const char* kind_name(PartKind k) { return k == PartKind::Coverage ? "coverage" : "transit"; }

json line_coords(const std::vector<LonLat>& pts) {
  json c = json::array();
  for (const auto& p : pts) c.push_back({p.lon, p.lat});
  return c;
}

/// The transit parts before the first coverage part of a sortie (out) or after its last (back), as one
/// line of positions (empty when there are none).
json sortie_transit(const Sortie& s, bool out) {
  std::vector<LonLat> pts;
  auto add = [&](const PathPart& part) {
    for (const auto& p : part.wgs84)
      if (pts.empty() || pts.back().lon != p.lon || pts.back().lat != p.lat) pts.push_back(p);
  };
  if (out) {
    for (const auto& part : s.parts) {
      if (part.kind == PartKind::Coverage) break;
      add(part);
    }
  } else {
    std::size_t k = s.parts.size();
    while (k > 0 && s.parts[k - 1].kind != PartKind::Coverage) --k;
    for (; k < s.parts.size(); ++k) add(s.parts[k]);
  }
  return line_coords(pts);
}

/// A part's attitude (PathPart::attitude) as a paths.geojson property: only the fields set; the ROI as
/// [longitude, latitude].
json attitude_json(const Attitude& a, const geodesy::LocalFrame& frame) {
  json j = json::object();
  if (a.altitude_m) j["altitude_m"] = *a.altitude_m;
  if (!a.heading_deg.empty()) j["heading_deg"] = a.heading_deg;
  if (a.gimbal_pitch_deg) j["gimbal_pitch_deg"] = *a.gimbal_pitch_deg;
  if (a.roi) {
    const LonLat r = frame.to_wgs84(*a.roi);
    j["roi"] = {r.lon, r.lat};
  }
  if (a.trigger_distance_m) j["trigger_distance_m"] = *a.trigger_distance_m;
  return j;
}

json sorties_json(const UavPlan& u) {
  json out = json::array();
  for (const auto& s : u.sorties)
    out.push_back({{"index", s.index},
                   {"first_waypoint", s.first_waypoint},
                   {"last_waypoint", s.last_waypoint},
                   {"turns", s.turns},
                   {"length_m", s.length_m},
                   {"duration_min", s.duration_min},
                   {"transit_out", sortie_transit(s, true)},
                   {"transit_back", sortie_transit(s, false)}});
  return out;
}

}  // namespace

json paths_geojson(const Plan& plan, std::optional<std::size_t> only_uav) {
  json features = json::array();
  for (std::size_t a = 0; a < plan.mission.area.size(); ++a)
    features.push_back({{"type", "Feature"},
                        {"properties", {{"role", "area"}, {"index", a}}},
                        {"geometry", mission::geo_polygon_json(plan.mission.area[a])}});
  for (std::size_t z = 0; z < plan.mission.no_fly_zones.size(); ++z)
    features.push_back({{"type", "Feature"},
                        {"properties", {{"role", "no_fly_zone"}, {"index", z}}},
                        {"geometry", mission::geo_polygon_json(plan.mission.no_fly_zones[z])}});
  for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
    if (only_uav && *only_uav != i) continue;
    const auto& u = plan.uavs[i];
    int part_index = 0;
    for (const auto& part : u.parts) {
      const double len = geometry::length(part.local);
      const int turns = part.kind == PartKind::Coverage ? static_cast<int>(part.local.size()) : 0;
      // the segments flown with the camera off (turns, turnarounds: docs/patterns.md), by index
      json off = json::array();
      for (std::size_t k = 0; k < part.camera_off.size(); ++k)
        if (part.camera_off[k] != 0) off.push_back(k);
      features.push_back({{"type", "Feature"},
                          {"properties",
                           {{"uav", u.id},
                            {"kind", kind_name(part.kind)},
                            {"part", part_index++},
                            {"share_requested", u.share_requested},
                            {"share_actual", u.share_actual},
                            {"length_m", len},
                            {"turns", turns}}},
                          {"geometry", {{"type", "LineString"}, {"coordinates", line_coords(part.wgs84)}}}});
      if (!off.empty()) features.back()["properties"]["camera_off"] = std::move(off);
      if (!part.attitude.empty())
        features.back()["properties"]["attitude"] =
            attitude_json(part.attitude, geodesy::LocalFrame(plan.origin));
    }
  }
  return {{"type", "FeatureCollection"}, {"features", std::move(features)}};
}

json plan_json(const Plan& plan, const json& extra) {
  const Mission& m = plan.mission;
  json uavs = json::array();
  double total_len = 0, total_cov = 0;
  int total_turns = 0;
  for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
    const auto& u = plan.uavs[i];
    const auto& mu = m.uavs.at(i);
    json region = json::array();
    for (const auto& poly : u.region) region.push_back(mission::geo_polygon_json(poly).at("coordinates"));
    uavs.push_back({{"id", u.id},
                    {"start", {mu.start_resolved.lon, mu.start_resolved.lat}},
                    {"start_given", mu.start.has_value()},
                    {"share_requested", u.share_requested},
                    {"share_actual", u.share_actual},
                    {"regions", u.regions},
                    {"region", {{"type", "MultiPolygon"}, {"coordinates", std::move(region)}}},
                    {"coverage_length_m", u.coverage_length_m},
                    {"length_m", u.length_m},
                    {"turns", u.turns},
                    {"transition_altitude_m", u.transition_altitude_m},
                    {"expected_finish_min", u.expected_finish_min},
                    {"vertical_time_s", u.vertical_time_s},
                    {"batteries", u.sorties.size()},
                    {"sorties", sorties_json(u)},
                    {"diagnostics", u.diagnostics}});
    total_len += u.length_m;
    total_cov += u.coverage_length_m;
    total_turns += u.turns;
  }
  json j = {
      {"uavcover_version", "0.1.0"},
      {"mission", mission::to_json(m)},
      {"origin", {plan.origin.lon, plan.origin.lat}},
      {"spacing_m", m.spacing_m},
      {"gsd_m", m.gsd_m ? json(*m.gsd_m) : json(nullptr)},
      {"footprint_m", m.footprint_m ? json(*m.footprint_m) : json(nullptr)},
      {"altitude_m", m.altitude_m},
      {"altitude_source", m.altitude_source},
      {"mode", m.mode == Mode::Strict ? "strict" : "coverage"},
      {"seed", m.seed},
      {"battery_reserve", m.battery_reserve},
      {"planner", plan.planner},
      {"complete", plan.complete},
      {"planner_diagnostics", plan.diagnostics},
      {"warnings", plan.warnings},
      {"uavs", std::move(uavs)},
      {"totals",
       {{"length_m", total_len},
        {"coverage_length_m", total_cov},
        {"turns", total_turns},
        {"free_area_m2", plan.free_area_m2},
        {"compute_time_s", plan.compute_time_s}}},
  };
  if (const auto images = photo::estimate(plan)) j["images"] = photo::to_json(*images);
  // issue 32: how "planner": "auto" chose (docs/planners.md), the altitude layers' separations
  if (!plan.selection.is_null()) j["selection"] = plan.selection;
  if (!plan.separation.is_null()) j["separation"] = plan.separation;
  // issue 31: the rally points the exports and uploads carry (given or proposed)
  if (!plan.rally.empty()) {
    json r = json::array();
    for (const auto& p : plan.rally) r.push_back({p.lon, p.lat});
    j["rally"] = std::move(r);
  }
  for (auto it = extra.begin(); it != extra.end(); ++it) j[it.key()] = it.value();
  return j;
}

namespace {

using evaluation::read_position;

/// Positions of a plan must lie near the mission: within this distance of the frame's origin.
constexpr double kMaxPlanExtentM = 500'000.0;

int whole(const json& j, const std::string& field, int lo, int hi) {
  if (!j.is_number_integer()) throw InputError(field, "expected a whole number");
  const auto v = j.get<std::int64_t>();
  if (v < lo || v > hi)
    throw InputError(field, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return static_cast<int>(v);
}

}  // namespace

Plan load_plan(const json& pj, const json& gj) {
  Plan plan;
  try {
    if (!pj.is_object() || !pj.contains("mission")) throw InputError("plan.json: mission", "missing");
    plan.mission = parse_mission(pj["mission"].dump(), ParseOptions{std::size_t{1} << 40});
    plan.origin = read_position(pj.at("origin"), "plan.json: origin");
    const geodesy::LocalFrame frame(plan.origin);
    if (const Point c = frame.to_local(geodesy::centroid(plan.mission.area));
        !(std::hypot(c.x(), c.y()) <= kMaxPlanExtentM))
      throw InputError("plan.json: origin", "lies more than 500 km from the mission's area");
    auto local = [&](const LonLat& ll, const std::string& field) {
      const Point p = frame.to_local(ll);
      if (!(std::hypot(p.x(), p.y()) <= kMaxPlanExtentM))
        throw InputError(field, "lies more than 500 km from the mission");
      return p;
    };
    const auto& ju = pj.at("uavs");
    if (!ju.is_array() || ju.size() != plan.mission.uavs.size())
      throw InputError("plan.json: uavs", "does not match the mission's UAVs");
    plan.planner = pj.at("planner").get<std::string>();
    if (pj.contains("selection")) plan.selection = pj.at("selection");
    if (pj.contains("separation")) plan.separation = pj.at("separation");
    if (pj.contains("rally")) {
      const json& r = pj.at("rally");
      if (!r.is_array() || r.size() > 1000)
        throw InputError("plan.json: rally", "expected at most 1000 positions");
      for (std::size_t k = 0; k < r.size(); ++k) {
        const std::string f = "plan.json: rally[" + std::to_string(k) + "]";
        const LonLat p = read_position(r[k], f);
        (void)local(p, f);
        plan.rally.push_back(p);
      }
    }
    plan.complete = pj.at("complete").get<bool>();
    plan.diagnostics = pj.at("planner_diagnostics");
    plan.warnings = pj.at("warnings").get<std::vector<std::string>>();
    plan.free_area_m2 = pj.at("totals").at("free_area_m2").get<double>();
    plan.compute_time_s = pj.at("totals").at("compute_time_s").get<double>();
    // sorties (docs/sorties.md): read here, checked and completed once the paths are read
    std::vector<std::vector<Sortie>> sorties(ju.size());
    bool any_sorties = false;
    for (std::size_t i = 0; i < ju.size(); ++i) {
      if (!ju[i].is_object() || !ju[i].contains("sorties")) continue;
      any_sorties = true;
      const std::string f = "plan.json: uavs[" + std::to_string(i) + "].sorties";
      const json& js = ju[i]["sorties"];
      if (!js.is_array()) throw InputError(f, "expected an array");
      for (std::size_t k = 0; k < js.size(); ++k) {
        const std::string fk = f + "[" + std::to_string(k) + "]";
        const json& e = js[k];
        if (!e.is_object()) throw InputError(fk, "expected an object");
        Sortie s;
        s.index = whole(e.at("index"), fk + ".index", 0, 1 << 30);
        s.first_waypoint = whole(e.at("first_waypoint"), fk + ".first_waypoint", 0, 1 << 30);
        s.last_waypoint = whole(e.at("last_waypoint"), fk + ".last_waypoint", 0, 1 << 30);
        for (const char* name : {"transit_out", "transit_back"}) {
          const json& line = e.at(name);
          if (!line.is_array() || line.size() == 1)
            throw InputError(fk + "." + name, "expected an empty array or at least 2 positions");
          PathPart t{PartKind::Transit, {}, {}};
          for (const auto& c : line) {
            t.wgs84.push_back(read_position(c, fk + "." + name));
            t.local.push_back(local(t.wgs84.back(), fk + "." + name));
          }
          s.parts.push_back(std::move(t));
        }
        sorties[i].push_back(std::move(s));
      }
    }
    if (any_sorties && pj.contains("battery_reserve")) {
      const json& r = pj["battery_reserve"];
      if (!r.is_number() || !(r.get<double>() >= 0.0 && r.get<double>() <= 0.9))
        throw InputError("plan.json: battery_reserve", "must be a number in [0, 0.9]");
    }
    for (std::size_t i = 0; i < ju.size(); ++i) {
      const std::string f = "plan.json: uavs[" + std::to_string(i) + "]";
      auto& mu = plan.mission.uavs[i];
      mu.start_resolved = read_position(ju[i].at("start"), f + ".start");
      (void)local(mu.start_resolved, f + ".start");
      UavPlan up;
      up.id = ju[i].at("id").get<std::string>();
      if (up.id != mu.id) throw InputError(f + ".id", "does not match the mission's UAV \"" + mu.id + "\"");
      up.share_requested = ju[i].at("share_requested").get<double>();
      up.share_actual = ju[i].at("share_actual").get<double>();
      up.regions = ju[i].at("regions").get<int>();
      up.coverage_length_m = ju[i].at("coverage_length_m").get<double>();
      up.length_m = ju[i].at("length_m").get<double>();
      up.turns = ju[i].at("turns").get<int>();
      up.transition_altitude_m = ju[i].at("transition_altitude_m").get<double>();
      up.expected_finish_min = ju[i].value("expected_finish_min", 0.0);  // plans before issue 32: none
      up.vertical_time_s = ju[i].value("vertical_time_s", 0.0);
      up.diagnostics = ju[i].at("diagnostics");
      const auto& region = ju[i].at("region");
      if (!region.is_object() || region.value("type", "") != "MultiPolygon" ||
          !region.at("coordinates").is_array())
        throw InputError(f + ".region", "expected a GeoJSON MultiPolygon");
      for (const auto& jpoly : region.at("coordinates")) {
        GeoPolygon gp;
        Polygon lp;
        for (const auto& jring : jpoly) {
          if (!jring.is_array() || jring.size() < 4)
            throw InputError(f + ".region", "rings need 4 positions");
          GeoRing ring;
          Polygon::ring_type lring;
          for (const auto& c : jring) {
            ring.push_back(read_position(c, f + ".region"));
            lring.push_back(local(ring.back(), f + ".region"));
          }
          (gp.empty() ? lp.outer() : (lp.inners().push_back({}), lp.inners().back())) = std::move(lring);
          gp.push_back(std::move(ring));
        }
        if (gp.empty()) throw InputError(f + ".region", "empty polygon");
        bg::correct(lp);
        if (std::string why; !bg::is_valid(lp, why))
          throw InputError(f + ".region", "not a valid polygon: " + why);
        up.region.push_back(std::move(gp));
        up.region_local.push_back(std::move(lp));
      }
      plan.uavs.push_back(std::move(up));
    }
    if (!gj.is_object() || !gj.contains("features") || !gj["features"].is_array())
      throw InputError("paths.geojson: features", "missing");
    std::size_t index = 0;
    for (const auto& feature : gj["features"]) {
      const std::string f = "paths.geojson: features[" + std::to_string(index++) + "]";
      const auto& props = feature.at("properties");
      if (!props.is_object() || !props.contains("uav")) continue;
      const std::string id = props.at("uav").get<std::string>();
      auto it =
          std::find_if(plan.uavs.begin(), plan.uavs.end(), [&](const UavPlan& u) { return u.id == id; });
      if (it == plan.uavs.end()) throw InputError(f + ".properties.uav", "unknown UAV \"" + id + "\"");
      const std::string kind = props.at("kind").get<std::string>();
      if (kind != "coverage" && kind != "transit")
        throw InputError(f + ".properties.kind",
                         "expected \"coverage\" or \"transit\", got \"" + kind + "\"");
      const auto& geometry = feature.at("geometry");
      if (geometry.value("type", "") != "LineString" || !geometry.at("coordinates").is_array() ||
          geometry.at("coordinates").size() < 2)
        throw InputError(f + ".geometry", "expected a LineString of at least 2 positions");
      PathPart part;
      part.kind = kind == "coverage" ? PartKind::Coverage : PartKind::Transit;
      for (const auto& c : geometry.at("coordinates")) {
        part.wgs84.push_back(read_position(c, f + ".geometry.coordinates"));
        part.local.push_back(local(part.wgs84.back(), f + ".geometry.coordinates"));
      }
      evaluation::read_camera_properties(props, f + ".properties", part, local);
      it->parts.push_back(std::move(part));
    }
    if (any_sorties) {
      for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
        sorties::rebuild_sorties(plan, i, sorties[i], "plan.json: uavs[" + std::to_string(i) + "].sorties");
        plan.uavs[i].sorties = std::move(sorties[i]);
      }
    } else {
      // a plan folder from before sorties: cut them now (as plan() would)
      sorties::fill_sorties(plan, {}, &plan.warnings);
    }
  } catch (const json::exception& e) {
    throw InputError("PLAN_DIR",
                     std::string("plan.json or paths.geojson is not a uavcover plan: ") + e.what());
  }
  return plan;
}

}  // namespace uavcover::codec
