// Mission file parsing and validation: uavcover v1 (GeoJSON conventions) and the
// mCPP-optimized-DARP input format (input_v1.cpp, input_mcpp.cpp, over the field readers of
// fields.cpp and the camera geometry of camera.cpp). Every refusal is an InputError naming the field.
#include <fmt/format.h>

#include <cmath>

#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "json/strict.hpp"
#include "mission/mission_json.hpp"
#include "mission/parse_internal.hpp"
#include "mission/pattern.hpp"
#include "photo/oblique.hpp"
#include "planners/planner.hpp"
#include "uavcover/error.hpp"
#include "uavcover/mission.hpp"

namespace uavcover {

namespace {

using namespace mission::detail;

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
  if (raw.planner == "auto") {
    // every candidate plans with its own defaults: parameters belong to one planner
    if (raw.planner_params.is_object() ? !raw.planner_params.empty() : !raw.planner_params.is_null())
      throw InputError("planner_params",
                       "\"planner\": \"auto\" plans with each planner's defaults; give none");
    m.planner_params = nlohmann::json::object();
  } else {
    m.planner_params = planners::validate_params(planners::require(raw.planner), raw.planner_params);
  }
  m.objective = raw.objective;
  m.transition_altitudes = raw.transition_altitudes;
  m.seed = raw.seed;
  m.battery_reserve = raw.battery_reserve;
  m.terrain = raw.terrain;
  m.wind = raw.wind;
  m.corridor = raw.corridor;
  m.pattern = raw.pattern;
  m.structure = raw.structure;
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

  // a UAV holding its airspeed into a wind at least as fast makes no ground speed on an upwind leg
  if (m.wind)
    for (std::size_t i = 0; i < raw.uavs.size(); ++i)
      if (m.wind->speed_mps >= raw.uavs[i].speed_mps)
        throw InputError("wind.speed_mps", "must be below every UAV's speed_mps: " +
                                               json(m.wind->speed_mps).dump() + " m/s is not below " +
                                               raw.uavs[i].id + "'s " + json(raw.uavs[i].speed_mps).dump() +
                                               " m/s, so a leg into the wind cannot be flown");

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
  // oblique passes (docs/patterns.md "Obliques"): the mission camera's fields of view tilt the footprint
  if (m.pattern && m.pattern->oblique) {
    const Oblique& o = *m.pattern->oblique;
    if (!m.camera || !m.footprint_m || !m.along_track_footprint_m)
      throw InputError(
          "pattern.oblique",
          "needs a camera block (its fields of view give the tilted footprint) instead of spacing_m");
    for (std::size_t i = 0; i < raw.uavs.size(); ++i)
      if (raw.uavs[i].camera)
        throw InputError(
            idx("uavs", i) + ".camera",
            "the oblique passes (pattern.oblique) fly the mission's camera; give no UAV its own");
    if (!o.nadir && m.pattern->crosshatch)
      throw InputError("pattern.crosshatch",
                       "crosses the nadir grid, which pattern.oblique.nadir false leaves out");
    const double vfov = photo::fov_deg(*m.along_track_footprint_m, m.altitude_m);
    const double far_edge = 90.0 + o.gimbal_pitch_deg + 0.5 * vfov;
    if (far_edge > mission::kMaxObliqueFarEdgeDeg)
      throw InputError(
          "pattern.oblique.gimbal_pitch_deg",
          fmt::format(
              "with the camera's vertical field of view of {:.3g} degrees the footprint's far edge would "
              "be {:.3g} degrees from nadir (at most {}: closer to the horizon the footprint grows "
              "without bound); pitch the gimbal down to at most {:.3g}",
              vfov, far_edge, mission::kMaxObliqueFarEdgeDeg,
              mission::kMaxObliqueFarEdgeDeg - 0.5 * vfov - 90.0));
  }
  // rally points (issue 31, docs/fence-rally.md): safe landing points, never in a no-fly zone, near
  // the work (within 10 km of the area)
  for (std::size_t i = 0; i < raw.rally.size(); ++i) {
    const Point p = frame.to_local(raw.rally[i]);
    if (!no_fly.empty() && bg::covered_by(p, no_fly))
      throw InputError(idx("rally", i), "the rally point lies in a no-fly zone");
    const double far = geometry::distance(area_union, p);
    if (far > 10000.0)
      throw InputError(
          idx("rally", i),
          fmt::format("the rally point is {:.1f} km from the area (at most 10 km)", far / 1000.0));
  }
  m.rally = raw.rally;
  m.propose_rally = raw.propose_rally;
  m.resume_backoff_m = raw.resume_backoff;
  m.autopilot = raw.autopilot;
  m.max_mission_items = raw.max_mission_items;
  m.uavs = raw.uavs;
  return m;
}

}  // namespace uavcover
