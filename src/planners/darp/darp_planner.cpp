#include "planners/darp/darp_planner.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>

#include "planners/darp/division.hpp"
#include "planners/darp/extend.hpp"
#include "planners/darp/grid.hpp"
#include "planners/darp/placement.hpp"
#include "planners/darp/regions.hpp"
#include "planners/darp/stc.hpp"
#include "uavcover/error.hpp"

namespace uavcover::darp {

namespace {

double dist2(Point a, Point b) {
  const double dx = a.x() - b.x(), dy = a.y() - b.y();
  return dx * dx + dy * dy;
}

/// The free cell containing p, or the free cell whose centre is nearest to p.
int start_cell(const grid::Grid& g, Point p, bool& inside) {
  const Point q = g.local_to_q(p);
  const int c = static_cast<int>(std::floor((q.x() - g.x0) / g.dn));
  const int r = static_cast<int>(std::floor((q.y() - g.y0) / g.dn));
  inside = g.free_at(r, c);
  if (inside) return g.idx(r, c);
  int best = -1;
  double bd = std::numeric_limits<double>::infinity();
  for (int k = 0; k < g.rows * g.cols; ++k) {
    if (!g.free[k]) continue;
    const double d = dist2(g.cell_centre(k / g.cols, k % g.cols), p);
    if (d < bd) bd = d, best = k;
  }
  return best;
}

/// The nearest cell of `comp_cells` (by BFS over links from `from`) not in `taken`.
int nearest_untaken(const grid::Grid& g, int from, const std::vector<char>& taken) {
  std::vector<char> seen(static_cast<std::size_t>(g.rows) * g.cols, 0);
  std::vector<int> queue{from};
  seen[from] = 1;
  std::array<int, 4> nb{};
  for (std::size_t h = 0; h < queue.size(); ++h) {
    const int u = queue[h];
    if (!taken[u]) return u;
    const int m = g.neighbours(u, nb);
    for (int i = 0; i < m; ++i)
      if (!seen[nb[i]]) {
        seen[nb[i]] = 1;
        queue.push_back(nb[i]);
      }
  }
  return -1;
}

/// How many cells UAV i can reach from its start cell over links without entering another UAV's
/// start cell (its own region can never be larger).
int reachable(const grid::Grid& g, const std::vector<int>& scell, int i) {
  if (scell[i] < 0) return 0;
  std::vector<char> seen(static_cast<std::size_t>(g.rows) * g.cols, 0);
  for (int k : scell)
    if (k >= 0) seen[k] = 1;
  std::vector<int> queue{scell[i]};
  std::array<int, 4> nb{};
  for (std::size_t h = 0; h < queue.size(); ++h) {
    const int m = g.neighbours(queue[h], nb);
    for (int j = 0; j < m; ++j)
      if (!seen[nb[j]]) {
        seen[nb[j]] = 1;
        queue.push_back(nb[j]);
      }
  }
  return static_cast<int>(queue.size());
}

/// A start outside the area goes to the free cell nearest it, and that cell can wall another UAV in:
/// on a five-pointed star (issue 26) a UAV's cell in one point has its only link into the cell another
/// UAV's start took, so it can never hold more than that one cell (1 / 10 / 7 cells for 6 / 6 / 6). A UAV
/// is walled in when it reaches (reachable) fewer cells than its target less the division's tolerance;
/// then a start outside the area that borders it (without which it reaches more) moves to the nearest
/// free cell to its take-off point (of the 64 nearest) that walls nobody in. Starts inside the area stay
/// where they are.
void unwall_starts(const grid::Grid& g, const std::vector<Point>& starts, const std::vector<double>& target,
                   const std::vector<char>& outside, std::vector<int>& scell) {
  const int U = static_cast<int>(scell.size());
  auto walled = [&](int i) {
    return scell[i] >= 0 && reachable(g, scell, i) < target[i] - tolerance(target[i]) - 1e-9;
  };
  auto any_walled = [&] {
    for (int i = 0; i < U; ++i)
      if (walled(i)) return true;
    return false;
  };
  for (int i = 0; i < U; ++i) {
    if (!walled(i)) continue;
    for (int j = 0; j < U && walled(i); ++j) {
      if (j == i || !outside[j] || scell[j] < 0) continue;
      // j borders i: without j's start cell in the way, i reaches more
      std::vector<int> without = scell;
      without[j] = -1;
      if (reachable(g, without, i) <= reachable(g, scell, i)) continue;
      std::vector<std::pair<double, int>> cands;
      for (int k = 0; k < g.rows * g.cols; ++k)
        if (g.free[k] && std::find(scell.begin(), scell.end(), k) == scell.end())
          cands.emplace_back(dist2(g.cell_centre(k / g.cols, k % g.cols), starts[j]), k);
      std::sort(cands.begin(), cands.end());
      if (cands.size() > 64) cands.resize(64);
      const int before = scell[j];
      for (const auto& [d, k] : cands) {
        scell[j] = k;
        if (!any_walled()) break;
        scell[j] = before;
      }
    }
  }
}

}  // namespace

std::optional<std::string> coarse_grid_warning(const std::vector<double>& target, double ds,
                                               double free_area_m2) {
  const int U = static_cast<int>(target.size());
  const double L = std::accumulate(target.begin(), target.end(), 0.0);
  if (U < 2 || !(L > 0)) return std::nullopt;
  // the best division at this grid: whole cells by largest remainder (it minimises the largest deviation)
  std::vector<double> cells(target.size());
  std::vector<int> order(target.size());
  double given = 0;
  for (int i = 0; i < U; ++i) given += cells[i] = std::floor(target[i] + 1e-9), order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return target[a] - cells[a] > target[b] - cells[b]; });
  for (int k = 0; k < U && given + 0.5 < std::round(L); ++k) cells[order[k]] += 1, given += 1;
  double dev = 0, rel = 0, smallest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < U; ++i) {
    if (target[i] <= 0) continue;
    smallest = std::min(smallest, target[i]);
    const double d = std::fabs(cells[i] - target[i]);
    dev = std::max(dev, d);
    rel = std::max(rel, d / target[i]);
  }
  if (!(rel > 0.02 + 1e-9)) return std::nullopt;  // DARP's own tolerance: 2 % of a UAV's share
  // 25 cells for the smallest share keep whole cells within 2 % of it; cells are (2 ds)^2
  constexpr double kCellsPerShare = 25;
  const double needed = kCellsPerShare * L / smallest;
  const double finer = std::min(ds * std::sqrt(L / needed), std::sqrt(free_area_m2 / needed) / 2);
  return fmt::format(
      "DARP's grid is too coarse for the shares: {:.0f} free cells for {} UAVs ({:.1f} per UAV; the "
      "smallest share, {:.3f}, is {:.1f} cells), so the best division at this grid is off by up to {:.2f} "
      "cells ({:.1f} points of the area, {:.0f} % of a share; DARP aims at 2 %). Choose a finer spacing "
      "(about {:.0f} m or less for {:.0f} cells per UAV of the smallest share) or a planner that divides "
      "continuously (boustrophedon, spiral)",
      L, U, L / U, smallest / L, smallest, dev, 100 * dev / L, 100 * rel, std::floor(finer), kCellsPerShare);
}

