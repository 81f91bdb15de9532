// Reassignment of a failed UAV's remaining coverage (docs/flights.md, "Reassignment"): the failed UAV's
// region minus the footprint its coverage swept up to the last reached waypoint (the evaluator's square
// footprint of its own camera, Boost.Geometry buffer and difference), re-planned as a sub-mission with the
// mission's planner over the helpers, cut into battery sorties by plan(), exported as mission items at each
// helper's own transition altitude of the full plan.
#include "flight/reassign.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string_view>

#include "evaluation/evaluate.hpp"
#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "geometry/millimetres.hpp"
#include "sorties/sorties.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover::flight {

namespace {

using MultiLinestring = bg::model::multi_linestring<Polyline>;

void validate(const Plan& plan, std::size_t failed, const std::vector<Helper>& helpers) {
  if (plan.uavs.size() != plan.mission.uavs.size())
    throw InputError("plan.uavs", "the plan and its mission name different numbers of UAVs");
  if (failed >= plan.uavs.size())
    throw InputError("failed", fmt::format("must be a UAV index in [0, {}]", plan.uavs.size() - 1));
  if (helpers.empty()) throw InputError("helpers", "at least one UAV still flying is needed");
  std::set<std::size_t> seen;
  for (std::size_t k = 0; k < helpers.size(); ++k) {
    const Helper& h = helpers[k];
    const std::string field = fmt::format("helpers[{}]", k);
    if (h.index >= plan.uavs.size())
      throw InputError(field + ".index", fmt::format("must be a UAV index in [0, {}]", plan.uavs.size() - 1));
    if (h.index == failed) throw InputError(field + ".index", "the failed UAV cannot help itself");
    if (!seen.insert(h.index).second) throw InputError(field + ".index", "each UAV may help once");
    if (!std::isfinite(h.battery_fraction) || h.battery_fraction <= 0.0 || h.battery_fraction > 1.0)
      throw InputError(field + ".battery_fraction", "must be in (0, 1]");
    if (h.depot && !(std::abs(h.depot->lon) <= 180.0 && std::abs(h.depot->lat) <= 90.0))
      throw InputError(field + ".depot", "must be a position (lon in [-180, 180], lat in [-90, 90])");
  }
}

void check_last_reached(const UavPlan& up, int n, int last_reached) {
  if (last_reached < -1 || last_reached > n - 1)
    throw InputError("last_reached", fmt::format("must be in [-1, {}] for UAV \"{}\" ({} coverage waypoints)",
                                                 n - 1, up.id, n));
}

/// The coverage legs flown up to global waypoint `last_reached` (inclusive), as 2-point lines.
MultiLinestring flown_legs(const UavPlan& up, const std::vector<sorties::WaypointRef>& wps,
                           int last_reached) {
  MultiLinestring legs;
  for (int g = 1; g <= last_reached; ++g) {
    const auto& a = wps[static_cast<std::size_t>(g - 1)];
    const auto& b = wps[static_cast<std::size_t>(g)];
    if (a.part != b.part) continue;  // a transit joins the two coverage parts
    const auto& pts = up.parts[b.part].local;
    Polyline leg{pts[a.vertex], pts[b.vertex]};
    if (bg::distance(leg.front(), leg.back()) > 1e-9) legs.push_back(std::move(leg));
  }
  return legs;
}

// The swept area and the difference are computed on integer millimetres (geometry/millimetres.hpp):
// Boost.Geometry 1.74's union on doubles lost whole footprint rectangles.
using geometry::from_mm;
using geometry::MmMultiPolygon;
using geometry::MmPolygon;
using geometry::to_mm;

/// Union of polygons [lo, hi), halves first (each polygon takes part in O(log n) unions).
MmMultiPolygon unite_mm(const std::vector<MmPolygon>& polys, std::size_t lo, std::size_t hi,
                        const Context& ctx) {
  if (hi - lo == 1) return {polys[lo]};
  const std::size_t mid = lo + (hi - lo) / 2;
  const MmMultiPolygon a = unite_mm(polys, lo, mid, ctx);
  const MmMultiPolygon b = unite_mm(polys, mid, hi, ctx);
  ctx.check();
  MmMultiPolygon out;
  bg::union_(a, b, out);
  return out;
}

/// What the evaluator counts as scanned by those legs (src/evaluation/coverage.hpp): a square
/// footprint of width w swept along each straight leg, w/2 beyond each end, i.e. one rectangle per leg.
MmMultiPolygon swept_area(const MultiLinestring& legs, double w, const Context& ctx) {
  std::vector<MmPolygon> rects;
  for (const auto& leg : legs) {
    const Point a = leg.front(), b = leg.back();
    const double len = bg::distance(a, b);
    const double ux = (b.x() - a.x()) / len * w / 2.0, uy = (b.y() - a.y()) / len * w / 2.0;
    MmPolygon r;
    r.outer() = {
        to_mm(Point(a.x() - ux - uy, a.y() - uy + ux)), to_mm(Point(b.x() + ux - uy, b.y() + uy + ux)),
        to_mm(Point(b.x() + ux + uy, b.y() + uy - ux)), to_mm(Point(a.x() - ux + uy, a.y() - uy - ux))};
    r.outer().push_back(r.outer().front());
    bg::correct(r);
    rects.push_back(std::move(r));
  }
  if (rects.empty()) return {};
  return unite_mm(rects, 0, rects.size(), ctx);
}

/// GeoJSON polygons (counter-clockwise outer rings, clockwise holes) of local polygons.
std::vector<GeoPolygon> to_geo(const MultiPolygon& mp, const geodesy::LocalFrame& frame) {
  std::vector<GeoPolygon> out;
  auto ring_of = [&](const auto& ring) {
    GeoRing r = geometry::to_wgs84_dense(std::vector<Point>(ring.begin(), ring.end()), frame);
    std::reverse(r.begin(), r.end());  // Boost's rings turn the other way
    return r;
  };
  for (const auto& poly : mp) {
    GeoPolygon gp{ring_of(poly.outer())};
    for (const auto& inner : poly.inners()) gp.push_back(ring_of(inner));
    out.push_back(std::move(gp));
  }
  return out;
}

/// The parts again with local coordinates in `frame` (the full plan's), from their WGS84 vertices.
std::vector<PathPart> in_frame(std::vector<PathPart> parts, const geodesy::LocalFrame& frame) {
  for (auto& part : parts) {
    part.local.clear();
    for (const auto& p : part.wgs84) part.local.push_back(frame.to_local(p));
  }
  return parts;
}

/// The area re-planned. The planners keep paths inside the area (strict mode) on a grid or lattice
/// of it, so a remainder made of strips one or two cells wide would lose its edges (measured on the
/// olive grove: 53 % of bravo's remainder covered when planned as it is). A path within w/2 of the
/// remainder still scans it, so the remainder is grown by w/2 (round joins), within the mission's free
/// area: 94 % covered there. With heterogeneous cameras w is the largest helper's own footprint, so that
/// the widest-seeing helper's paths reach the edges too.
MultiPolygon planned_area(const Plan& plan, const std::vector<Helper>& helpers, const MultiPolygon& rest,
                          const geodesy::LocalFrame& frame) {
  double w = 0.0;
  for (const auto& h : helpers) w = std::max(w, evaluation::footprint_for(plan.mission, h.index));
  const double grow = w / 2.0;
  MultiPolygon grown;
  bg::buffer(rest, grown, bg::strategy::buffer::distance_symmetric<double>(grow),
             bg::strategy::buffer::side_straight(), bg::strategy::buffer::join_round(16),
             bg::strategy::buffer::end_flat(), bg::strategy::buffer::point_square());
  if (!(bg::area(grown) >= bg::area(rest))) return rest;  // a failed buffer: the remainder as it is
  return geometry::intersection_mm(grown, evaluation::free_area(plan.mission, frame));
}

}  // namespace

