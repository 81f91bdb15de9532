#include "planners/boustrophedon/boustrophedon.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "geometry/geometry.hpp"
#include "photo/oblique.hpp"
#include "planners/boustrophedon/decomposition.hpp"
#include "planners/boustrophedon/division.hpp"
#include "planners/boustrophedon/ordering.hpp"
#include "planners/boustrophedon/sweep.hpp"
#include "planners/corridor/corridor.hpp"
#include "planners/structure/structure.hpp"
#include "uavcover/error.hpp"

namespace uavcover::planners {

namespace {

using namespace boustro;

constexpr double kPi = std::numbers::pi;
constexpr const char* kStage = "boustrophedon";

/// Bearing (degrees clockwise from north) <-> direction (radians counter-clockwise from east).
double from_bearing(double deg) { return kPi / 2 - deg * kPi / 180.0; }
double to_bearing(double rad) {
  double b = 90.0 - rad * 180.0 / kPi;
  b = std::fmod(b, 180.0);
  if (b < 0) b += 180.0;
  return std::round(b * 1e6) / 1e6;
}

/// A decomposition direction and the sweep of each of its cells.
struct Layout {
  double angle = 0.0;
  std::vector<CellSweep> sweeps;
  int legs = 0;
  double score = std::numeric_limits<double>::infinity();
};

std::vector<double> candidate_angles(const MultiPolygon& region, std::optional<double> fixed) {
  if (fixed) return {*fixed};
  std::vector<double> a;
  auto add_ring = [&](const Ring& r) {
    for (std::size_t i = 1; i < r.size(); ++i) {
      const double dx = r[i].x() - r[i - 1].x(), dy = r[i].y() - r[i - 1].y();
      if (std::hypot(dx, dy) < 1e-6) continue;
      double t = std::fmod(std::atan2(dy, dx), kPi);
      if (t < 0) t += kPi;
      a.push_back(t);
    }
  };
  for (const auto& p : region) {
    add_ring(p.outer());
    for (const auto& in : p.inners()) add_ring(in);
  }
  for (int d = 0; d < 180; d += 5) a.push_back(d * kPi / 180.0);
  std::sort(a.begin(), a.end());
  std::vector<double> out;
  for (double t : a)
    if (out.empty() || t - out.back() > 1e-6) out.push_back(t);
  if (out.size() > 1 && out.back() - out.front() > kPi - 1e-6) out.pop_back();
  return out;
}

/// Turns (two per leg) first, then one per cell (a transit each).
double cell_cost(int legs, std::size_t cells) { return 2.0 * legs + static_cast<double>(cells); }

/// Cuts a cell at some of its reflex lines where sweeping the sides separately needs fewer turns
/// (e.g. the two arms of an L): dynamic programming over the groups of consecutive pieces.
std::vector<CellSweep> partition(const Monotone& cell, const std::vector<double>& cuts, const Frame& frame,
                                 double angle, double spacing, std::optional<double> fixed) {
  std::vector<double> b{cell.xmin()};
  for (double x : cuts)
    if (x > b.back() + 1e-6 && x < cell.xmax() - 1e-6) b.push_back(x);
  b.push_back(cell.xmax());
  const std::size_t pieces = b.size() - 1;
  if (pieces == 1) return {choose_direction(cell, frame, angle, spacing, fixed)};
  auto allowed = [&](std::size_t i, std::size_t j) { return j - i <= 6 || (i == 0 && j == pieces); };
  std::vector<double> best(pieces + 1, std::numeric_limits<double>::infinity());
  std::vector<std::size_t> from(pieces + 1, 0);
  best[0] = 0.0;
  std::vector<std::vector<std::optional<CellSweep>>> memo(pieces + 1,
                                                          std::vector<std::optional<CellSweep>>(pieces + 1));
  for (std::size_t j = 1; j <= pieces; ++j)
    for (std::size_t i = 0; i < j; ++i) {
      if (!allowed(i, j) || !std::isfinite(best[i])) continue;
      auto s = choose_direction(i == 0 && j == pieces ? cell : clip(cell, b[i], b[j]), frame, angle, spacing,
                                fixed);
      const double c = best[i] + cell_cost(s.legs, 1);
      if (c < best[j] - 1e-9) {
        best[j] = c;
        from[j] = i;
      }
      memo[i][j] = std::move(s);
    }
  std::vector<CellSweep> out;
  for (std::size_t j = pieces; j > 0; j = from[j]) out.push_back(*memo[from[j]][j]);
  std::reverse(out.begin(), out.end());
  return out;
}

/// The decomposition direction whose cells, each swept its own best way, need the fewest legs.
Layout best_layout(const MultiPolygon& region, double spacing, std::optional<double> fixed,
                   const Context& ctx, double f0, double f1) {
  const std::vector<double> cands = candidate_angles(region, fixed);
  const double region_area = bg::area(region);
  Layout best;
  for (std::size_t i = 0; i < cands.size(); ++i) {
    ctx.check();
    ctx.report(kStage, f0 + (f1 - f0) * static_cast<double>(i) / static_cast<double>(cands.size()));
    Layout l;
    l.angle = cands[i];
    Decomposition dec = decompose(region, Frame(l.angle), ctx, true);
    double covered = 0.0;
    for (const auto& c : dec.cells) covered += area(c);
    // an edge exactly along the sweep (a division cut at the fixed angle) can make the decomposition lose
    // the region: the same direction nudged by a microradian, invisible in the legs, decomposes it
    for (const double nudge : {1e-6, -1e-6}) {
      if (covered >= (1.0 - 1e-6) * region_area) break;
      Decomposition again = decompose(region, Frame(cands[i] + nudge), ctx, true);
      double c2 = 0.0;
      for (const auto& c : again.cells) c2 += area(c);
      if (c2 > covered) {
        covered = c2;
        dec = std::move(again);
        l.angle = cands[i] + nudge;
      }
    }
    const Frame frame(l.angle);
    // a decomposition that lost a piece (a failed overlay) ranks after every complete one
    const double lost = covered < (1.0 - 1e-6) * region_area ? 1e9 + region_area - covered : 0.0;
    for (std::size_t c = 0; c < dec.cells.size(); ++c) {
      // cells too small to matter (below 1e-4 of a spacing squared) are dropped
      if (area(dec.cells[c]) < 1e-4 * spacing * spacing) continue;
      for (auto& s : partition(dec.cells[c], dec.cuts[c], frame, l.angle, spacing, fixed)) {
        l.legs += s.legs;
        l.sweeps.push_back(std::move(s));
      }
    }
    l.score = cell_cost(l.legs, l.sweeps.size()) + lost;
    if (l.score < best.score - 1e-9) best = std::move(l);
  }
  return best;
}

MultiPolygon drop_slivers(MultiPolygon m, double min_area) {
  std::erase_if(m, [&](const Polygon& p) { return std::abs(bg::area(p)) < min_area; });
  return m;
}

/// The region less a thin band along the other UAVs' regions, so that paths of different UAVs
/// never touch along a shared border.
MultiPolygon inset_against(const MultiPolygon& region, const MultiPolygon& others, double eps) {
  if (others.empty() || region.empty()) return region;
  MultiPolygon o = others;
  remove_near_duplicates(o);
  MultiPolygon grown;
  bg::strategy::buffer::distance_symmetric<double> distance(eps);
  bg::strategy::buffer::side_straight side;
  bg::strategy::buffer::join_miter join;
  bg::strategy::buffer::end_flat end;
  bg::strategy::buffer::point_square point;
  bg::buffer(o, grown, distance, side, join, end, point);
  MultiPolygon out;
  bg::difference(region, grown, out);
  remove_near_duplicates(out);
  return out;
}

/// The region swept along the vector v (the Minkowski sum of the region and the segment 0-v): the region,
/// its copy moved by v, and the band each edge sweeps between them.
MultiPolygon swept_along(const MultiPolygon& region, Point v) {
  MultiPolygon pieces;
  const double len = std::hypot(v.x(), v.y());
  auto moved = [&](const Polygon& poly) {
    Polygon out;
    for (const auto& q : poly.outer()) out.outer().push_back(Point{q.x() + v.x(), q.y() + v.y()});
    for (const auto& in : poly.inners()) {
      out.inners().emplace_back();
      for (const auto& q : in) out.inners().back().push_back(Point{q.x() + v.x(), q.y() + v.y()});
    }
    return out;
  };
  auto bands = [&](const Ring& r) {
    for (std::size_t i = 1; i < r.size(); ++i) {
      const Point a = r[i - 1], b = r[i];
      const double cross = (b.x() - a.x()) * v.y() - (b.y() - a.y()) * v.x();
      // an edge (nearly) along v sweeps a band under 1 cm wide: the region and its copy cover it, and
      // such slivers make the overlay fail
      if (std::abs(cross) < 0.01 * len) continue;
      Polygon band;
      band.outer() = {a, b, Point{b.x() + v.x(), b.y() + v.y()}, Point{a.x() + v.x(), a.y() + v.y()}, a};
      bg::correct(band);
      pieces.push_back(std::move(band));
    }
  };
  for (const auto& poly : region) {
    pieces.push_back(poly);
    pieces.push_back(moved(poly));
    bands(poly.outer());
  }
  MultiPolygon out = geometry::unite(pieces);
  // a failed overlay (it loses area): the convex hull of the region and its copy, which holds the sum
  if (!bg::is_valid(out) || bg::area(out) < 0.999 * bg::area(region)) {
    MultiPolygon both = region;
    for (const auto& poly : region) both.push_back(moved(poly));
    Polygon hull;
    bg::convex_hull(both, hull);
    out = {hull};
  }
  return out;
}

/// Clearance kept from no-fly zones: legs that end at a no-fly zone's edge end this far from it, so
/// that no waypoint lies on (and, after rounding to WGS84, inside) an exclusion polygon.
constexpr double kNoFlyClearanceM = 0.5;
/// The most (separate) no-fly zones it plans around.
constexpr std::size_t kMaxNoFlyZones = 64;

class BoustrophedonPlanner final : public Planner {
 public:
  [[nodiscard]] Assignment plan(const Problem& problem, const nlohmann::json& params,
                                const Context& ctx) const override {
    if (!problem.corridor_line.empty()) return corridor::plan(problem, ctx);
    if (problem.structure) return structure::plan(problem, ctx);
    // its cell decomposition grows with the square of the zones (50 zones: 6 s, 100: 25 s): refuse
    // what it cannot plan in seconds rather than hang
    if (problem.no_fly.size() > kMaxNoFlyZones)
      throw InputError("no_fly_zones",
                       "the boustrophedon planner plans around at most " + std::to_string(kMaxNoFlyZones) +
                           " no-fly zones, this mission has " + std::to_string(problem.no_fly.size()) +
                           ": use the darp planner or merge nearby zones");
    if (problem.no_fly.empty()) return plan_with_clearance(problem, params, ctx);
    Problem q = problem;
    MultiPolygon zones = problem.no_fly;
    remove_near_duplicates(zones);
    bg::strategy::buffer::distance_symmetric<double> distance(kNoFlyClearanceM);
    bg::strategy::buffer::side_straight side;
    bg::strategy::buffer::join_miter join;
    bg::strategy::buffer::end_flat end;
    bg::strategy::buffer::point_square point;
    MultiPolygon grown;
    bg::buffer(zones, grown, distance, side, join, end, point);
    if (grown.empty()) return plan_with_clearance(problem, params, ctx);
    q.no_fly = grown;
    q.free.clear();
    bg::difference(problem.free, grown, q.free);
    remove_near_duplicates(q.free);
    return plan_with_clearance(q, params, ctx);
  }