Output run(const Input& input, const Options& options, const Context& ctx) {
  Output out;
  // A time limit bounds the whole command, and the stages that finish a plan cannot be cut short: the
  // STC loops, the extended legs, the region outlines, then transit, sorties and the plan's own files.
  // At 1M mega-cells they take several seconds, so the placement and the division (the stages that
  // only improve a plan) end that long before the deadline: kFinishPasses times the cost of one pass
  // over the grid, measured as the placement's first evaluation (so it follows the grid's size and the
  // machine's load). At 1M mega-cells x 50 UAVs the stages after the placement took 35 such passes
  // (2.1 s after a first evaluation of 0.06 s, `uavcover plan --time-limit 2`, docs/stops.md).
  static constexpr int kFinishPasses = 32;
  Context::Clock::time_point placement_began{};
  std::optional<Context::Clock::duration> reserve;
  const auto stop_early = [&out, &ctx, &placement_began, &reserve] {
    if (ctx.stop_requested()) throw Cancelled();
    if (!ctx.deadline()) return out.stopped_early;
    const auto now = Context::Clock::now();
    // first asked after the placement's first evaluation
    if (!reserve) reserve = (now - placement_began) * kFinishPasses;
    if (now + *reserve >= *ctx.deadline()) out.stopped_early = true;
    return out.stopped_early;
  };
  const auto name = [&input](int i) {
    return i < static_cast<int>(input.ids.size()) ? input.ids[static_cast<std::size_t>(i)]
                                                  : std::to_string(i + 1);
  };
  const int U = static_cast<int>(input.starts.size());
  if (U == 0) throw InputError("uavs", "at least one UAV is needed");
  if (!(input.ds > 0)) throw InputError("spacing_m", "must be positive");

  // ---- 1-2. grid and placement ----
  grid::Prepared prep = grid::prepare(input.free, input.no_fly, input.ds, input.mode);
  if (input.mode == Mode::Coverage) prep.estimate_samples = 16;  // coverage is the main objective there
  grid::PlacementOptions popt;
  popt.evaluations = options.placement_evaluations;
  popt.optimise = options.optimise_placement;
  popt.seed = input.seed;
  popt.stop_early = stop_early;
  popt.on_evaluation = options.on_placement_evaluation;
  if (input.mode == Mode::Coverage) {
    // coverage mode: the path may leave the area, so reward coverage first, and weigh the length a little.
    // With shifted legs (LegExtender::shift) coverage weight 25 gave 99.45 % PoC, 81.1 turns, 25.95 km on
    // the paper's regions, against 99.44 %, 84.1, 26.13 km with 40 and 99.43 %, 81.4, 25.89 km with 20
    // (bench/results/darp-quality.md)
    popt.weights.coverage_weight = 25.0;
    popt.weights.length_weight = 3.0;
    popt.rerank = 64;
  } else {
    // strict mode: length weight 3.6 gives 98.11 % PoC, 79.8 turns, 24.44 km on the paper's regions with
    // shifted legs; 5.0 gave 97.57 %, 79.7, 24.11 km and 5.5 97.23 %, 80.2, 24.00 km
    // (bench/results/darp-quality.md), but 5.0 cost the reassignment of a failed UAV's remainder on the
    // olive grove 8 points of PoC (0.943 -> 0.865, Reassign.HelpersCoverTheRemainder...): the shorter grids
    // leave more of a small irregular area's edge unflown.
    popt.weights.length_weight = 3.6;
  }
  popt.weights.a = options.j_weight_a;
  popt.weights.b = options.j_weight_b;
  popt.weights.c = options.j_weight_c;
  if (options.paper_objective) {
    // the paper's J alone (eq. 7 and the authors' disconnected penalty): no coverage estimate, no length
    // term, and the search's best is kept (re-ranking by the finer estimate would add nothing to J)
    popt.weights.coverage_weight = 0.0;
    popt.weights.length_weight = 0.0;
    popt.rerank = 1;
    prep.estimate_coverage = false;
  }
  placement_began = Context::Clock::now();
  grid::PlacementResult pr =
      grid::optimise_placement(prep, popt, [&](double f) { ctx.report("placement", f); });
  out.placement = pr.placement;
  const grid::Grid& g = pr.grid;
  if (g.free_cells == 0)
    throw InputError("spacing_m", fmt::format("no free grid cell at spacing {} m in {} mode: the area is too "
                                              "small or narrow for this spacing",
                                              input.ds, input.mode == Mode::Strict ? "strict" : "coverage"));
  const int N = g.rows * g.cols;
  out.grid.cell_m = g.dn;
  out.grid.rotation_deg = g.theta_deg;
  out.grid.origin = g.q_to_local(g.x0, g.y0);
  out.grid.rows = g.rows;
  out.grid.cols = g.cols;
  out.grid.owner.assign(N, -1);

  // ---- components and start cells ----
  std::vector<int> label;
  const int C = grid::components(g, label);
  std::vector<std::vector<int>> comp_cells(C);
  for (int k = 0; k < N; ++k)
    if (label[k] >= 0) comp_cells[label[k]].push_back(k);
  const double L = g.free_cells;
  std::vector<double> share(input.shares);
  share.resize(U, 0.0);
  double ssum = std::accumulate(share.begin(), share.end(), 0.0);
  if (!(ssum > 0)) std::fill(share.begin(), share.end(), 1.0), ssum = U;
  std::vector<double> target(U);
  for (int i = 0; i < U; ++i) target[i] = share[i] / ssum * L;
  if (auto w = coarse_grid_warning(target, input.ds, bg::area(input.free))) out.warnings.push_back(*w);

  std::vector<int> scell(U);
  std::vector<char> taken(N, 0), outside(U, 0);
  for (int i = 0; i < U; ++i) {
    bool inside = false;
    int k = start_cell(g, input.starts[i], inside);
    outside[i] = !bg::within(input.starts[i], input.free) ? 1 : 0;
    // a take-off point beside the field is normal; one inside the free area that misses every free
    // cell (a narrow strip, a corner) is worth telling the operator
    if (!inside && !outside[i])
      out.warnings.push_back(
          fmt::format("UAV {}: the start lies in the area but on no free grid cell; its region starts at "
                      "the nearest free cell",
                      name(i)));
    if (taken[k]) k = nearest_untaken(g, k, taken);  // shared start cells: the next free one
    scell[i] = k;
    if (k >= 0) taken[k] = 1;
  }
  unwall_starts(g, input.starts, target, outside, scell);
  std::fill(taken.begin(), taken.end(), 0);
  for (int k : scell)
    if (k >= 0) taken[k] = 1;

  // ---- 4. distribute the components over the UAVs ----
  // participants[c]: UAVs dividing component c (with their start cells inside it)
  std::vector<std::vector<int>> participants(C);
  for (int i = 0; i < U; ++i)
    if (scell[i] >= 0) participants[label[scell[i]]].push_back(i);
  // expected load of each UAV from its home component, proportional to the targets
  std::vector<double> home_load(U, 0.0), extra(U, 0.0);
  for (int c = 0; c < C; ++c) {
    double tsum = 0;
    for (int i : participants[c]) tsum += target[i];
    for (int i : participants[c]) home_load[i] = tsum > 0 ? comp_cells[c].size() * target[i] / tsum : 0.0;
  }
  // orphan components (no start inside), largest first, to the UAV with the largest deficit
  std::vector<int> orphans;
  for (int c = 0; c < C; ++c)
    if (participants[c].empty()) orphans.push_back(c);
  std::stable_sort(orphans.begin(), orphans.end(),
                   [&](int a, int b) { return comp_cells[a].size() > comp_cells[b].size(); });
  std::vector<int> orphan_owner(C, -1);
  for (int c : orphans) {
    int best = 0;
    double bd = -std::numeric_limits<double>::infinity();
    const Point centre = g.cell_centre(comp_cells[c][0] / g.cols, comp_cells[c][0] % g.cols);
    for (int i = 0; i < U; ++i) {
      const double deficit = target[i] - home_load[i] - extra[i];
      // prefer the deficit; among near-equal deficits the nearer UAV
      const double key = deficit - 1e-9 * std::sqrt(dist2(centre, input.starts[i]));
      if (key > bd) bd = key, best = i;
    }
    orphan_owner[c] = best;
    extra[best] += static_cast<double>(comp_cells[c].size());
  }

  // demand[c]: (UAV, wanted cells, start cell) of the UAVs dividing component c; `movable`: the start
  // cell is only where the UAV enters (its take-off point is outside the area, or it joins the component)
  struct Part {
    int uav;
    double want;
    int start;
    bool movable;
  };
  std::vector<std::vector<Part>> demand(C);
  for (int c = 0; c < C; ++c)
    for (int i : participants[c])
      demand[c].push_back({i, std::max(1.0, target[i] - extra[i]), scell[i], outside[i] != 0});
  // UAVs that their own component cannot feed (too small, or crowded) join the component with
  // the largest surplus, entering at its cell nearest to their start
  auto expected = [&](std::vector<double>& load) {
    load.assign(U, 0.0);
    for (int i = 0; i < U; ++i) load[i] = extra[i];
    for (int c = 0; c < C; ++c) {
      double sum = 0;
      for (const auto& p : demand[c]) sum += p.want;
      for (const auto& p : demand[c]) load[p.uav] += comp_cells[c].size() * p.want / sum;
    }
  };
  for (int round = 0; round < U && C > 1; ++round) {
    std::vector<double> load;
    expected(load);
    int worst = -1;
    double wd = 0, wn = 1.0;  // deficit in cells, and in units of the UAV's tolerance
    for (int i = 0; i < U; ++i)
      if ((target[i] - load[i]) / tolerance(target[i]) > wn)
        wn = (target[i] - load[i]) / tolerance(target[i]), wd = target[i] - load[i], worst = i;
    if (worst < 0) break;
    int best_c = -1;
    double best_surplus = tolerance(target[worst]);
    for (int c = 0; c < C; ++c) {
      bool in = false;
      double want = 0;
      for (const auto& p : demand[c]) in |= p.uav == worst, want += p.want;
      const double surplus = comp_cells[c].size() - (demand[c].empty() ? 0.0 : want);
      if (!in && !demand[c].empty() && surplus > best_surplus && comp_cells[c].size() > demand[c].size() + 1)
        best_surplus = surplus, best_c = c;
    }
    if (best_c < 0) break;
    int entry = -1;
    double bd = std::numeric_limits<double>::infinity();
    for (int k : comp_cells[best_c]) {
      if (taken[k]) continue;
      const double d = dist2(g.cell_centre(k / g.cols, k % g.cols), input.starts[worst]);
      if (d < bd) bd = d, entry = k;
    }
    if (entry < 0) break;
    taken[entry] = 1;
    // the joining UAV asks for its deficit (at most the surplus); the others keep their demand
    demand[best_c].push_back({worst, std::min(wd, best_surplus), entry, true});
  }

  // ---- 3. DARP per shared component ----
  std::vector<std::vector<std::vector<int>>> regions(U);  // per UAV: list of regions (cell lists)
  out.converged = true;
  int done_cells = 0;
  for (int c = 0; c < C; ++c) {
    const auto& cells = comp_cells[c];
    if (demand[c].empty()) {
      regions[orphan_owner[c]].push_back(cells);
      continue;
    }
    std::vector<int> P;
    for (const auto& p : demand[c]) P.push_back(p.uav);
    if (P.size() == 1) {
      regions[P[0]].push_back(cells);
      continue;
    }
    DivisionInput din;
    din.cells = cells;
    din.max_iterations = options.max_iterations;
    din.seed = input.seed + static_cast<std::uint64_t>(c) * 7919;
    din.stop_early = stop_early;
    double want = 0;
    for (const auto& p : demand[c]) want += std::max(1.0, p.want);
    for (const auto& p : demand[c]) {
      din.starts.push_back(p.start);
      din.movable.push_back(p.movable ? 1 : 0);
      din.targets.push_back(std::max(1.0, p.want) / want * static_cast<double>(cells.size()));
    }
    const double frac0 = static_cast<double>(done_cells) / L, frac1 = (done_cells + cells.size()) / L;
    DivisionResult dr = divide(g, din, [&](double f) { ctx.report("darp", frac0 + (frac1 - frac0) * f); });
    done_cells += static_cast<int>(cells.size());
    out.iterations += dr.iterations;
    if (!dr.converged) {
      out.converged = false;
      out.warnings.push_back(fmt::format(
          "DARP did not meet the share tolerance (max deviation {:.0f} cells of {}) after {} iterations; "
          "using the best connected division found",
          dr.max_deviation, cells.size(), dr.iterations));
    }
    std::vector<std::vector<int>> per(P.size());
    for (std::size_t x = 0; x < cells.size(); ++x) per[dr.owner[x]].push_back(cells[x]);
    for (std::size_t j = 0; j < P.size(); ++j)
      if (!per[j].empty()) regions[P[j]].push_back(std::move(per[j]));
  }
  ctx.report("darp", 1.0);

  // ---- 5. STC loops, regions flown nearest-first, U-turns at the region's edge extended ----
  out.uavs.resize(U);
  const LegExtender extender(prep, g, input.free);
  int planned = 0;
  for (int i = 0; i < U; ++i) {
    UavResult& ur = out.uavs[i];
    for (const auto& reg : regions[i]) {
      ur.cells += static_cast<int>(reg.size());
      for (int k : reg) out.grid.owner[k] = i;
    }
    ur.share_actual = ur.cells / L;
    if (ur.cells == 0)
      out.warnings.push_back(
          fmt::format("UAV {} has no cell to cover (its share is too small or its start "
                      "lies in a component shared by more UAVs than cells)",
                      name(i)));
    Point here = input.starts[i];
    std::vector<char> flown(regions[i].size(), 0);
    for (std::size_t n = 0; n < regions[i].size(); ++n) {
      std::size_t pick = 0;
      double bd = std::numeric_limits<double>::infinity();
      for (std::size_t j = 0; j < regions[i].size(); ++j) {
        if (flown[j]) continue;
        for (int k : regions[i][j]) {
          const double d = dist2(g.cell_centre(k / g.cols, k % g.cols), here);
          if (d < bd) bd = d, pick = j;
        }
      }
      flown[pick] = 1;
      if (ctx.stop_requested()) throw Cancelled();
      stc::Loop loop =
          stc::plan_loop(g, regions[i][pick], here, options.min_turn_orientation ? stc::kOrientations : 1);
      if (options.extend_legs) extender.extend(loop.points);
      here = loop.points.front();
      ur.loops.push_back(std::move(loop.points));
      ++planned;
      ctx.report("stc", static_cast<double>(planned) / std::max(1, C + U - 1));
    }
  }
  if (options.shift_legs) {
    std::vector<std::vector<Point>*> all;
    std::vector<double> swaths;  // per loop: its UAV's own footprint width (0: the mission's)
    for (std::size_t i = 0; i < out.uavs.size(); ++i)
      for (auto& loop : out.uavs[i].loops) {
        all.push_back(&loop);
        swaths.push_back(i < input.own_footprint_m.size() ? input.own_footprint_m[i] : 0.0);
      }
    extender.shift(all, swaths);
  }
  double worst = 0, worst_n = 1.0;  // cells, of the UAV furthest outside its tolerance (0: none)
  for (int i = 0; i < U; ++i) {
    const double dev = std::fabs(out.uavs[i].cells - target[i]);
    if (dev / tolerance(target[i]) > worst_n) worst_n = dev / tolerance(target[i]), worst = dev;
  }
  if (out.converged && worst > 0) {
    out.converged = false;
    out.warnings.push_back(
        fmt::format("the free space is split into {} parts that cannot be shared as "
                    "requested (max deviation {:.0f} cells of {})",
                    C, worst, g.free_cells));
  }
  for (int i = 0; i < U; ++i)
    out.uavs[i].cells_outline = cells_to_polygons(g.rows, g.cols, out.grid.owner, i, [&g](int c, int r) {
      return g.q_to_local(g.x0 + c * g.dn, g.y0 + r * g.dn);
    });
  ctx.report("stc", 1.0);
  return out;
}

}  // namespace uavcover::darp
