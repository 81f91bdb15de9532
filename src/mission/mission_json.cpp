#include "mission/mission_json.hpp"

#include "mission/pattern.hpp"

#include <algorithm>
#include <set>

namespace uavcover {

namespace mission {

using nlohmann::json;

std::size_t normalise_ring(GeoRing& ring, bool ccw) {
  GeoRing out;
  for (const auto& p : ring)
    if (out.empty() || !(out.back() == p)) out.push_back(p);
  while (out.size() > 1 && out.front() == out.back()) out.pop_back();
  // a ring traced several times over (same cycle repeated) collapses to one cycle
  for (std::size_t period = 3; period < out.size(); ++period) {
    if (out.size() % period != 0) continue;
    bool repeats = true;
    for (std::size_t i = period; i < out.size() && repeats; ++i) repeats = out[i] == out[i % period];
    if (repeats) {
      out.resize(period);
      break;
    }
  }
  std::set<std::pair<double, double>> distinct;
  for (const auto& p : out) distinct.insert({p.lon, p.lat});
  double twice_area = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const auto& a = out[i];
    const auto& b = out[(i + 1) % out.size()];
    twice_area += (a.lon * b.lat - b.lon * a.lat);
  }
  if ((twice_area < 0) == ccw) std::reverse(out.begin(), out.end());
  if (!out.empty()) out.push_back(out.front());
  ring = std::move(out);
  return distinct.size();
}

json geo_polygon_json(const GeoPolygon& poly) {
  json rings = json::array();
  for (const auto& r : poly) {
    json ring = json::array();
    for (const auto& p : r) ring.push_back({p.lon, p.lat});
    rings.push_back(std::move(ring));
  }
  return {{"type", "Polygon"}, {"coordinates", std::move(rings)}};
}

namespace {

// A camera block (the mission's or a UAV's own).
json camera_json(const Camera& c) {
  json cj = {{"altitude_m", c.altitude_m}};
  if (c.hfov_deg) cj["hfov_deg"] = *c.hfov_deg;
  if (c.overlap) cj["overlap"] = *c.overlap;
  if (c.sensor_width_mm) cj["sensor_width_mm"] = *c.sensor_width_mm;
  if (c.focal_length_mm) cj["focal_length_mm"] = *c.focal_length_mm;
  if (c.image_width_px) cj["image_width_px"] = *c.image_width_px;
  if (c.side_overlap) cj["side_overlap"] = *c.side_overlap;
  // photogrammetry fields: written when given or not the default, so old documents round-trip unchanged
  const Camera defaults;
  if (c.front_overlap != defaults.front_overlap) cj["front_overlap"] = c.front_overlap;
  if (c.vfov_deg) cj["vfov_deg"] = *c.vfov_deg;
  if (c.sensor_height_mm) cj["sensor_height_mm"] = *c.sensor_height_mm;
  if (c.image_height_px) cj["image_height_px"] = *c.image_height_px;
  if (c.min_trigger_interval_s) cj["min_trigger_interval_s"] = *c.min_trigger_interval_s;
  if (c.gimbal_pitch_deg != defaults.gimbal_pitch_deg) cj["gimbal_pitch_deg"] = c.gimbal_pitch_deg;
  if (c.capture != defaults.capture) cj["capture"] = c.capture;
  if (c.image_size_mb != defaults.image_size_mb) cj["image_size_mb"] = c.image_size_mb;
  return cj;
}

}  // namespace

json to_json(const Mission& m) {
  json area;
  if (m.area.size() == 1) {
    area = geo_polygon_json(m.area.front());
  } else {
    json polys = json::array();
    for (const auto& p : m.area) polys.push_back(geo_polygon_json(p)["coordinates"]);
    area = {{"type", "MultiPolygon"}, {"coordinates", std::move(polys)}};
  }
  json nfz = json::array();
  for (const auto& p : m.no_fly_zones) nfz.push_back(geo_polygon_json(p));
  json j = {{"version", 1}, {"name", m.name}, {"area", std::move(area)}, {"no_fly_zones", std::move(nfz)}};
  if (m.camera) {
    j["camera"] = camera_json(*m.camera);
  } else {
    j["spacing_m"] = m.spacing_m;
    if (m.altitude_source == "altitude_m") j["altitude_m"] = m.altitude_m;
  }
  json uavs = json::array();
  for (const auto& u : m.uavs) {
    json ju = {{"id", u.id},
               {"share", u.share},
               {"speed_mps", u.speed_mps},
               {"max_accel_mps2", u.max_accel_mps2},
               {"endurance_min", u.endurance_min},
               {"turn_c1", u.turn_c1},
               {"turn_c2", u.turn_c2}};
    if (u.climb_mps != UavDefaults::climb_mps) ju["climb_mps"] = u.climb_mps;
    if (u.descent_mps != UavDefaults::descent_mps) ju["descent_mps"] = u.descent_mps;
    if (u.start) ju["start"] = {u.start->lon, u.start->lat};
    if (u.camera) ju["camera"] = camera_json(*u.camera);
    if (u.share_auto) ju["share"] = "auto";
    if (!u.autopilot.empty()) ju["autopilot"] = u.autopilot;
    uavs.push_back(std::move(ju));
  }
  j["uavs"] = std::move(uavs);
  j["mode"] = m.mode == Mode::Strict ? "strict" : "coverage";
  j["planner"] = m.planner;
  if (!m.planner_params.empty()) j["planner_params"] = m.planner_params;
  if (m.objective != "time") j["objective"] = m.objective;
  if (m.transition_altitudes != "hong") j["transition_altitudes"] = m.transition_altitudes;
  j["seed"] = m.seed;
  // written when not the default, so that missions without it keep their JSON unchanged
  if (m.battery_reserve != kDefaultBatteryReserve) j["battery_reserve"] = m.battery_reserve;
  if (m.terrain) {
    const Terrain& t = *m.terrain;
    j["terrain"] = {{"mode", t.mode}, {"tolerance_m", t.tolerance_m}};
    if (t.dem_id > 0)
      j["terrain"]["dem_id"] = t.dem_id;
    else if (t.source == "server")
      j["terrain"]["source"] = "server";
    else
      j["terrain"]["dem"] = t.dem;
    if (t.max_climb_mps) j["terrain"]["max_climb_mps"] = *t.max_climb_mps;
    if (t.max_descent_mps) j["terrain"]["max_descent_mps"] = *t.max_descent_mps;
    if (t.max_grade) j["terrain"]["max_grade"] = *t.max_grade;
  }
  // a corridor mission is written as its corridor (the area is its buffer, derived again on reading)
  if (m.corridor) {
    j.erase("area");
    j["corridor"] = corridor_json(*m.corridor);
  }
  // a structure mission likewise as its structure (the area is the footprint's buffer by the standoff)
  if (m.structure) {
    j.erase("area");
    const Structure& st = *m.structure;
    j["structure"] = {{"footprint", geo_polygon_json(st.footprint)},
                      {"height_m", st.height_m},
                      {"standoff_m", st.standoff_m},
                      {"top", st.top}};
    if (st.safe_height_m != Structure{}.safe_height_m) j["structure"]["safe_height_m"] = st.safe_height_m;
  }
  if (m.pattern) j["pattern"] = pattern_json(*m.pattern);
  if (m.wind) j["wind"] = {{"speed_mps", m.wind->speed_mps}, {"from_deg", m.wind->from_deg}};
  // issue 31: each written only when given, so that missions without them keep their JSON unchanged
  if (!m.rally.empty()) {
    json r = json::array();
    for (const auto& p : m.rally) r.push_back({p.lon, p.lat});
    j["rally"] = std::move(r);
  }
  if (m.propose_rally) j["propose_rally"] = true;
  if (m.resume_backoff_m) j["resume_backoff_m"] = *m.resume_backoff_m;
  if (!m.autopilot.empty()) j["autopilot"] = m.autopilot;
  if (m.max_mission_items) j["max_mission_items"] = *m.max_mission_items;
  return j;
}

}  // namespace mission

std::string mission_to_json(const Mission& m, int indent) { return mission::to_json(m).dump(indent); }

}  // namespace uavcover
