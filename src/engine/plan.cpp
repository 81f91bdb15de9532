// The facade's plan(): one pipeline for every planner.
//   mission -> local frame and free space -> starts (given or drawn from the seed)
//   -> the planner (registry) -> transit legs routed around no-fly zones -> WGS84 -> metrics,
//   regions, transition altitudes -> battery sorties (the planner's own boundaries when it gives them).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <random>

#include "engine/local_mission.hpp"
#include "engine/rally.hpp"
#include "engine/shares.hpp"
#include "engine/test_hold.hpp"
#include "evaluation/evaluate.hpp"
#include "geometry/geometry.hpp"
#include "planners/planner.hpp"
#include "planners/structure/structure.hpp"
#include "sorties/sorties.hpp"
#include "terrain/terrain.hpp"
#include "uavcover/uavcover.hpp"
#include "waypoints/vertical.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover {

namespace {

/// Refuses what the planner cannot do (its documented capabilities).
void check_capabilities(const planners::PlannerInfo& info, const Mission& m) {
  const auto& c = info.supports;
  const std::string who = "planner \"" + info.name + "\"";
  if (!c.no_fly_zones && !m.no_fly_zones.empty())
    throw InputError("no_fly_zones", who + " does not plan around no-fly zones; choose another planner");
  if (!c.multiple_areas && m.area.size() > 1)
    throw InputError("area", who + " plans one polygon; this area has " + std::to_string(m.area.size()));
  if (m.mode == Mode::Strict && !c.strict_mode) throw InputError("mode", who + " has no strict mode");
  if (m.mode == Mode::Coverage && !c.coverage_mode) throw InputError("mode", who + " has no coverage mode");
  // the patterns (docs/patterns.md)
  if (m.corridor && !c.corridor)
    throw InputError("corridor", who + " does not plan corridors; choose boustrophedon or milp");
  if (m.structure && !c.structure)
    throw InputError("structure",
                     who + " does not plan structure (facade) scans; choose boustrophedon or milp");
  if (m.pattern) {
    const Pattern& p = *m.pattern;
    auto refuse = [&](bool asked, bool can, const std::string& field) {
      if (asked && !can)
        throw InputError("pattern." + field, who + " does not support it (uavcover planners)");
    };
    refuse(p.crosshatch, c.crosshatch, "crosshatch");
    refuse(p.turnaround_m > 0.0, c.turnaround, "turnaround_m");
    refuse(p.entry != "auto", c.entry, "entry");
    refuse(p.alternate_transects, c.alternate_transects, "alternate_transects");
    refuse(p.capture_in_turnaround, c.capture_in_turnaround, "capture_in_turnaround");
    refuse(p.oblique.has_value(), c.oblique, "oblique");
    if (p.oblique && m.corridor)
      throw InputError("pattern.oblique", "oblique passes are planned over areas, not corridors");
  }
  if (!c.shares)
    for (std::size_t i = 1; i < m.uavs.size(); ++i)
      if (std::fabs(m.uavs[i].share - m.uavs[0].share) > 1e-9)
        throw InputError("uavs[" + std::to_string(i) + "].share",
                         who + " divides the area equally; give every UAV the same share");
}

/// Altitude layers (Mission::transition_altitudes "layers", docs/mission-format.md): UAVs i and j
/// conflict when a transit leg of one crosses the other's region, or their transit legs cross while both
/// fly them (the time model: eq. 15 per part, from take-off); the conflict graph is coloured greedily
/// (DSatur, ties by index) and layer k flies at base + k * step. Fills Plan::separation.
void assign_layers(Plan& out, std::vector<std::string>* warnings) {
  const std::size_t n = out.uavs.size();
  struct Leg {
    std::vector<Point> line;
    bg::model::box<Point> box;
    double t0, t1;  // minutes from take-off
  };
  std::vector<std::vector<Leg>> legs(n);
  std::vector<bg::model::box<Point>> region_box(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& up = out.uavs[i];
    bg::envelope(up.region_local, region_box[i]);
    double t = 0;
    for (const auto& part : up.parts) {
      const int turns = part.kind == PartKind::Coverage ? static_cast<int>(part.local.size()) : 0;
      const double dt = evaluation::flight_duration_min(
          evaluation::air_length_m(part.local, out.mission.uavs[i].speed_mps, out.mission.wind), turns,
          out.mission.uavs[i]);
      if (part.kind == PartKind::Transit && part.local.size() >= 2) {
        Leg leg{part.local, {}, t, t + dt};
        bg::envelope(bg::model::linestring<Point>(part.local.begin(), part.local.end()), leg.box);
        legs[i].push_back(std::move(leg));
      }
      t += dt;
    }
  }
  auto crosses_region = [&](std::size_t a, std::size_t b) {  // a's transits cross b's region
    if (out.uavs[b].region_local.empty()) return false;
    for (const auto& l : legs[a]) {
      if (!bg::intersects(l.box, region_box[b])) continue;
      if (bg::intersects(bg::model::linestring<Point>(l.line.begin(), l.line.end()),
                         out.uavs[b].region_local))
        return true;
    }
    return false;
  };
  auto transits_cross = [&](std::size_t a, std::size_t b) {
    for (const auto& la : legs[a])
      for (const auto& lb : legs[b]) {
        if (la.t1 < lb.t0 || lb.t1 < la.t0 || !bg::intersects(la.box, lb.box)) continue;
        if (bg::intersects(bg::model::linestring<Point>(la.line.begin(), la.line.end()),
                           bg::model::linestring<Point>(lb.line.begin(), lb.line.end())))
          return true;
      }
    return false;
  };
  std::vector<std::vector<std::size_t>> adj(n);
  nlohmann::json conflicts = nlohmann::json::array();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      std::string why;
      if (crosses_region(i, j))
        why = "transit of " + out.uavs[i].id + " crosses the region of " + out.uavs[j].id;
      else if (crosses_region(j, i))
        why = "transit of " + out.uavs[j].id + " crosses the region of " + out.uavs[i].id;
      else if (transits_cross(i, j))
        why = "transits cross while both fly";
      if (why.empty()) continue;
      adj[i].push_back(j);
      adj[j].push_back(i);
      conflicts.push_back({out.uavs[i].id, out.uavs[j].id, why});
    }
  // DSatur: the uncoloured UAV with the most distinct neighbour colours, then the most neighbours
  std::vector<int> colour(n, -1);
  for (std::size_t step = 0; step < n; ++step) {
    std::size_t pick = n, best_sat = 0, best_deg = 0;
    for (std::size_t v = 0; v < n; ++v) {
      if (colour[v] >= 0) continue;
      std::vector<int> seen;
      for (std::size_t w : adj[v])
        if (colour[w] >= 0 && std::find(seen.begin(), seen.end(), colour[w]) == seen.end())
          seen.push_back(colour[w]);
      if (pick == n || seen.size() > best_sat || (seen.size() == best_sat && adj[v].size() > best_deg)) {
        pick = v;
        best_sat = seen.size();
        best_deg = adj[v].size();
      }
    }
    int c = 0;
    while (std::any_of(adj[pick].begin(), adj[pick].end(), [&](std::size_t w) { return colour[w] == c; }))
      ++c;
    colour[pick] = c;
  }
  std::size_t layers = 0;
  for (int c : colour) layers = std::max(layers, static_cast<std::size_t>(c) + 1);
  waypoints::AltitudeOptions alt;
  bool fits = true;
  try {
    alt = waypoints::resolve_altitudes(alt, layers, out.mission.altitude_m, warnings);
  } catch (const InputError& e) {
    fits = false;
    alt.transition_base_m = waypoints::transition_altitude(alt, 0, out.mission.altitude_m);
    if (warnings != nullptr) warnings->push_back(std::string("transition altitude layers: ") + e.what());
  }
  nlohmann::json layer = nlohmann::json::array();
  for (int c : colour) layer.push_back(c);
  // every pair: [i, j, vertical separation m] (0: the same layer, safe because they do not conflict)
  nlohmann::json pairs = nlohmann::json::array();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      pairs.push_back({i, j, std::fabs(colour[i] - colour[j]) * alt.transition_step_m});
  out.separation = {
      {"rule", "layers"},
      {"layers", layers},
      {"base_m", alt.transition_base_m},
      {"step_m", alt.transition_step_m},
      {"fits_ceiling", fits},
      {"layer", std::move(layer)},
      {"conflicts", std::move(conflicts)},
      {"same_layer_safe_because",
       "no conflict: neither UAV's transit legs cross the other's region, and their transit legs do not "
       "cross while both fly them"},
      {"pairs_format", "[uav index i, uav index j, vertical separation m]"},
      {"pairs", std::move(pairs)}};
  for (std::size_t i = 0; i < n; ++i)
    out.uavs[i].transition_altitude_m =
        waypoints::transition_altitude(alt, static_cast<std::size_t>(colour[i]), out.mission.altitude_m);
}

