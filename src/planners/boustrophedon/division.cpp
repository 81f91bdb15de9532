#include "planners/boustrophedon/division.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <numeric>
#include <tuple>

#include "planners/boustrophedon/decomposition.hpp"

namespace uavcover::planners::boustro {

namespace {

constexpr double kPi = std::numbers::pi;

struct Piece {
  int cell = 0;
  double x0 = 0.0, x1 = 0.0;
  double area = 0.0;
  std::vector<std::pair<int, int>> nb;  ///< (piece, side: 0 left, 1 right)
  int owner = -1;
};

/// Articulation points of the graph of unowned pieces (Tarjan).
std::vector<bool> articulation(const std::vector<Piece>& ps) {
  const std::size_t n = ps.size();
  std::vector<int> disc(n, -1), low(n, 0);
  std::vector<bool> cut(n, false);
  int time = 0;
  std::function<void(int, int)> dfs = [&](int u, int parent) {
    const auto uu = static_cast<std::size_t>(u);
    disc[uu] = low[uu] = time++;
    int children = 0;
    for (const auto& [v, side] : ps[uu].nb) {
      const auto vv = static_cast<std::size_t>(v);
      if (ps[vv].owner >= 0 || v == parent) continue;
      if (disc[vv] < 0) {
        ++children;
        dfs(v, u);
        low[uu] = std::min(low[uu], low[vv]);
        if (parent >= 0 && low[vv] >= disc[uu]) cut[uu] = true;
      } else {
        low[uu] = std::min(low[uu], disc[vv]);
      }
    }
    if (parent < 0 && children > 1) cut[uu] = true;
  };
  for (std::size_t i = 0; i < n; ++i)
    if (ps[i].owner < 0 && disc[i] < 0) dfs(static_cast<int>(i), -1);
  return cut;
}

/// Connected parts of the unowned pieces without piece `skip`: (area, pieces), largest first.
std::vector<std::pair<double, std::vector<int>>> components_without(const std::vector<Piece>& ps, int skip) {
  std::vector<std::pair<double, std::vector<int>>> out;
  std::vector<bool> seen(ps.size(), false);
  for (std::size_t s = 0; s < ps.size(); ++s) {
    if (seen[s] || ps[s].owner >= 0 || static_cast<int>(s) == skip) continue;
    std::pair<double, std::vector<int>> comp{0.0, {}};
    std::vector<int> stack{static_cast<int>(s)};
    seen[s] = true;
    while (!stack.empty()) {
      const int u = stack.back();
      stack.pop_back();
      comp.first += ps[static_cast<std::size_t>(u)].area;
      comp.second.push_back(u);
      for (const auto& [v, side] : ps[static_cast<std::size_t>(u)].nb) {
        const auto vv = static_cast<std::size_t>(v);
        if (seen[vv] || ps[vv].owner >= 0 || v == skip) continue;
        seen[vv] = true;
        stack.push_back(v);
      }
    }
    out.push_back(std::move(comp));
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  return out;
}

}  // namespace

namespace {

Division divide_once(const MultiPolygon& free, const std::vector<double>& shares,
                     const std::vector<Point>& starts, double angle, double spacing, const Context& ctx) {
  Division out;
  const std::size_t n = shares.size();
  out.regions.resize(n);
  if (n == 1) {
    out.regions[0] = free;
    return out;
  }
  const Frame f(angle);
  const Decomposition d = decompose(free, f, ctx);
  double total = 0.0;
  for (const auto& c : d.cells) total += area(c);
  if (!(total > 0.0)) return out;

  // strips along the legs
  const double piece_area = total / (30.0 * static_cast<double>(n));
  std::vector<Piece> ps;
  std::vector<int> first(d.cells.size()), last(d.cells.size());
  for (std::size_t c = 0; c < d.cells.size(); ++c) {
    const Monotone& m = d.cells[c];
    const double w = m.xmax() - m.xmin();
    const double a = area(m);
    const int by_width = std::max(1, static_cast<int>(std::floor(w / (0.5 * spacing))));
    const int k = std::clamp(static_cast<int>(std::ceil(a / piece_area)), 1, by_width);
    first[c] = static_cast<int>(ps.size());
    for (int i = 0; i < k; ++i) {
      Piece p;
      p.cell = static_cast<int>(c);
      p.x0 = m.xmin() + w * i / k;
      p.x1 = i + 1 == k ? m.xmax() : m.xmin() + w * (i + 1) / k;
      p.area = area(clip(m, p.x0, p.x1));
      if (i > 0) {
        const int me = static_cast<int>(ps.size());
        p.nb.emplace_back(me - 1, 0);
        ps.back().nb.emplace_back(me, 1);
      }
      ps.push_back(std::move(p));
    }
    last[c] = static_cast<int>(ps.size()) - 1;
  }
  for (const auto& l : d.links) {
    const int a = last[static_cast<std::size_t>(l.left)], b = first[static_cast<std::size_t>(l.right)];
    ps[static_cast<std::size_t>(a)].nb.emplace_back(b, 1);
    ps[static_cast<std::size_t>(b)].nb.emplace_back(a, 0);
  }
  out.pieces = static_cast<int>(ps.size());

  // UAVs from the left of the strips (by their start's position across the legs)
  std::vector<std::size_t> uav_order(n);
  std::iota(uav_order.begin(), uav_order.end(), 0);
  std::stable_sort(uav_order.begin(), uav_order.end(),
                   [&](std::size_t a, std::size_t b) { return f.to(starts[a]).x() < f.to(starts[b]).x(); });

  auto piece_area_between = [&](const Piece& p, double x0, double x1) {
    return area(clip(d.cells[static_cast<std::size_t>(p.cell)], x0, x1));
  };
  for (std::size_t step = 0; step + 1 < n; ++step) {
    const int k = static_cast<int>(uav_order[step]);
    const double target = shares[static_cast<std::size_t>(k)] * total;
    double acc = 0.0;
    bool any = false;
    while (acc < target - 1e-9 * total) {
      ctx.check();
      const std::vector<bool> cut = articulation(ps);
      auto touches_chunk = [&](const Piece& p) {
        return std::any_of(p.nb.begin(), p.nb.end(),
                           [&](const auto& e) { return ps[static_cast<std::size_t>(e.first)].owner == k; });
      };
      std::vector<int> frontier, free_pieces;
      for (std::size_t i = 0; i < ps.size(); ++i) {
        if (ps[i].owner >= 0) continue;
        free_pieces.push_back(static_cast<int>(i));
        if (any && touches_chunk(ps[i])) frontier.push_back(static_cast<int>(i));
      }
      if (free_pieces.empty()) break;
      std::vector<int> pool = frontier.empty() ? free_pieces : frontier;
      std::vector<int> cands;
      for (int i : pool)
        if (!cut[static_cast<std::size_t>(i)]) cands.push_back(i);
      const double need = target - acc;
      auto take = [&](int i) {
        ps[static_cast<std::size_t>(i)].owner = k;
        acc += ps[static_cast<std::size_t>(i)].area;
        any = true;
      };
      if (cands.empty()) {
        // every piece at hand holds the rest together: take the leftmost with the parts it would cut
        // off (all but the largest), when they fit; else this UAV stops short of its share
        std::vector<int> sorted = pool;
        std::stable_sort(sorted.begin(), sorted.end(), [&](int a, int b) {
          return ps[static_cast<std::size_t>(a)].x0 < ps[static_cast<std::size_t>(b)].x0;
        });
        bool taken = false;
        for (int c : sorted) {
          const auto comps = components_without(ps, c);
          double cut_off = 0.0;
          for (std::size_t i = 1; i < comps.size(); ++i) cut_off += comps[i].first;
          if (ps[static_cast<std::size_t>(c)].area + cut_off > need + 1e-9 * total) continue;
          take(c);
          for (std::size_t i = 1; i < comps.size(); ++i)
            for (int q : comps[i].second) take(q);
          taken = true;
          break;
        }
        if (!taken) {
          ++out.split_failures;
          break;
        }
        continue;
      }
      std::stable_sort(cands.begin(), cands.end(), [&](int a, int b) {
        return ps[static_cast<std::size_t>(a)].x0 < ps[static_cast<std::size_t>(b)].x0;
      });
      // a side from which piece i can be cut: touching the chunk, with no unowned neighbour
      auto split_side = [&](int i) {
        const Piece& p = ps[static_cast<std::size_t>(i)];
        bool chunk[2] = {!any, !any}, rest[2] = {false, false};
        for (const auto& [o, side] : p.nb) {
          const int owner = ps[static_cast<std::size_t>(o)].owner;
          if (owner == k) chunk[side] = true;
          if (owner < 0) rest[side] = true;
        }
        for (int s = 0; s < 2; ++s)
          if (chunk[s] && !rest[s]) return s;
        return -1;
      };
      auto split = [&](int i, int side) {
        Piece& p = ps[static_cast<std::size_t>(i)];
        double lo = p.x0, hi = p.x1;
        for (int it = 0; it < 60; ++it) {
          const double mid = 0.5 * (lo + hi);
          const double a = side == 0 ? piece_area_between(p, p.x0, mid) : piece_area_between(p, mid, p.x1);
          if ((a < need) == (side == 0))
            lo = mid;
          else
            hi = mid;
        }
        const double xc = 0.5 * (lo + hi);
        Piece taken;
        taken.cell = p.cell;
        taken.x0 = side == 0 ? p.x0 : xc;
        taken.x1 = side == 0 ? xc : p.x1;
        taken.area = piece_area_between(p, taken.x0, taken.x1);
        taken.owner = k;
        (side == 0 ? p.x0 : p.x1) = xc;
        p.area -= taken.area;
        std::erase_if(p.nb, [&](const auto& e) { return e.second == side; });
        acc += taken.area;
        any = true;
        ps.push_back(std::move(taken));
      };
      const int c0 = cands.front();
      if (ps[static_cast<std::size_t>(c0)].area <= need + 1e-9 * total) {
        take(c0);
        continue;
      }
      if (const int s = split_side(c0); s >= 0) {
        split(c0, s);
        break;
      }
      bool done = false, progressed = false;
      for (int i : cands)
        if (ps[static_cast<std::size_t>(i)].area <= need + 1e-9 * total) {
          take(i);
          progressed = true;
          break;
        }
      if (progressed) continue;
      for (int i : cands)
        if (const int s = split_side(i); s >= 0) {
          split(i, s);
          done = true;
          break;
        }
      if (done) break;
      ++out.split_failures;
      if (need > 0.5 * ps[static_cast<std::size_t>(c0)].area) take(c0);
      break;
    }
  }
  for (auto& p : ps)
    if (p.owner < 0) p.owner = static_cast<int>(uav_order[n - 1]);

  // regions: contiguous runs of a cell's pieces, then their union
  constexpr double kGrow = 0.5;
  const MultiPolygon free_frame = to_frame(free, f);
  for (std::size_t k = 0; k < n; ++k) {
    ctx.check();
    std::vector<const Piece*> mine;
    for (const auto& p : ps)
      if (p.owner == static_cast<int>(k) && p.x1 > p.x0) mine.push_back(&p);
    std::stable_sort(mine.begin(), mine.end(), [](const Piece* a, const Piece* b) {
      return a->cell != b->cell ? a->cell < b->cell : a->x0 < b->x0;
    });
    MultiPolygon acc;
    for (std::size_t i = 0; i < mine.size();) {
      std::size_t j = i;
      while (j + 1 < mine.size() && mine[j + 1]->cell == mine[i]->cell &&
             mine[j + 1]->x0 - mine[j]->x1 < 1e-9)
        ++j;
      // united in the frame, where the shared sides are exactly the same vertical lines; each run is
      // grown by kGrow along the legs (out of the free area: a run spans the free area's whole
      // interval there), so that runs around a no-fly zone never touch at a single point, and the
      // union is cut back to the free area
      Monotone run = clip(d.cells[static_cast<std::size_t>(mine[i]->cell)], mine[i]->x0, mine[j]->x1);
      for (auto& q : run.lower) q.y(q.y() - kGrow);
      for (auto& q : run.upper) q.y(q.y() + kGrow);
      MultiPolygon next;
      bg::union_(acc, monotone_polygon(run), next);
      acc = std::move(next);
      i = j + 1;
    }
    MultiPolygon region;
    bg::intersection(acc, free_frame, region);
    acc = from_frame(region, f);
    bg::correct(acc);
    remove_near_duplicates(acc);
    // slivers left by the overlay along the runs' sides
    std::erase_if(acc, [&](const Polygon& poly) { return std::abs(bg::area(poly)) < 1e-6 * total; });
    out.regions[k] = std::move(acc);
  }
  return out;
}

}  // namespace

Division divide(const MultiPolygon& free, const std::vector<double>& shares, const std::vector<Point>& starts,
                double angle, double spacing, const Context& ctx) {
  // strips handed out from either end, along the legs or across them; the first division whose
  // shares are all within 2 % and whose regions are connected wins, else the best by that order
  const double total = bg::area(free);
  const std::size_t parts = free.size();
  Division best;
  std::tuple<int, int, double> best_score{1 << 30, 1 << 30, 1e300};
  for (const double a : {angle, angle + kPi, angle + kPi / 2, angle + 3 * kPi / 2}) {
    Division d = divide_once(free, shares, starts, a, spacing, ctx);
    int disconnected = 0;
    double worst = 0.0;
    for (std::size_t k = 0; k < shares.size(); ++k) {
      if (d.regions[k].size() > std::max<std::size_t>(parts, 1)) ++disconnected;
      worst = std::max(worst, std::abs(bg::area(d.regions[k]) / total - shares[k]));
    }
    const std::tuple<int, int, double> score{worst > 0.02 ? 1 : 0, disconnected, worst};
    if (score < best_score) {
      best_score = score;
      best = std::move(d);
    }
    if (std::get<0>(score) == 0 && disconnected == 0) break;
  }
  return best;
}

}  // namespace uavcover::planners::boustro