 private:
  static Assignment plan_with_clearance(const Problem& p, const nlohmann::json& params, const Context& ctx) {
    ctx.check();
    const std::size_t n = p.starts.size();
    if (n == 0) throw InputError("uavs", "at least one UAV is needed");
    if (p.shares.size() != n) throw InputError("uavs", "one share per UAV is needed");
    if (!(p.spacing_m > 0.0) || !std::isfinite(p.spacing_m))
      throw InputError("spacing_m", "the line spacing must be a positive number of metres");
    const double footprint = p.footprint_m > 0.0 ? p.footprint_m : 1.5 * p.spacing_m;
    std::optional<double> fixed;
    if (params.is_object() && params.contains("angle_deg") && params["angle_deg"].is_number())
      fixed = std::fmod(from_bearing(params["angle_deg"].get<double>()) + 4 * kPi, kPi);

    Assignment out;
    out.uavs.resize(n);
    const double free_area = bg::area(p.free);
    if (p.free.empty() || !(free_area > 0.0)) return out;
    ctx.report(kStage, 0.0);

    // division among the UAVs
    std::vector<MultiPolygon> regions(n);
    // the oblique passes' headings (docs/patterns.md "Obliques"): the same for every UAV, from the legs'
    // direction given, else the division's, else (one UAV) its own decomposition's
    std::optional<double> heading_ref = fixed;
    if (n == 1) {
      regions[0] = p.free;
    } else {
      // strips along the legs of the largest cell of the whole area's best layout
      const Layout whole = best_layout(p.free, p.spacing_m, fixed, ctx, 0.0, 0.1);
      double angle = whole.angle, largest = -1.0;
      for (const auto& s : whole.sweeps)
        if (area(s.mono) > largest) largest = area(s.mono), angle = s.angle;
      const Division div = divide(p.free, p.shares, p.starts, angle, p.spacing_m, ctx);
      regions = div.regions;
      out.diagnostics["division_angle_deg"] = to_bearing(angle);
      if (!heading_ref) heading_ref = angle;
      out.diagnostics["division_pieces"] = div.pieces;
      out.diagnostics["division_split_failures"] = div.split_failures;
    }
    ctx.report(kStage, 0.2);

    Surroundings env;
    env.area = &p.area;
    env.no_fly = &p.no_fly;
    env.stops.add(p.area);
    env.stops.add(p.no_fly);
    env.no_fly_edges.add(p.no_fly);
    SweepOptions opt{p.spacing_m, footprint, p.mode, n == 1};
    opt.pattern = p.pattern ? &*p.pattern : nullptr;

    const double eps = std::min(0.1, 0.01 * p.spacing_m);  // gap between UAVs' paths along borders
    for (std::size_t k = 0; k < n; ++k) {
      const double f0 = 0.2 + 0.8 * static_cast<double>(k) / static_cast<double>(n);
      const double f1 = 0.2 + 0.8 * static_cast<double>(k + 1) / static_cast<double>(n);
      auto& ua = out.uavs[k];
      ua.region = regions[k];
      ua.share_actual = bg::area(regions[k]) / free_area;
      if (regions[k].empty()) continue;
      if (p.free.size() == 1 && regions[k].size() > 1)
        out.warnings.push_back("uavs[" + std::to_string(k) + "]: its region is in " +
                               std::to_string(regions[k].size()) + " parts");
      MultiPolygon others;
      for (std::size_t j = 0; j < n; ++j)
        if (j != k)
          for (const auto& poly : regions[j]) others.push_back(poly);
      const MultiPolygon planned =
          n == 1 ? regions[k] : drop_slivers(inset_against(regions[k], others, eps), 1e-3 * p.spacing_m);
      env.others = p.mode == Mode::Coverage && n > 1 ? &others : nullptr;

      const Layout lay = best_layout(planned, p.spacing_m, fixed, ctx, f0, f0 + 0.6 * (f1 - f0));
      // crosshatch (docs/patterns.md): a second sweep of the same part, every cell at 90 degrees to the first
      std::optional<Layout> cross;
      if (p.pattern && p.pattern->crosshatch)
        cross = best_layout(planned, p.spacing_m, std::fmod(lay.angle + kPi / 2, kPi), ctx, f0, f0);
      std::vector<std::array<std::vector<Point>, 2>> paths;
      std::vector<std::array<std::vector<std::uint8_t>, 2>> flags;
      std::vector<CellEnds> ends;
      nlohmann::json cells = nlohmann::json::array();
      int legs = 0;
      std::vector<const CellSweep*> sweeps;
      for (const auto& s : lay.sweeps) sweeps.push_back(&s);
      const std::size_t first_sweep = sweeps.size();
      if (cross)
        for (const auto& s : cross->sweeps) sweeps.push_back(&s);
      std::vector<std::size_t> second;  // indices into paths of the second sweep's cells
      for (std::size_t c = 0; c < sweeps.size(); ++c) {
        ctx.check();
        flags.emplace_back();
        paths.push_back(lawnmower(*sweeps[c], opt, env, ctx, &flags.back()));
        const auto& pa = paths.back();
        if (pa[0].empty() || pa[1].empty()) {
          paths.pop_back();
          flags.pop_back();
          continue;
        }
        if (c >= first_sweep) {
          second.push_back(paths.size() - 1);
          continue;
        }
        CellEnds e;
        e.entry = {pa[0].front(), pa[0].back(), pa[1].front(), pa[1].back()};
        e.exit = {pa[0].back(), pa[0].front(), pa[1].back(), pa[1].front()};
        ends.push_back(e);
        legs += sweeps[c]->legs;
        cells.push_back({{"angle_deg", to_bearing(sweeps[c]->angle)},
                         {"legs", sweeps[c]->legs},
                         {"area_m2", area(sweeps[c]->mono)}});
      }
      ctx.report(kStage, f0 + 0.8 * (f1 - f0));
      // entry (docs/patterns.md): the tour starts from the region's corner that way, else nearest the start
      Point entry = p.starts[k];
      const bool fixed_entry = p.pattern && p.pattern->entry != "auto";
      if (fixed_entry) {
        Box box;
        bg::envelope(planned, box);
        const bool north = p.pattern->entry[0] == 'n', east = p.pattern->entry[1] == 'e';
        entry = Point{east ? box.max_corner().x() : box.min_corner().x(),
                      north ? box.max_corner().y() : box.min_corner().y()};
      }
      auto fly = [&](const std::vector<CellEnds>& e, const std::vector<std::size_t>& which, Point from,
                     nlohmann::json& order) {
        // a fixed entry: the first leg weighs 1000 times (the corner first), the tour returns to the start
        const bool first = fixed_entry && order.empty() && ua.coverage.empty();
        const Tour tour = first ? order_cells(e, from, p.starts[k], 1000.0, ctx) : order_cells(e, from, ctx);
        for (std::size_t i = 0; i < tour.order.size(); ++i) {
          const int way = tour.variant[i];
          const std::size_t c = which[static_cast<std::size_t>(tour.order[i])];
          auto path = paths[c][static_cast<std::size_t>(way / 2)];
          auto off = flags[c][static_cast<std::size_t>(way / 2)];
          if (way % 2 == 1) {
            std::reverse(path.begin(), path.end());
            std::reverse(off.begin(), off.end());
          }
          ua.coverage.push_back(std::move(path));
          ua.camera_off.push_back(std::move(off));
          order.push_back(tour.order[i]);
        }
        return tour;
      };
      std::vector<std::size_t> first_cells(ends.size());
      std::iota(first_cells.begin(), first_cells.end(), 0);
      nlohmann::json order = nlohmann::json::array();
      const bool nadir = !(p.pattern && p.pattern->oblique && !p.pattern->oblique->nadir);
      const Tour tour = nadir ? fly(ends, first_cells, entry, order) : Tour{};
      if (nadir && !second.empty()) {
        std::vector<CellEnds> e2;
        for (std::size_t c : second) {
          const auto& pa = paths[c];
          CellEnds e;
          e.entry = {pa[0].front(), pa[0].back(), pa[1].front(), pa[1].back()};
          e.exit = {pa[0].back(), pa[0].front(), pa[1].back(), pa[1].front()};
          e2.push_back(e);
        }
        nlohmann::json order2 = nlohmann::json::array();
        const Point from = ua.coverage.empty() ? entry : ua.coverage.back().back();
        fly(e2, second, from, order2);
        cells.push_back(
            {{"crosshatch_angle_deg", to_bearing(cross->angle)}, {"cell_order", std::move(order2)}});
      }
      // oblique passes (docs/patterns.md "Obliques"): per direction, a lawnmower at the nadir grid's lane
      // direction over the region swept back from where the camera faces by h tan(tilt) (so the tilted
      // footprints reach the region's edges), never into another UAV's region or a no-fly zone, the
      // camera at a fixed heading and the gimbal at the pattern's pitch
      nlohmann::json passes = nlohmann::json::array();
      if (p.pattern && p.pattern->oblique) {
        const Oblique& ob = *p.pattern->oblique;
        const double h = p.altitude_m;
        const double along = k < p.uav_footprints.size() && p.uav_footprints[k].along_m > 0
                                 ? p.uav_footprints[k].along_m
                                 : 0.75 * footprint;
        const photo::ObliqueFootprint fp = photo::oblique_footprint(
            h, ob.gimbal_pitch_deg, photo::fov_deg(footprint, h), photo::fov_deg(along, h));
        const double growth = fp.centre_m;  // h tan(tilt)
        const double lanes = to_bearing(lay.angle);
        const double reference = to_bearing(heading_ref.value_or(lay.angle));
        const double front = p.camera ? p.camera->front_overlap : 0.75;
        SweepOptions oopt = opt;
        oopt.mode = Mode::Strict;  // the grown area is the pass's whole ground: nothing to extend past
        oopt.overhang = false;
        ua.attitude.resize(ua.coverage.size());
        for (int d = 0; d < ob.directions; ++d) {
          ctx.check();
          const double heading = std::fmod(reference + d * 360.0 / ob.directions, 360.0);
          const double b = heading * kPi / 180.0;
          MultiPolygon grown = swept_along(planned, Point{-growth * std::sin(b), -growth * std::cos(b)});
          if (!others.empty()) grown = inset_against(grown, others, eps);
          if (!p.no_fly.empty()) {
            MultiPolygon out_nfz;
            bg::difference(grown, p.no_fly, out_nfz);
            grown = std::move(out_nfz);
          }
          remove_near_duplicates(grown);
          grown = drop_slivers(grown, 1e-3 * p.spacing_m);
          Surroundings oenv;
          oenv.area = &grown;
          oenv.no_fly = &p.no_fly;
          oenv.stops.add(grown);
          oenv.stops.add(p.no_fly);
          oenv.no_fly_edges.add(p.no_fly);
          const Layout ol = best_layout(grown, p.spacing_m, lay.angle, ctx, f0, f0);
          std::vector<std::size_t> which;
          std::vector<CellEnds> e;
          int olegs = 0;
          for (const auto& sw : ol.sweeps) {
            flags.emplace_back();
            paths.push_back(lawnmower(sw, oopt, oenv, ctx, &flags.back()));
            const auto& pa = paths.back();
            if (pa[0].empty() || pa[1].empty()) {
              paths.pop_back();
              flags.pop_back();
              continue;
            }
            which.push_back(paths.size() - 1);
            CellEnds ce;
            ce.entry = {pa[0].front(), pa[0].back(), pa[1].front(), pa[1].back()};
            ce.exit = {pa[0].back(), pa[0].front(), pa[1].back(), pa[1].front()};
            e.push_back(ce);
            olegs += sw.legs;
          }
          if (e.empty()) continue;
          const std::size_t before = ua.coverage.size();
          nlohmann::json porder = nlohmann::json::array();
          fly(e, which, ua.coverage.empty() ? entry : ua.coverage.back().back(), porder);
          Attitude att;
          att.gimbal_pitch_deg = ob.gimbal_pitch_deg;
          att.trigger_distance_m = photo::oblique_trigger_distance(fp, lanes, heading, front);
          for (std::size_t c = before; c < ua.coverage.size(); ++c) {
            att.heading_deg.assign(ua.coverage[c].size(), heading);
            ua.attitude.push_back(att);
          }
          passes.push_back({{"heading_deg", heading},
                            {"gimbal_pitch_deg", ob.gimbal_pitch_deg},
                            {"growth_m", growth},
                            {"area_m2", bg::area(grown)},
                            {"legs", olegs},
                            {"parts", ua.coverage.size() - before},
                            {"trigger_distance_m", *att.trigger_distance_m},
                            {"cell_order", std::move(porder)}});
        }
      }
      ua.diagnostics = {{"decomposition_angle_deg", to_bearing(lay.angle)},
                        {"cells", std::move(cells)},
                        {"cell_order", std::move(order)},
                        {"legs", legs},
                        {"transit_estimate_m", tour.transit_m}};
      if (!passes.empty()) ua.diagnostics["oblique_passes"] = std::move(passes);
      ctx.report(kStage, f1);
    }
    ctx.report(kStage, 1.0);
    return out;
  }
};

}  // namespace

PlannerInfo boustrophedon_planner_info() {
  PlannerInfo info;
  info.name = "boustrophedon";
  info.summary =
      "Lawnmower over a boustrophedon cell decomposition: shares by strips/cells, per-cell sweep direction "
      "with the fewest turns, short cell tour";
  ParamSpec angle;
  angle.name = "angle_deg";
  angle.type = ParamSpec::Type::Number;
  angle.default_value = nullptr;
  angle.min = -360.0;
  angle.max = 360.0;
  angle.description =
      "Direction of the legs in degrees clockwise from north (0: north-south legs, 90: east-west legs); "
      "absent: chosen per cell to minimise turns";
  info.params.push_back(std::move(angle));
  info.supports = Capabilities{true, true, true, true, true, false};
  info.supports.corridor = info.supports.crosshatch = info.supports.turnaround = info.supports.entry =
      info.supports.alternate_transects = info.supports.capture_in_turnaround = true;
  info.supports.structure = true;  // facade orbits (src/planners/structure/)
  info.supports.oblique = true;    // areas only: the engine refuses obliques over corridors
  info.create = [] { return std::make_unique<BoustrophedonPlanner>(); };
  return info;
}

}  // namespace uavcover::planners