/// UavPlan::expected_finish_min (issue 32, docs/wind.md): the evaluator's time model for each UAV, eq. 15
/// under the mission's wind (its sorties' batteries), plus eq. 19's battery changes, plus the vertical time
/// of its missions (UavPlan::vertical_time_s).
void set_expected_finish(Plan& out) {
  evaluation::EvaluateOptions eo;
  eo.compute_coverage = false;
  evaluation::Evaluation ev;
  try {
    ev = evaluation::evaluate_plan(out, eo);
  } catch (const InputError& e) {  // the plan stays usable; its finish times are unknown (0)
    out.warnings.push_back(std::string("expected finish times: ") + e.what());
    return;
  }
  // the whole flight (docs/wind.md#the-whole-flight): the climbs and descents of the missions' items, at
  // the export's transition altitudes (no ceiling when the UAVs cannot be separated under it)
  const waypoints::AltitudeOptions alt = waypoints::whole_flight_altitudes(out);
  for (std::size_t i = 0; i < out.uavs.size() && i < ev.cost.uavs.size(); ++i) {
    out.uavs[i].vertical_time_s = waypoints::uav_vertical_time_s(out, i, alt);
    out.uavs[i].expected_finish_min = ev.cost.uavs[i].flight_duration_min +
                                      ev.cost.uavs[i].change_battery_delay_min +
                                      out.uavs[i].vertical_time_s / 60.0;
  }
}

}  // namespace