MultiPolygon remainder_area(const Plan& plan, std::size_t failed, int last_reached, const Context& ctx) {
  if (failed >= plan.uavs.size())
    throw InputError("failed", fmt::format("must be a UAV index below {}", plan.uavs.size()));
  const UavPlan& up = plan.uavs[failed];
  const auto wps = sorties::coverage_waypoints(up);
  const int n = static_cast<int>(wps.size());
  check_last_reached(up, n, last_reached);
  MultiPolygon rest;
  if (last_reached >= n - 1) return rest;  // everything flown
  // what it scanned: its own camera's footprint (uavs[failed].camera), else the mission's
  const double w = evaluation::footprint_for(plan.mission, failed);
  const MmMultiPolygon swept = swept_area(flown_legs(up, wps, last_reached), w, ctx);
  if (swept.empty()) {
    rest = up.region_local;
  } else {
    MmMultiPolygon rest_mm;
    bg::difference(to_mm(up.region_local), swept, rest_mm);
    rest = from_mm(rest_mm);
  }
  // slivers along the swept edge and pieces smaller than one footprint square are not worth a flight
  std::erase_if(rest, [&](const Polygon& p) { return std::abs(bg::area(p)) < w * w; });
  return rest;
}

Reassignment reassign(const Plan& plan, std::size_t failed, int last_reached,
                      const std::vector<Helper>& helpers, const waypoints::AltitudeOptions& altitude,
                      const Context& ctx) {
  validate(plan, failed, helpers);
  const UavPlan& up = plan.uavs[failed];
  const int n = static_cast<int>(sorties::coverage_waypoints(up).size());
  check_last_reached(up, n, last_reached);
  // the helpers' transition altitudes in the full plan (InputError "altitude.*" when they cannot be had)
  const waypoints::AltitudeOptions resolved =
      waypoints::resolve_altitudes(altitude, waypoints::altitude_slots(plan), plan.mission.altitude_m);

  Reassignment out;
  out.failed_uav = up.id;
  out.last_reached = last_reached;
  for (int g = last_reached + 1; g < n; ++g) out.remaining_waypoints.push_back(g);
  ctx.report("reassign", 0.0);
  ctx.check();

  const geodesy::LocalFrame frame(plan.origin);
  const MultiPolygon rest = remainder_area(plan, failed, last_reached, ctx);
  ctx.check();
  if (rest.empty()) {
    if (!out.remaining_waypoints.empty())
      out.warnings.push_back(
          fmt::format("UAV \"{}\": what its {} remaining waypoints would cover is already "
                      "covered up to pieces smaller than one footprint square",
                      up.id, out.remaining_waypoints.size()));
    ctx.report("reassign", 1.0);
    return out;
  }
  out.area = to_geo(rest, frame);
  out.area_m2 = std::abs(bg::area(rest));

  // the sub-mission: the remainder, the same no-fly zones, sensor, planner and seed, over the helpers
  // (each with its own camera, uavs[i].camera, which plan() passes to the planner and the evaluator)
  const MultiPolygon planned = planned_area(plan, helpers, rest, frame);
  Mission sub = plan.mission;
  sub.name = plan.mission.name + " (reassigned from " + up.id + ")";
  sub.area = to_geo(planned, frame);
  sub.planner = plan.planner;
  sub.uavs.clear();
  double total = 0.0;
  for (const auto& h : helpers) total += h.battery_fraction;
  for (const auto& h : helpers) {
    Uav u = plan.mission.uavs[h.index];
    // from the air: out from where it is, on the battery it has left
    u.start = h.depot.value_or(u.start_resolved);
    if (h.depot) u.endurance_min *= h.battery_fraction;
    u.share = h.battery_fraction / total;
    sub.uavs.push_back(std::move(u));
  }
  const Context sub_ctx = ctx.with_progress(
      [&ctx](std::string_view stage, double f) { ctx.report(fmt::format("reassign/{}", stage), f); });
  Plan sp;
  try {
    sp = uavcover::plan(sub, {}, sub_ctx);
  } catch (const InputError& e) {
    throw InputError("failed", fmt::format("the remainder of UAV \"{}\" ({:.0f} m2 in {} pieces) cannot be "
                                           "planned with planner \"{}\": {}",
                                           up.id, out.area_m2, rest.size(), plan.planner, e.what()));
  }
  for (const auto& wmsg : sp.warnings) out.warnings.push_back("re-plan: " + wmsg);

  for (std::size_t j = 0; j < helpers.size(); ++j) {
    ctx.check();
    const UavPlan& hp = sp.uavs[j];
    if (hp.turns == 0) continue;
    const std::size_t index = helpers[j].index;
    ReassignedWork work;
    work.uav = hp.id;
    work.index = index;
    work.parts = in_frame(hp.parts, frame);
    work.coverage_length_m = hp.coverage_length_m;
    work.waypoints = static_cast<int>(sorties::coverage_waypoints(hp).size());
    // one mission per sortie, flown at the helper's transition altitude of the full plan
    waypoints::AltitudeOptions own = altitude;
    own.transition_base_m = waypoints::transition_altitude(resolved, waypoints::altitude_slot(plan, index),
                                                           plan.mission.altitude_m);
    std::vector<Sortie> sorties = hp.sorties;
    if (sorties.empty()) {  // a leg longer than one battery (plan() warned): one mission of it all
      Sortie whole;
      whole.first_waypoint = 0;
      whole.last_waypoint = work.waypoints - 1;
      whole.parts = hp.parts;
      whole.length_m = hp.length_m;
      whole.turns = work.waypoints;
      sorties.push_back(std::move(whole));
    }
    for (const auto& s : sorties) {
      Plan one = sorties::sortie_plan(sp, j, s);
      one.uavs = {one.uavs[j]};
      one.mission.uavs = {one.mission.uavs[j]};
      // from the air, only the first mission starts at the depot: the later ones take off from home
      if (&s != &sorties.front())
        one.mission.uavs[0].start_resolved = plan.mission.uavs[index].start_resolved;
      auto items = waypoints::mission_items(one, 0, own);
      for (auto& it : items)
        if (it.waypoint >= 0) it.waypoint += s.first_waypoint;
      work.missions.push_back(std::move(items));
    }
    for (const auto& s : hp.sorties) {
      Sortie local = s;
      local.parts = in_frame(s.parts, frame);
      work.sorties.push_back(std::move(local));
    }
    out.work.push_back(std::move(work));
    ctx.report("reassign", static_cast<double>(j + 1) / static_cast<double>(helpers.size()));
  }
  ctx.report("reassign", 1.0);
  return out;
}

}  // namespace uavcover::flight