std::vector<PlannerDescription> available_planners() {
  std::vector<PlannerDescription> out;
  for (const auto& p : planners::registry()) out.push_back({p.name, p.summary, planners::describe(p)});
  return out;
}

namespace {

Plan plan_one(const Mission& mission, const PlanOptions& options, const Context& ctx) {
  const auto t0 = std::chrono::steady_clock::now();
  Plan out;
  out.mission = mission;
  if (options.seed) out.mission.seed = *options.seed;
  if (out.mission.uavs.empty()) throw InputError("uavs", "at least one UAV is needed");
  const planners::PlannerInfo* info = &planners::require(out.mission.planner);
  out.mission.planner_params = planners::validate_params(*info, out.mission.planner_params);
  check_capabilities(*info, out.mission);
  out.planner = info->name;

  engine::LocalMission lm = engine::to_local(out.mission);
  // a structure scan (docs/patterns.md): the footprint grown by half the standoff is a no-fly zone for
  // the planner and the router, so that no transit leg crosses (or grazes) the building
  if (out.mission.structure) {
    lm.no_fly = geometry::unite(planners::structure::keep_out(
        geometry::to_local(out.mission.structure->footprint, lm.frame), *out.mission.structure, lm.no_fly));
    lm.free = geometry::free_space(lm.area, lm.no_fly);
  }
  out.origin = lm.frame.origin();
  out.free_area_m2 = bg::area(lm.free);
  if (lm.free.empty() || out.free_area_m2 <= 0.0)
    throw InputError("no_fly_zones", "the no-fly zones remove the whole area");

  // starts: given, or drawn inside the free area from the seed
  planners::Problem problem;
  problem.area = lm.area;
  problem.no_fly = lm.no_fly;
  problem.free = lm.free;
  problem.spacing_m = out.mission.spacing_m;
  problem.footprint_m = evaluation::footprint_for(out.mission);
  problem.altitude_m = out.mission.altitude_m;
  problem.camera = out.mission.camera;
  problem.mode = out.mission.mode;
  problem.seed = out.mission.seed;
  problem.pattern = out.mission.pattern;
  problem.wind = out.mission.wind;
  if (out.mission.corridor) {
    for (const auto& p : out.mission.corridor->line) problem.corridor_line.push_back(lm.frame.to_local(p));
    problem.corridor_width_m = out.mission.corridor->width_m;
  }
  if (out.mission.structure) {  // docs/patterns.md: the footprint and its keep-out (transit goes around)
    problem.structure = out.mission.structure;
    problem.structure_footprint = geometry::to_local(out.mission.structure->footprint, lm.frame);
  }
  std::mt19937_64 rng(out.mission.seed ^ 0x5eedf00dULL);
  // missing starts: spread over the free area by share (engine/shares.hpp), so that the division can
  // meet the shares; one UAV meets its share from anywhere and keeps the uniform draw
  std::vector<Point> spread;
  if (out.mission.uavs.size() > 1) {
    std::vector<double> shares;
    for (const auto& u : out.mission.uavs) shares.push_back(u.share);
    bool missing = false;
    for (const auto& u : out.mission.uavs) missing |= !u.start;
    if (missing) spread = engine::spread_starts(lm.free, shares, rng);
  }
  for (auto& u : out.mission.uavs) {
    const std::size_t i = problem.starts.size();
    const Point s = u.start          ? lm.frame.to_local(*u.start)
                    : spread.empty() ? engine::random_free_point(lm.free, rng)
                                     : spread[i];
    u.start_resolved = u.start ? *u.start : lm.frame.to_wgs84(s);
    problem.starts.push_back(s);
    problem.shares.push_back(u.share);
    planners::UavFootprint f;
    f.width_m = evaluation::footprint_for(out.mission, problem.uav_footprints.size());
    f.along_m = u.camera_geometry ? u.camera_geometry->along_track_footprint_m
                                  : out.mission.along_track_footprint_m.value_or(f.width_m);
    f.own_camera = u.camera.has_value();
    problem.uav_footprints.push_back(f);
  }
  problem.uavs = out.mission.uavs;

  // a free area in several parts: every UAV's share over the parts, the planner on each part
  engine::test_hold(ctx, "planning", out.mission.name);
  if (ctx.stop_requested()) throw Cancelled();
  // a corridor is planned along its line whole, even where no-fly zones cut it into parts; a structure
  // all round its footprint
  std::optional<planners::Assignment> by_parts =
      problem.corridor_line.empty() && !problem.structure
          ? engine::plan_by_parts(*info, problem, out.mission.planner_params, ctx)
          : std::nullopt;
  const planners::Assignment res =
      by_parts ? std::move(*by_parts) : info->create()->plan(problem, out.mission.planner_params, ctx);
  if (res.uavs.size() != out.mission.uavs.size())
    throw OperationError(fmt::format("planner \"{}\" returned {} UAVs for {}", info->name, res.uavs.size(),
                                     out.mission.uavs.size()));
  out.warnings = res.warnings;
  out.complete = res.complete;
  out.diagnostics = res.diagnostics;
  ctx.report("transit", 0.0);

  auto make_part = [&](PartKind kind, std::vector<Point> pts,
                       const std::vector<std::uint8_t>* off = nullptr) {
    // long segments near the poles get vertices so that GeoJSON's lon/lat edges follow the local ones
    PathPart part{kind, {}, {}, {}};
    part.wgs84 = geometry::to_wgs84_dense(pts, lm.frame, &part.local);
    // the camera-off flags follow their segments into the dense polyline
    if (off != nullptr && std::find(off->begin(), off->end(), 1) != off->end()) {
      std::size_t orig = 0;
      for (std::size_t j = 1; j < part.local.size(); ++j) {
        part.camera_off.push_back(orig < off->size() ? (*off)[orig] : 0);
        if (orig + 1 < pts.size() && part.local[j].x() == pts[orig + 1].x() &&
            part.local[j].y() == pts[orig + 1].y())
          ++orig;
      }
    }
    return part;
  };
  // the planner's attitude of a coverage part (UavAssignment::attitude) on its dense polyline: the headings
  // of the planner's vertices, turned the short way in proportion along a segment at added vertices
  auto dense_attitude = [](const Attitude& a, const std::vector<Point>& pts, const PathPart& part) {
    Attitude out = a;
    if (a.heading_deg.size() != pts.size() || part.local.size() == pts.size()) return out;
    out.heading_deg.clear();
    std::size_t orig = 0;
    for (std::size_t j = 0; j < part.local.size(); ++j) {
      const Point& p = part.local[j];
      if (orig + 1 < pts.size() && p.x() == pts[orig + 1].x() && p.y() == pts[orig + 1].y()) ++orig;
      if (orig + 1 >= pts.size() || (p.x() == pts[orig].x() && p.y() == pts[orig].y())) {
        out.heading_deg.push_back(a.heading_deg[orig]);
        continue;
      }
      const double len = std::hypot(pts[orig + 1].x() - pts[orig].x(), pts[orig + 1].y() - pts[orig].y());
      const double t = len > 0 ? std::hypot(p.x() - pts[orig].x(), p.y() - pts[orig].y()) / len : 0.0;
      const double d = std::remainder(a.heading_deg[orig + 1] - a.heading_deg[orig], 360.0);
      const double h = std::fmod(a.heading_deg[orig] + t * d, 360.0);
      out.heading_deg.push_back(h < 0 ? h + 360.0 : h);
    }
    return out;
  };
  // transition altitudes (Hong et al. 2021 §2.3): the export's rule, under its default ceiling when the
  // UAVs can be separated there
  waypoints::AltitudeOptions altitudes;
  // altitude layers: resolved once the conflict graph is known (assign_layers)
  if (out.mission.transition_altitudes == "layers")
    altitudes.transition_ceiling_m = 0;
  else
    try {
      altitudes = waypoints::resolve_altitudes(altitudes, out.mission.uavs.size(), out.mission.altitude_m,
                                               &out.warnings);
    } catch (const InputError& e) {
      altitudes.transition_ceiling_m = 0;
      out.warnings.push_back(std::string("transition altitudes: ") + e.what());
    }
  // one router for every transit leg: the no-fly zones' R-tree and visibility nodes are built once
  const geometry::Router router(lm.no_fly);
  std::size_t legs_total = 0, legs_done = 0;
  for (const auto& r : res.uavs) legs_total += r.coverage.size() + r.sortie_starts.size() + 1;
  // the planner's sortie boundaries, as indices among each UAV's (non-empty) coverage parts
  sorties::Options sortie_options;
  sortie_options.sortie_starts.resize(out.mission.uavs.size());
  double region_total = 0.0;
  for (const auto& r : res.uavs) region_total += bg::area(r.region);
  for (std::size_t i = 0; i < out.mission.uavs.size(); ++i) {
    if (ctx.stop_requested()) throw Cancelled();
    const auto& u = out.mission.uavs[i];
    const auto& r = res.uavs[i];
    UavPlan up;
    up.id = u.id;
    up.share_requested = u.share;
    up.share_actual = r.share_actual       ? *r.share_actual
                      : region_total > 0.0 ? bg::area(r.region) / region_total
                                           : 0.0;
    up.region_local = r.region;
    up.region = engine::to_wgs84(r.region, lm.frame);
    up.regions = static_cast<int>(r.region.size());
    up.diagnostics = r.diagnostics;
    up.transition_altitude_m = waypoints::transition_altitude(altitudes, i, out.mission.altitude_m);
    Point here = problem.starts[i];
    auto transit_to = [&](Point target) {
      if (ctx.stop_requested()) throw Cancelled();
      ++legs_done;
      if (bg::distance(here, target) < 1e-6) return;
      up.parts.push_back(make_part(PartKind::Transit, router.route(here, target)));
      here = target;
      ctx.report("transit", static_cast<double>(legs_done) / static_cast<double>(legs_total));
    };
    const auto& starts = r.sortie_starts;
    for (std::size_t k = 0; k < starts.size(); ++k)
      if (starts[k] >= r.coverage.size() || (k == 0 ? starts[k] != 0 : starts[k] <= starts[k - 1]))
        throw OperationError(
            fmt::format("planner \"{}\" gave UAV {} sortie starts that are not increasing "
                        "coverage indices from 0",
                        info->name, u.id));
    std::size_t next_start = 0, parts_done = 0;
    bool begins = false;
    for (std::size_t c = 0; c < r.coverage.size(); ++c) {
      const auto& cov = r.coverage[c];
      if (next_start < starts.size() && starts[next_start] == c) {
        ++next_start;
        begins = true;
      }
      if (cov.empty()) continue;
      if (begins) {  // a sortie of the planner's begins: back to the start first
        if (parts_done > 0) transit_to(problem.starts[i]);
        sortie_options.sortie_starts[i].push_back(parts_done);
        begins = false;
      }
      ++parts_done;
      transit_to(cov.front());
      up.parts.push_back(
          make_part(PartKind::Coverage, cov, c < r.camera_off.size() ? &r.camera_off[c] : nullptr));
      if (c < r.attitude.size())
        up.parts.back().attitude = dense_attitude(r.attitude[c], cov, up.parts.back());
      up.coverage_length_m += geometry::length(cov);
      up.turns += static_cast<int>(cov.size());
      here = cov.back();
    }
    transit_to(problem.starts[i]);
    for (const auto& part : up.parts) up.length_m += geometry::length(part.local);
    out.uavs.push_back(std::move(up));
  }
  // battery sorties for every planner (docs/sorties.md)
  ctx.report("sorties", 0.0);
  // a UAV with a leg longer than one battery keeps no sorties, with a warning (docs/sorties.md)
  // (the planner's own boundaries where it gives them)
  sorties::fill_sorties(out, sortie_options, &out.warnings, &router, &ctx);
  // climb and descent limits (issue 31): where the ground is too steep to follow at speed, said
  if (out.mission.terrain && out.mission.terrain->follow() && terrain::grid(out.mission) != nullptr &&
      (out.mission.terrain->max_climb_mps || out.mission.terrain->max_descent_mps ||
       out.mission.terrain->max_grade))
    for (std::size_t i = 0; i < out.uavs.size(); ++i) {
      if (ctx.stop_requested()) throw Cancelled();
      try {
        const auto legs = waypoints::steep_legs(out, i, waypoints::mission_items(out, i));
        for (std::size_t k = 0; k < legs.size() && k < 5; ++k)
          out.warnings.push_back(
              fmt::format("uav '{}': terrain: {}", out.uavs[i].id, waypoints::describe(legs[k], out)));
        if (legs.size() > 5)
          out.warnings.push_back(
              fmt::format("uav '{}': terrain: {} more steep legs", out.uavs[i].id, legs.size() - 5));
      } catch (const InputError&) {
        // altitudes the default options cannot separate: the export says so with its own options
      }
    }
  // rally points (issue 31): the mission's, or the proposal (one per UAV inside its region)
  out.rally = out.mission.rally;
  if (out.mission.propose_rally) out.rally = engine::propose_rally(out, lm.no_fly, lm.frame);
  if (out.mission.transition_altitudes == "layers") assign_layers(out, &out.warnings);
  set_expected_finish(out);
  ctx.report("done", 1.0);
  out.compute_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

Plan plan_in_wind(const Mission& mission, const PlanOptions& options, const Context& ctx);

/// `"planner": "auto"` (docs/planners.md): every planner that supports the mission plans it, under a
/// share of what is left of the time limit; each plan is evaluated by the real evaluator and the best by
/// the objective wins among those whose PoC is at least the best PoC less 0.5 points.
Plan plan_auto(const Mission& mission, const PlanOptions& options, const Context& ctx) {
  constexpr double kPocSlack = 0.005;  // 0.5 percentage points (PoC is a fraction)
  struct Candidate {
    std::string name;
    std::string status;  // "ok", "skipped", "failed"
    std::string reason;
    std::optional<Plan> plan;
    double time_min = 0, poc = 0, length_m = 0, compute_s = 0;
    int turns = 0;
  };
  const auto& all = planners::registry();
  std::vector<Candidate> cands;
  std::vector<std::size_t> runnable;
  for (const auto& info : all) {
    Candidate c;
    c.name = info.name;
    try {
      check_capabilities(info, mission);
      runnable.push_back(cands.size());
      c.status = "pending";
    } catch (const InputError& e) {
      c.status = "skipped";
      c.reason = e.what();
    }
    cands.push_back(std::move(c));
  }
  if (runnable.empty()) throw InputError("planner", "\"auto\": no planner supports this mission");
  const std::string& objective = mission.objective;
  for (std::size_t k = 0; k < runnable.size(); ++k) {
    Candidate& c = cands[runnable[k]];
    if (ctx.stop_requested()) throw Cancelled();
    if (ctx.time_up()) {
      c.status = "skipped";
      c.reason = "the time limit was spent by the planners before it";
      continue;
    }
    const double done = static_cast<double>(k) / static_cast<double>(runnable.size());
    const double step = 1.0 / static_cast<double>(runnable.size());
    // one stage per candidate, its fraction never going back (the run's stages each count from 0)
    auto high = std::make_shared<double>(done);
    Context sub = ctx.with_progress([&ctx, name = c.name, done, step, high](std::string_view, double f) {
      *high = std::max(*high, done + step * std::clamp(f, 0.0, 1.0));
      ctx.report("auto: " + name, *high);
    });
    // an equal share of what is left of the whole limit for this and the planners after it
    if (ctx.deadline()) {
      const auto left = *ctx.deadline() - Context::Clock::now();
      sub = sub.with_time_limit(left / static_cast<long>(runnable.size() - k));
    }
    Mission m = mission;
    m.planner = c.name;
    m.planner_params = nlohmann::json::object();  // each planner's defaults
    try {
      // in wind, a planner with a free sweep direction searches it within its share of the time
      Plan p = plan_in_wind(m, options, sub);
      evaluation::EvaluateOptions eo;
      eo.coverage.context = &sub;
      const evaluation::Evaluation ev = evaluation::evaluate_plan(p, eo);
      c.poc = ev.coverage.total.poc;
      c.turns = ev.coverage.total.turns;
      c.length_m = ev.coverage.total.length_m;
      c.time_min = ev.cost.flight_time_min;
      c.compute_s = p.compute_time_s;
      c.status = "ok";
      c.plan = std::move(p);
    } catch (const Cancelled&) {
      throw;
    } catch (const TimeLimitReached& e) {
      c.status = "failed";
      c.reason = e.what();
    } catch (const InputError& e) {
      c.status = "failed";
      c.reason = e.what();
    } catch (const OperationError& e) {
      c.status = "failed";
      c.reason = e.what();
    }
  }
  double best_poc = -1;
  for (const auto& c : cands)
    if (c.status == "ok") best_poc = std::max(best_poc, c.poc);
  if (best_poc < 0) {
    if (ctx.time_up()) throw TimeLimitReached("\"auto\": no planner finished a plan within the time limit");
    std::string why;
    for (const auto& c : cands) why += (why.empty() ? "" : "; ") + c.name + ": " + c.reason;
    throw InputError("planner", "\"auto\": no planner could plan this mission (" + why + ")");
  }
  auto value = [&](const Candidate& c) {
    if (objective == "poc") return -c.poc;
    if (objective == "turns") return static_cast<double>(c.turns);
    if (objective == "length") return c.length_m;
    return c.time_min;
  };
  const double min_poc = best_poc - kPocSlack;
  std::size_t win = cands.size();
  for (std::size_t i = 0; i < cands.size(); ++i) {
    const auto& c = cands[i];
    if (c.status != "ok" || c.poc < min_poc - 1e-12) continue;
    // ties: the registry's order (deterministic)
    if (win == cands.size() || value(c) < value(cands[win])) win = i;
  }
  auto figures = [](const Candidate& c) {
    return nlohmann::json{{"time_min", c.time_min},
                          {"poc", c.poc},
                          {"turns", c.turns},
                          {"length_m", c.length_m},
                          {"compute_time_s", c.compute_s}};
  };
  nlohmann::json rows = nlohmann::json::array();
  for (std::size_t i = 0; i < cands.size(); ++i) {
    const auto& c = cands[i];
    nlohmann::json r{{"planner", c.name}, {"status", i == win ? "won" : c.status}};
    if (c.status == "ok") {
      r["figures"] = figures(c);
      r["meets_poc_rule"] = c.poc >= min_poc - 1e-12;
      if (i != win)
        r["why_not"] = c.poc < min_poc - 1e-12
                           ? fmt::format("PoC {:.2f} % is below the best {:.2f} % less 0.5 points",
                                         100 * c.poc, 100 * best_poc)
                           : fmt::format("{} {:.4g} is not better than the winner's", objective,
                                         objective == "poc" ? c.poc : value(c));
    } else {
      r["reason"] = c.reason;
    }
    rows.push_back(std::move(r));
  }
  const Candidate& w = cands[win];
  Plan out = std::move(*cands[win].plan);
  out.mission.planner = "auto";  // what was asked; out.planner names the winner
  out.mission.planner_params = nlohmann::json::object();
  const double wv = objective == "poc" ? w.poc : value(w);
  out.selection = {
      {"by", "auto"},
      {"objective", objective},
      {"winner", w.name},
      {"objective_value", wv},
      {"why", fmt::format("best {} ({:.4g}) among the planners whose PoC ({:.2f} % for it) is at least the "
                          "best PoC {:.2f} % less 0.5 points",
                          objective, wv, 100 * w.poc, 100 * best_poc)},
      {"poc_rule", {{"best_poc", best_poc}, {"min_poc", min_poc}, {"slack_points", 0.5}}},
      {"candidates", std::move(rows)}};
  ctx.report("done", 1.0);
  return out;
}

/// The evaluator's flight time of a plan (eq. 17 under the mission's wind), the sum over its UAVs (ties)
/// and its PoC.
struct Figures {
  double time = 0, sum = 0, poc = 0;
};
Figures figures_of(const Plan& p, const Context& ctx) {
  evaluation::EvaluateOptions eo;
  eo.coverage.context = &ctx;
  const evaluation::Evaluation ev = evaluation::evaluate_plan(p, eo);
  Figures f{ev.cost.flight_time_min, 0.0, ev.coverage.total.poc};
  for (const auto& u : ev.cost.uavs) f.sum += u.flight_duration_min;
  return f;
}

/// Sweep direction in wind (issue 32, docs/wind.md): for a planner with an `angle_deg` parameter the
/// mission leaves free, the planner's own choice (fewest turns) and fixed directions (across and along the
/// wind, every 30 degrees) are planned, and the plan with the least flight time in that wind is kept
/// among those whose PoC is at least the planner's own less 0.5 points (ties: the planner's own, then
/// the first). A fixed direction the planner refuses is skipped. Without wind, a corridor, or a given
/// angle: plan_one.
Plan plan_in_wind(const Mission& mission, const PlanOptions& options, const Context& ctx) {
  const planners::PlannerInfo* info = planners::find(mission.planner);
  const bool has_angle =
      info != nullptr && std::any_of(info->params.begin(), info->params.end(),
                                     [](const planners::ParamSpec& p) { return p.name == "angle_deg"; });
  const bool free_angle =
      !mission.planner_params.contains("angle_deg") || mission.planner_params["angle_deg"].is_null();
  if (!mission.wind || !(mission.wind->speed_mps > 0.0) || !has_angle || !free_angle || mission.corridor) {
    return plan_one(mission, options, ctx);
  }
  // bearings of the legs (degrees clockwise from north, modulo 180)
  const double across = std::fmod(mission.wind->from_deg + 90.0, 180.0);
  const double along = std::fmod(mission.wind->from_deg, 180.0);
  std::vector<nlohmann::json> cands{nullptr, across, along};
  for (int d = 0; d < 180; d += 30)
    if (std::fabs(d - across) > 1e-9 && std::fabs(d - along) > 1e-9) cands.emplace_back(d);
  constexpr double kPocSlack = 0.005;  // as "planner": "auto"
  std::optional<Plan> best;
  Figures best_t, own;
  nlohmann::json best_angle, rows = nlohmann::json::array();
  for (std::size_t k = 0; k < cands.size(); ++k) {
    if (best && ctx.time_up()) break;  // the time limit: the best direction so far
    const double done = static_cast<double>(k) / static_cast<double>(cands.size());
    const double step = 1.0 / static_cast<double>(cands.size());
    const Context sub = ctx.with_progress([&ctx, done, step](std::string_view stage, double f) {
      ctx.report(stage, done + step * std::clamp(f, 0.0, 1.0));
    });
    Mission m = mission;
    m.planner_params["angle_deg"] = cands[k];
    std::optional<Plan> planned;
    try {
      planned = plan_one(m, options, sub);
    } catch (const TimeLimitReached&) {
      if (k == 0) throw;
      break;
    } catch (const InputError& e) {
      if (k == 0) throw;
      rows.push_back({{"angle_deg", cands[k]}, {"error", e.what()}});
      continue;
    } catch (const OperationError& e) {
      if (k == 0) throw;
      rows.push_back({{"angle_deg", cands[k]}, {"error", e.what()}});
      continue;
    }
    Plan& p = *planned;
    const Figures t = figures_of(p, sub);
    if (k == 0) own = t;
    const bool covers = t.poc >= own.poc - kPocSlack - 1e-12;
    rows.push_back(
        {{"angle_deg", cands[k]}, {"flight_time_min", t.time}, {"poc", t.poc}, {"meets_poc_rule", covers}});
    if (!covers) continue;
    if (!best || t.time < best_t.time - 1e-9 || (t.time < best_t.time + 1e-9 && t.sum < best_t.sum - 1e-9)) {
      best = std::move(p);
      best_t = t;
      best_angle = cands[k];
    }
  }
  Plan out = std::move(*best);
  out.mission.planner_params = mission.planner_params;  // what was asked: the search is deterministic
  out.diagnostics["wind_sweep"] = {
      {"angle_deg", best_angle},
      {"flight_time_min", best_t.time},
      {"why",
       "the sweep direction with the least flight time in the mission's wind among those whose PoC is "
       "at least the planner's own less 0.5 points (null: the planner's own, fewest turns)"},
      {"candidates", std::move(rows)}};
  return out;
}

/// The planner asked for (auto: every planner), in wind.
Plan plan_dispatch(const Mission& mission, const PlanOptions& options, const Context& ctx) {
  if (mission.planner == "auto") return plan_auto(mission, options, ctx);
  return plan_in_wind(mission, options, ctx);
}

/// Shares from capabilities (issue 32, docs/wind.md): UAVs with share_auto divide what the others leave
/// in proportion to their area rate (speed x line spacing, times the share of a battery cycle spent
/// flying when one battery is not enough), then the shares are corrected from the evaluator's finish
/// times (expected_finish_min) until every auto UAV finishes within 2 % of the others, or 8 plans.
Plan plan_capability_shares(const Mission& mission, const PlanOptions& options, const Context& ctx) {
  constexpr int kRounds = 8;
  constexpr double kSpread = 0.02;
  const std::size_t n = mission.uavs.size();
  std::vector<std::size_t> autos;
  double fixed_sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (mission.uavs[i].share_auto)
      autos.push_back(i);
    else
      fixed_sum += mission.uavs[i].share;
  }
  if (mission.planner != "auto")
    if (const auto* info = planners::find(mission.planner); info != nullptr && !info->supports.shares)
      throw InputError("uavs[" + std::to_string(autos.front()) + "].share",
                       "\"auto\" needs a planner that honours shares; planner \"" + info->name +
                           "\" divides the area equally");
  const double rest = std::max(0.0, 1.0 - fixed_sum);
  // the area rate (m^2 per minute of the mission) of each auto UAV
  const double area = [&] {
    const engine::LocalMission lm = engine::to_local(mission);
    return std::abs(bg::area(lm.free));
  }();
  const evaluation::CostOptions co;
  std::vector<double> rate(n, 0.0);
  double rate_sum = 0.0;
  for (std::size_t i : autos) {
    const Uav& u = mission.uavs[i];
    const double spacing = u.camera_geometry ? u.camera_geometry->spacing_m : mission.spacing_m;
    rate[i] = u.speed_mps * 60.0 * spacing;  // m^2 per minute in the air
    rate_sum += rate[i];
  }
  std::vector<double> share(n);
  for (std::size_t i = 0; i < n; ++i) share[i] = mission.uavs[i].share;
  for (std::size_t i : autos) share[i] = rest * rate[i] / rate_sum;
  // limited by endurance: a UAV whose part outlasts one battery loses the changes' time
  double limited_sum = 0.0;
  for (std::size_t i : autos) {
    const Uav& u = mission.uavs[i];
    const double budget = u.endurance_min * (1.0 - mission.battery_reserve);
    // eq. 19's change: the trip out and back and the change itself
    const double change =
        2.0 * std::sqrt(area) / (3.0 * u.speed_mps * 60.0) + co.battery_change_min * static_cast<double>(n);
    const double air_min = share[i] * area / rate[i];
    if (air_min > budget) rate[i] *= budget / (budget + change);
    limited_sum += rate[i];
  }
  for (std::size_t i : autos) share[i] = rest * rate[i] / limited_sum;

  std::optional<Plan> best;
  double best_spread = 1e300;
  nlohmann::json rounds = nlohmann::json::array();
  std::vector<double> prev_share(n, 0.0), prev_t(n, 0.0);
  for (int round = 0; round < kRounds; ++round) {
    if (best && ctx.should_stop()) break;
    Mission m = mission;
    for (std::size_t i = 0; i < n; ++i) m.uavs[i].share = share[i];
    // the sweep direction in wind is chosen again in every round (the best direction depends on the part)
    Plan p = plan_dispatch(m, options, ctx);
    std::vector<double> t(n, 0.0);
    double lo = 1e300, hi = 0.0;
    for (std::size_t i : autos) {
      t[i] = p.uavs[i].expected_finish_min;
      lo = std::min(lo, t[i]);
      hi = std::max(hi, t[i]);
    }
    const double spread = hi > 0.0 ? (hi - lo) / hi : 0.0;
    nlohmann::json finish = nlohmann::json::array(), shares_j = nlohmann::json::array();
    for (std::size_t i : autos) {
      finish.push_back(p.uavs[i].expected_finish_min);
      shares_j.push_back(share[i]);
    }
    rounds.push_back(
        {{"shares", std::move(shares_j)}, {"expected_finish_min", std::move(finish)}, {"spread", spread}});
    if (spread < best_spread) {
      best_spread = spread;
      best = std::move(p);
    }
    if (spread <= kSpread) break;
    // a UAV left without work (the planner's division): no rate to correct from
    if (std::any_of(autos.begin(), autos.end(), [&](std::size_t i) { return !(t[i] > 0.0); })) break;
    // the next shares: each UAV's finish time as a line in its share, through the last two rounds
    // (secant) when they give a rising one, else through the origin (its achieved rate); the common
    // finish time T at which the lines' shares add up to `rest`, each step at most x3 either way
    double inv_sum = 0.0, base = 0.0;
    std::vector<double> slope(n, 0.0);
    for (std::size_t i : autos) {
      double k = share[i] > 0.0 ? t[i] / share[i] : 0.0;
      if (round > 0 && std::fabs(share[i] - prev_share[i]) > 1e-6 * rest) {
        const double secant = (t[i] - prev_t[i]) / (share[i] - prev_share[i]);
        if (secant > 0.0) k = secant;
      }
      if (!(k > 0.0)) k = 1.0;
      slope[i] = k;
      inv_sum += 1.0 / k;
      base += share[i] - t[i] / k;
    }
    const double target = (rest - base) / inv_sum;
    prev_share = share;
    prev_t = t;
    double sum = 0.0;
    for (std::size_t i : autos) {
      share[i] = std::clamp(share[i] + (target - t[i]) / slope[i], share[i] / 3.0, share[i] * 3.0);
      sum += share[i];
    }
    if (!(sum > 0.0)) break;
    for (std::size_t i : autos) share[i] *= rest / sum;
  }
  Plan out = std::move(*best);
  nlohmann::json ids = nlohmann::json::array();
  for (std::size_t i : autos) ids.push_back(mission.uavs[i].id);
  out.diagnostics["capability_shares"] = {
      {"uavs", std::move(ids)},
      {"spread", best_spread},
      {"why",
       "shares in proportion to each UAV's area rate (speed x line spacing, less the battery changes "
       "when one battery is not enough), corrected from the finish times until they agree within 2 %"},
      {"rounds", std::move(rounds)}};
  return out;
}

}  // namespace

Plan plan(const Mission& mission, const PlanOptions& options, const Context& ctx) {
  if (std::any_of(mission.uavs.begin(), mission.uavs.end(), [](const Uav& u) { return u.share_auto; }))
    return plan_capability_shares(mission, options, ctx);
  return plan_dispatch(mission, options, ctx);
}

}  // namespace uavcover
