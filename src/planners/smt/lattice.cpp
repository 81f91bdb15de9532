#include "planners/smt/lattice.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <queue>
#include <set>

#include "evaluation/cost.hpp"
#include "geometry/geometry.hpp"
#include "uavcover/error.hpp"

namespace uavcover::smt {

namespace {

constexpr double kTol = 1e-3;  // metres
/// How far outside a no-fly zone's edge a node moved out of the zone sits (coverage mode), metres.
constexpr double kMoveClearance = 1.0;

double dist2(Point a, Point b) {
  const double dx = a.x() - b.x(), dy = a.y() - b.y();
  return dx * dx + dy * dy;
}

void normalise(Walk& w) {
  while (w.size() > 1 && w.back() == w.front()) w.pop_back();
}

/// The point of the boundary of the no-fly zone holding p nearest to p (p itself when none holds it).
Point nearest_on_boundary(const MultiPolygon& zones, Point p) {
  Point best = p;
  double bd = std::numeric_limits<double>::infinity();
  auto scan = [&](const auto& ring) {
    for (std::size_t k = 1; k < ring.size(); ++k) {
      const Point a = ring[k - 1], b = ring[k];
      const double ex = b.x() - a.x(), ey = b.y() - a.y(), ll = ex * ex + ey * ey;
      const double t =
          ll > 0.0 ? std::clamp(((p.x() - a.x()) * ex + (p.y() - a.y()) * ey) / ll, 0.0, 1.0) : 0.0;
      const Point q(a.x() + t * ex, a.y() + t * ey);
      if (const double d = dist2(p, q); d < bd) bd = d, best = q;
    }
  };
  for (const auto& poly : zones) {
    if (!bg::covered_by(p, poly)) continue;  // the zone holding p has the nearest edge (zones are disjoint)
    scan(poly.outer());
    for (const auto& hole : poly.inners()) scan(hole);
  }
  return best;
}

}  // namespace

int Lattice::weight(int a, int b) const {
  const auto& ca = cell[static_cast<std::size_t>(a)];
  const auto& cb = cell[static_cast<std::size_t>(b)];
  return (ca[0] != cb[0] && ca[1] != cb[1]) ? 1414 : 1000;  // in ds / 1000
}

bool Lattice::adjacent(int a, int b) const {
  const auto& n = adj[static_cast<std::size_t>(a)];
  return std::binary_search(n.begin(), n.end(), b);
}

Lattice build_lattice(const planners::Problem& problem, bool eight_connected, int max_nodes,
                      const std::function<void()>& check) {
  const double ds = problem.spacing_m;
  if (!(ds > 0.0)) throw InputError("spacing_m", "must be > 0");
  bg::model::box<Point> box;
  bg::envelope(problem.free, box);
  const double w = box.max_corner().x() - box.min_corner().x();
  const double h = box.max_corner().y() - box.min_corner().y();
  const double cols_d = std::max(1.0, std::ceil(w / ds - 1e-9));
  const double rows_d = std::max(1.0, std::ceil(h / ds - 1e-9));
  // the lattice's cells bound its nodes; refuse before allocating them
  if (cols_d * rows_d > 8.0 * max_nodes)
    throw InputError("spacing_m",
                     fmt::format("the smt planner's lattice would have up to {:.0f} nodes at {} m "
                                 "(planner_params.max_nodes: {}); use a larger spacing",
                                 cols_d * rows_d, ds, max_nodes));
  Lattice lat;
  lat.ds = ds;
  lat.cols = static_cast<int>(cols_d);
  lat.rows = static_cast<int>(rows_d);
  lat.origin =
      Point(box.min_corner().x() - (cols_d * ds - w) / 2.0, box.min_corner().y() - (rows_d * ds - h) / 2.0);
  lat.node_of_cell.assign(static_cast<std::size_t>(lat.cols) * static_cast<std::size_t>(lat.rows), -1);
  const bool strict = problem.mode == Mode::Strict;
  std::vector<char> moved;  // per node: moved out of a no-fly zone (coverage mode)
  for (int r = 0; r < lat.rows; ++r) {
    if (check) check();
    for (int c = 0; c < lat.cols; ++c) {
      Point p(lat.origin.x() + (c + 0.5) * ds, lat.origin.y() + (r + 0.5) * ds);
      bool ok = false, shifted = false;
      if (strict) {
        ok = bg::covered_by(p, problem.free);
      } else if (geometry::distance(problem.free, p) <= 0.5 * ds) {
        ok = problem.no_fly.empty() || !bg::covered_by(p, problem.no_fly);
        if (!ok) {
          // a cell centred in a no-fly zone whose cell holds free ground: its node moves to the zone's
          // nearest edge, kMoveClearance outside, so that the band along the edge is flown
          const double e = 1e-3 * ds;
          const bg::model::box<Point> cellbox(Point(p.x() - 0.5 * ds + e, p.y() - 0.5 * ds + e),
                                              Point(p.x() + 0.5 * ds - e, p.y() + 0.5 * ds - e));
          if (bg::intersects(cellbox, problem.free)) {
            const Point q = nearest_on_boundary(problem.no_fly, p);
            const double d = std::sqrt(dist2(p, q));
            if (d > 0.0) {
              const Point moved_to(q.x() + (q.x() - p.x()) / d * kMoveClearance,
                                   q.y() + (q.y() - p.y()) / d * kMoveClearance);
              ok = !bg::covered_by(moved_to, problem.no_fly) &&
                   geometry::distance(problem.no_fly, moved_to) >= 0.5 * kMoveClearance &&
                   geometry::distance(problem.free, moved_to) <= 0.5 * ds;
              if (ok) p = moved_to, shifted = true;
            }
          }
        }
      }
      if (!ok) continue;
      if (lat.size() >= max_nodes)
        throw InputError("spacing_m", fmt::format("the smt planner's lattice has more than {} nodes at {} m "
                                                  "(planner_params.max_nodes); use a larger spacing",
                                                  max_nodes, ds));
      lat.node_of_cell[static_cast<std::size_t>(r) * static_cast<std::size_t>(lat.cols) +
                       static_cast<std::size_t>(c)] = lat.size();
      lat.pos.push_back(p);
      lat.cell.push_back({c, r});
      moved.push_back(shifted ? 1 : 0);
    }
  }
  if (lat.pos.empty())
    throw InputError("spacing_m",
                     fmt::format("no lattice node of the smt planner fits in the free area at {} m", ds));
  lat.adj.assign(lat.pos.size(), {});
  lat.adj4.assign(lat.pos.size(), {});
  auto clear = [&](Point a, Point b) {
    return strict ? geometry::segment_within(problem.free, a, b, kTol)
                  : problem.no_fly.empty() || !geometry::segment_enters(problem.no_fly, a, b, kTol);
  };
  std::vector<std::array<int, 2>> steps{{1, 0}, {0, 1}};
  if (eight_connected) steps.insert(steps.end(), {{1, 1}, {-1, 1}});
  for (int a = 0; a < lat.size(); ++a) {
    if (check && a % 256 == 0) check();
    const auto [c, r] = lat.cell[static_cast<std::size_t>(a)];
    for (const auto& [dc, dr] : steps) {
      const int c2 = c + dc, r2 = r + dr;
      if (c2 < 0 || r2 < 0 || c2 >= lat.cols || r2 >= lat.rows) continue;
      const int b = lat.node_of_cell[static_cast<std::size_t>(r2) * static_cast<std::size_t>(lat.cols) +
                                     static_cast<std::size_t>(c2)];
      if (b < 0 || !clear(lat.pos[static_cast<std::size_t>(a)], lat.pos[static_cast<std::size_t>(b)]))
        continue;
      lat.adj[static_cast<std::size_t>(a)].push_back(b);
      lat.adj[static_cast<std::size_t>(b)].push_back(a);
      if (dc == 0 || dr == 0) {
        lat.adj4[static_cast<std::size_t>(a)].push_back(b);
        lat.adj4[static_cast<std::size_t>(b)].push_back(a);
      }
    }
  }
  // moved nodes that no clear edge joins to an unmoved one would be routes of their own: dropped (their
  // edges join them only to each other, so the others' edges stay)
  std::vector<char> reached(lat.pos.size(), 0);
  std::vector<int> stack;
  for (int a = 0; a < lat.size(); ++a)
    if (!moved[static_cast<std::size_t>(a)]) reached[static_cast<std::size_t>(a)] = 1, stack.push_back(a);
  while (!stack.empty()) {
    const int a = stack.back();
    stack.pop_back();
    for (int b : lat.adj[static_cast<std::size_t>(a)])
      if (!reached[static_cast<std::size_t>(b)]) reached[static_cast<std::size_t>(b)] = 1, stack.push_back(b);
  }
  if (std::find(moved.begin(), moved.end(), 0) != moved.end()) {  // (all moved: none dropped)
    std::vector<int> renum(lat.pos.size(), -1);
    int kept = 0;
    for (std::size_t a = 0; a < lat.pos.size(); ++a)
      if (reached[a]) renum[a] = kept++;
    if (kept < lat.size()) {
      Lattice out = lat;
      out.pos.clear(), out.cell.clear(), out.adj.clear(), out.adj4.clear();
      std::fill(out.node_of_cell.begin(), out.node_of_cell.end(), -1);
      auto remap = [&](const std::vector<int>& n) {
        std::vector<int> m;
        for (int b : n)
          if (renum[static_cast<std::size_t>(b)] >= 0) m.push_back(renum[static_cast<std::size_t>(b)]);
        return m;
      };
      for (std::size_t a = 0; a < lat.pos.size(); ++a) {
        if (renum[a] < 0) continue;
        const auto [c, r] = lat.cell[a];
        out.node_of_cell[static_cast<std::size_t>(r) * static_cast<std::size_t>(lat.cols) +
                         static_cast<std::size_t>(c)] = renum[a];
        out.pos.push_back(lat.pos[a]);
        out.cell.push_back(lat.cell[a]);
        out.adj.push_back(remap(lat.adj[a]));
        out.adj4.push_back(remap(lat.adj4[a]));
      }
      lat = std::move(out);
    }
  }
  for (auto& n : lat.adj) std::sort(n.begin(), n.end());
  for (auto& n : lat.adj4) std::sort(n.begin(), n.end());
  return lat;
}

namespace {

/// Node visits the share balance (balance()) may spend: about a second on the largest lattices.
constexpr double kBalanceWork = 4e7;

/// Whether region `a` stays connected without node v (over axis edges): first within v's 3 x 3 cells
/// (the usual case on a lattice), else by a search over the region, which counts against `work`.
bool removable(const Lattice& lat, const std::vector<int>& owner, int v, int a, double& work) {
  std::vector<int> mine;
  for (int w : lat.adj4[static_cast<std::size_t>(v)])
    if (owner[static_cast<std::size_t>(w)] == a) mine.push_back(w);
  if (mine.size() <= 1) return true;  // a leaf (a region of v alone is never given away)
  // the region's nodes among v's eight neighbouring cells
  const auto [c0, r0] = lat.cell[static_cast<std::size_t>(v)];
  std::vector<int> ring;
  for (int dr = -1; dr <= 1; ++dr)
    for (int dc = -1; dc <= 1; ++dc) {
      const int c = c0 + dc, r = r0 + dr;
      if ((dr == 0 && dc == 0) || c < 0 || r < 0 || c >= lat.cols || r >= lat.rows) continue;
      const int w = lat.node_of_cell[static_cast<std::size_t>(r) * static_cast<std::size_t>(lat.cols) +
                                     static_cast<std::size_t>(c)];
      if (w >= 0 && owner[static_cast<std::size_t>(w)] == a) ring.push_back(w);
    }
  auto joined = [&](const std::vector<int>& within) {
    std::vector<int> seen{mine.front()}, queue{mine.front()};
    auto in = [&](int w) { return std::find(within.begin(), within.end(), w) != within.end(); };
    for (std::size_t h = 0; h < queue.size(); ++h)
      for (int w : lat.adj4[static_cast<std::size_t>(queue[h])])
        if (w != v && owner[static_cast<std::size_t>(w)] == a &&
            std::find(seen.begin(), seen.end(), w) == seen.end() && in(w))
          seen.push_back(w), queue.push_back(w);
    return std::all_of(mine.begin(), mine.end(),
                       [&](int m) { return std::find(seen.begin(), seen.end(), m) != seen.end(); });
  };
  if (joined(ring)) return true;
  // the whole region: breadth first from one neighbour, without v
  std::vector<char> seen(lat.pos.size(), 0);
  std::vector<int> queue{mine.front()};
  seen[static_cast<std::size_t>(mine.front())] = 1;
  seen[static_cast<std::size_t>(v)] = 1;
  for (std::size_t h = 0; h < queue.size(); ++h)
    for (int w : lat.adj4[static_cast<std::size_t>(queue[h])])
      if (!seen[static_cast<std::size_t>(w)] && owner[static_cast<std::size_t>(w)] == a)
        seen[static_cast<std::size_t>(w)] = 1, queue.push_back(w);
  work -= static_cast<double>(queue.size());
  return std::all_of(mine.begin(), mine.end(), [&](int m) { return seen[static_cast<std::size_t>(m)] != 0; });
}

/// Moves up to `want` nodes of region `a` to the adjacent region `b` across their border, each keeping
/// `a` connected (b grows from its border, so it stays connected) and never a seed; the nodes furthest
/// from a's seed and nearest b's first. Returns how many moved.
int hand_over(const Lattice& lat, std::vector<int>& owner, const std::vector<int>& seed, int a, int b,
              int want, double& work) {
  const Point sa = lat.pos[static_cast<std::size_t>(seed[static_cast<std::size_t>(a)])];
  const Point sb = lat.pos[static_cast<std::size_t>(seed[static_cast<std::size_t>(b)])];
  auto score = [&](int v) {
    const Point p = lat.pos[static_cast<std::size_t>(v)];
    return dist2(p, sa) - dist2(p, sb);
  };
  using Item = std::pair<double, int>;  // (score, node), highest first
  std::priority_queue<Item> border;
  auto touches_b = [&](int v) {
    for (int w : lat.adj4[static_cast<std::size_t>(v)])
      if (owner[static_cast<std::size_t>(w)] == b) return true;
    return false;
  };
  for (int v = 0; v < lat.size(); ++v)
    if (owner[static_cast<std::size_t>(v)] == a && touches_b(v)) border.emplace(score(v), v);
  work -= static_cast<double>(lat.size());
  int moved = 0;
  std::vector<int> skipped;
  while (moved < want && !border.empty() && work > 0) {
    const int v = border.top().second;
    border.pop();
    work -= 1;
    if (owner[static_cast<std::size_t>(v)] != a || v == seed[static_cast<std::size_t>(a)]) continue;
    if (!removable(lat, owner, v, a, work)) {
      skipped.push_back(v);  // may become removable once its neighbours have moved: tried again below
      continue;
    }
    owner[static_cast<std::size_t>(v)] = b;
    ++moved;
    for (int w : lat.adj4[static_cast<std::size_t>(v)])
      if (owner[static_cast<std::size_t>(w)] == a) border.emplace(score(w), w);
    if (border.empty() && !skipped.empty()) {
      for (int w : skipped) border.emplace(score(w), w);
      skipped.clear();
    }
  }
  return moved;
}

/// Balances a grown division towards the shares (issue 26: on a C or U shape the greedy growth walled
/// one UAV in, 15 points off its share). Repeatedly, the UAV furthest below its target receives over a
/// shortest chain of adjacent regions from the nearest UAV above its target: each region of the chain
/// hands the next one nodes across their border (hand_over), so the chain's ends change by the amount
/// and the regions between keep theirs; every region stays 4-connected and keeps its seed. A chain that
/// moves nothing is not tried again. Ends when no chain improves the sum of squared deviations, or
/// after kBalanceWork node visits. Deterministic.
void balance(const Lattice& lat, std::vector<int>& owner, const std::vector<int>& seed,
             const std::vector<double>& shares) {
  const std::size_t k = seed.size(), n = lat.pos.size();
  if (k < 2) return;
  double total_share = 0.0;
  for (double s : shares) total_share += std::max(s, 0.0);
  if (!(total_share > 0.0)) return;
  std::vector<double> target(k);
  for (std::size_t u = 0; u < k; ++u)
    target[u] = std::max(shares[u], 0.0) / total_share * static_cast<double>(n);
  std::set<std::pair<int, int>> blocked;  // (giver, receiver) of a chain that moved nothing
  double work = kBalanceWork;
  while (work > 0) {
    std::vector<int> count(k, 0);
    for (int o : owner) ++count[static_cast<std::size_t>(o)];
    // region adjacency over axis edges
    std::vector<std::vector<char>> touch(k, std::vector<char>(k, 0));
    for (std::size_t v = 0; v < n; ++v)
      for (int w : lat.adj4[v])
        if (owner[v] != owner[static_cast<std::size_t>(w)])
          touch[static_cast<std::size_t>(owner[v])]
               [static_cast<std::size_t>(owner[static_cast<std::size_t>(w)])] = 1;
    work -= static_cast<double>(n);
    // receivers furthest below their targets first
    std::vector<std::size_t> order(k);
    for (std::size_t u = 0; u < k; ++u) order[u] = u;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
      return count[x] - target[x] < count[y] - target[y];
    });
    bool moved_any = false;
    for (const std::size_t r : order) {
      const double need = target[r] - static_cast<double>(count[r]);
      if (need < 0.5) break;
      // shortest chain back from r to a region above its target that gains by giving (d - r > 1)
      std::vector<int> prev(k, -1);
      std::vector<std::size_t> queue{r};
      prev[r] = static_cast<int>(r);
      std::optional<std::size_t> giver;
      for (std::size_t h = 0; h < queue.size() && !giver; ++h) {
        const std::size_t x = queue[h];
        for (std::size_t y = 0; y < k; ++y) {
          if (prev[y] >= 0 || !touch[y][x] || blocked.contains({static_cast<int>(y), static_cast<int>(x)}))
            continue;
          prev[y] = static_cast<int>(x);
          const double surplus = static_cast<double>(count[y]) - target[y];
          if (surplus > 0.5 && surplus + need > 1.0) {
            giver = y;
            break;
          }
          queue.push_back(y);
        }
      }
      if (!giver) continue;
      const double surplus = static_cast<double>(count[*giver]) - target[*giver];
      int amount = std::max(1, static_cast<int>(std::floor(std::min(surplus, need))));
      // hand over along the chain, from the giver's end: giver -> ... -> r
      for (std::size_t y = *giver; y != r && amount > 0;) {
        const auto x = static_cast<std::size_t>(prev[y]);
        const int moved = hand_over(lat, owner, seed, static_cast<int>(y), static_cast<int>(x), amount, work);
        if (moved == 0) blocked.insert({static_cast<int>(y), static_cast<int>(x)});
        amount = moved;
        y = x;
      }
      if (amount > 0) {
        moved_any = true;
        break;  // counts changed: recount
      }
    }
    if (!moved_any) break;
  }
}

}  // namespace

std::vector<int> divide(const Lattice& lat, const std::vector<Point>& starts,
                        const std::vector<double>& shares) {
  const std::size_t n = lat.pos.size(), k = starts.size();
  if (k > n)
    throw InputError("uavs", fmt::format("the smt planner's lattice has {} nodes for {} UAVs; use a smaller "
                                         "spacing or fewer UAVs",
                                         n, k));
  std::vector<int> owner(n, -1), count(k, 0), seed(k, -1);
  using Item = std::pair<double, int>;  // (squared distance to the seed, node)
  std::vector<std::priority_queue<Item, std::vector<Item>, std::greater<>>> frontier(k);
  for (std::size_t u = 0; u < k; ++u) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t v = 0; v < n; ++v) {
      const double d = dist2(lat.pos[v], starts[u]);
      if (owner[v] < 0 && d < best) best = d, seed[u] = static_cast<int>(v);
    }
    owner[static_cast<std::size_t>(seed[u])] = static_cast<int>(u);
    count[u] = 1;
  }
  auto push_neighbours = [&](std::size_t u, int v) {
    for (int w : lat.adj4[static_cast<std::size_t>(v)])
      if (owner[static_cast<std::size_t>(w)] < 0)
        frontier[u].emplace(
            dist2(lat.pos[static_cast<std::size_t>(w)], lat.pos[static_cast<std::size_t>(seed[u])]), w);
  };
  for (std::size_t u = 0; u < k; ++u) push_neighbours(u, seed[u]);
  for (;;) {
    int pick = -1;
    double lowest = std::numeric_limits<double>::infinity();
    for (std::size_t u = 0; u < k; ++u) {
      while (!frontier[u].empty() && owner[static_cast<std::size_t>(frontier[u].top().second)] >= 0)
        frontier[u].pop();
      if (frontier[u].empty()) continue;
      const double fill = count[u] / std::max(shares[u], 1e-9);
      if (fill < lowest) lowest = fill, pick = static_cast<int>(u);
    }
    if (pick < 0) break;
    const auto u = static_cast<std::size_t>(pick);
    const int v = frontier[u].top().second;
    frontier[u].pop();
    owner[static_cast<std::size_t>(v)] = pick;
    ++count[u];
    push_neighbours(u, v);
  }
  // components no seed reached: whole, to the UAV whose start is nearest
  for (std::size_t v = 0; v < n; ++v) {
    if (owner[v] >= 0) continue;
    int to = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t u = 0; u < k; ++u)
      if (const double d = dist2(lat.pos[v], starts[u]); d < best) best = d, to = static_cast<int>(u);
    std::vector<int> stack{static_cast<int>(v)};
    owner[v] = to;
    while (!stack.empty()) {
      const int a = stack.back();
      stack.pop_back();
      for (int b : lat.adj4[static_cast<std::size_t>(a)])
        if (owner[static_cast<std::size_t>(b)] < 0)
          owner[static_cast<std::size_t>(b)] = to, stack.push_back(b);
    }
  }
  balance(lat, owner, seed, shares);
  return owner;
}

std::vector<std::vector<int>> split(const Lattice& lat, const std::vector<int>& nodes, int size,
                                    bool strips) {
  int tw = std::max(1, static_cast<int>(std::lround(std::sqrt(static_cast<double>(size)))));
  int th = std::max(1, (size + tw - 1) / tw);
  if (strips && !nodes.empty()) {  // two lattice lines wide, along the nodes' longer extent
    int c0 = lat.cols, c1 = -1, r0 = lat.rows, r1 = -1;
    for (int v : nodes) {
      const auto [c, r] = lat.cell[static_cast<std::size_t>(v)];
      c0 = std::min(c0, c), c1 = std::max(c1, c), r0 = std::min(r0, r), r1 = std::max(r1, r);
    }
    const int along = std::max(1, size / 2);
    tw = r1 - r0 >= c1 - c0 ? 2 : along;
    th = r1 - r0 >= c1 - c0 ? along : 2;
  }
  std::map<std::pair<int, int>, std::vector<int>> tiles;  // (tile row, tile column) -> nodes
  for (int v : nodes) {
    const auto [c, r] = lat.cell[static_cast<std::size_t>(v)];
    tiles[{r / th, c / tw}].push_back(v);
  }
  std::vector<std::vector<int>> out;
  std::vector<char> in(lat.pos.size(), 0), seen(lat.pos.size(), 0);
  for (auto& [key, members] : tiles) {
    std::sort(members.begin(), members.end());
    for (int v : members) in[static_cast<std::size_t>(v)] = 1;
    for (int s : members) {
      if (seen[static_cast<std::size_t>(s)]) continue;
      std::vector<int> part{s}, stack{s};
      seen[static_cast<std::size_t>(s)] = 1;
      while (!stack.empty()) {
        const int a = stack.back();
        stack.pop_back();
        for (int b : lat.adj[static_cast<std::size_t>(a)])
          if (in[static_cast<std::size_t>(b)] && !seen[static_cast<std::size_t>(b)]) {
            seen[static_cast<std::size_t>(b)] = 1;
            part.push_back(b);
            stack.push_back(b);
          }
      }
      std::sort(part.begin(), part.end());
      out.push_back(std::move(part));
    }
    for (int v : members) in[static_cast<std::size_t>(v)] = 0;
  }
  return out;
}

Subgraph subgraph(const Lattice& lat, const std::vector<int>& nodes) {
  Subgraph g;
  g.n = static_cast<int>(nodes.size());
  std::map<int, int> local;
  for (std::size_t k = 0; k < nodes.size(); ++k) local[nodes[k]] = static_cast<int>(k);
  for (std::size_t k = 0; k < nodes.size(); ++k)
    for (int b : lat.adj[static_cast<std::size_t>(nodes[k])]) {
      const auto it = local.find(b);
      if (it == local.end() || it->second <= static_cast<int>(k)) continue;
      g.edges.push_back({static_cast<int>(k), it->second});
      g.weight.push_back(lat.weight(nodes[k], b));
    }
  // turning pairs: two edges at a node that do not continue straight on (lattice steps never overlap)
  std::vector<std::vector<int>> at(nodes.size());
  for (std::size_t e = 0; e < g.edges.size(); ++e)
    for (int end : g.edges[e]) at[static_cast<std::size_t>(end)].push_back(static_cast<int>(e));
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const Point p = lat.pos[static_cast<std::size_t>(nodes[k])];
    auto away = [&](int e) {
      const auto& ed = g.edges[static_cast<std::size_t>(e)];
      const int w = ed[0] == static_cast<int>(k) ? ed[1] : ed[0];
      const Point q = lat.pos[static_cast<std::size_t>(nodes[static_cast<std::size_t>(w)])];
      return std::array<double, 2>{q.x() - p.x(), q.y() - p.y()};
    };
    const auto& inc = at[k];
    for (std::size_t i = 0; i < inc.size(); ++i)
      for (std::size_t j = i + 1; j < inc.size(); ++j) {
        const auto u = away(inc[i]), v = away(inc[j]);
        const double cross = u[0] * v[1] - u[1] * v[0], dot = u[0] * v[0] + u[1] * v[1];
        const bool straight = std::fabs(cross) <= 1e-9 * (std::fabs(dot) + 1.0) && dot < 0.0;
        if (!straight) g.turns.push_back({static_cast<int>(k), inc[i], inc[j]});
      }
  }
  return g;
}

std::vector<Point> walk_polyline(const Lattice& lat, const Walk& walk, bool closed) {
  std::vector<Point> pts;
  for (int v : walk) pts.push_back(lat.pos[static_cast<std::size_t>(v)]);
  if (closed && !walk.empty()) pts.push_back(lat.pos[static_cast<std::size_t>(walk.front())]);
  if (pts.size() <= 2) return pts;
  std::vector<Point> out{pts.front()};
  for (std::size_t k = 1; k + 1 < pts.size(); ++k) {
    const double ax = pts[k].x() - out.back().x(), ay = pts[k].y() - out.back().y();
    const double bx = pts[k + 1].x() - pts[k].x(), by = pts[k + 1].y() - pts[k].y();
    const bool straight = std::fabs(ax * by - ay * bx) <= 1e-9 * (ax * ax + ay * ay + bx * bx + by * by) &&
                          ax * bx + ay * by > 0.0;
    if (!straight) out.push_back(pts[k]);
  }
  out.push_back(pts.back());
  return out;
}

Walk flight_order(const Lattice& lat, const Walk& walk, int entry, Point home) {
  Walk out = walk;
  const auto it = std::find(out.begin(), out.end(), entry);
  if (it != out.end()) std::rotate(out.begin(), it, out.end());
  // the walk's last node is one of the entry's two neighbours on it: the one nearer home
  if (out.size() > 2 && dist2(lat.pos[static_cast<std::size_t>(out[1])], home) <
                            dist2(lat.pos[static_cast<std::size_t>(out.back())], home))
    std::reverse(out.begin() + 1, out.end());
  return out;
}

RouteCost path_cost(const Lattice& lat, const Walk& path, Point home, const Uav& uav, const LegFn& leg) {
  if (path.empty()) return {};
  const std::vector<Point> out_leg = leg(home, lat.pos[static_cast<std::size_t>(path.front())]);
  const std::vector<Point> cover = walk_polyline(lat, path, false);
  const std::vector<Point> back_leg = leg(lat.pos[static_cast<std::size_t>(path.back())], home);
  std::vector<Point> flight;
  auto append = [&](const std::vector<Point>& pts) {
    for (const Point& p : pts)
      if (flight.empty() || dist2(flight.back(), p) > 1e-12) flight.push_back(p);
  };
  append(out_leg);
  append(cover);
  append(back_leg);
  RouteCost out;
  out.length_m = geometry::length(flight);
  out.turns =
      static_cast<int>(cover.size()) + geometry::count_turns(out_leg) + geometry::count_turns(back_leg);
  out.time_s = evaluation::flight_duration_min(out.length_m, out.turns, uav) * 60.0;
  return out;
}

RouteCost route_cost(const Lattice& lat, const Walk& walk, int entry, Point home, const Uav& uav,
                     const LegFn& leg) {
  return path_cost(lat, flight_order(lat, walk, entry, home), home, uav, leg);
}

std::vector<Route> split_route(const Lattice& lat, const Route& route, Point home, const Uav& uav,
                               double max_time_s, const LegFn& leg) {
  const Walk& path = route.walk;
  std::vector<char> visited(lat.pos.size(), 0);
  std::vector<Route> out;
  std::size_t i = 0;
  auto skip_visited = [&] {
    while (i < path.size() && visited[static_cast<std::size_t>(path[i])]) ++i;
  };
  for (skip_visited(); i < path.size(); skip_visited()) {
    // the longest piece path[i..j] within the limit, then its trailing revisits dropped
    Walk piece{path[i]};
    RouteCost cost = path_cost(lat, piece, home, uav, leg);
    if (cost.time_s > max_time_s) {
      const Point q = lat.pos[static_cast<std::size_t>(path[i])];
      throw InputError(
          "planner_params.max_flight_time_s",
          fmt::format("must be at least {:.1f} s: the lattice node at ({:.1f}, {:.1f}) m takes that "
                      "long from home and back (limit {:.1f} s)",
                      cost.time_s, q.x(), q.y(), max_time_s));
    }
    std::size_t j = i + 1;
    for (; j < path.size(); ++j) {
      piece.push_back(path[j]);
      const RouteCost c = path_cost(lat, piece, home, uav, leg);
      if (c.time_s > max_time_s) {
        piece.pop_back();
        break;
      }
      cost = c;
    }
    while (piece.size() > 1 && (visited[static_cast<std::size_t>(piece.back())] ||
                                std::count(piece.begin(), piece.end(), piece.back()) > 1)) {
      piece.pop_back();
      cost = path_cost(lat, piece, home, uav, leg);
    }
    for (int v : piece) visited[static_cast<std::size_t>(v)] = 1;
    i = j;
    Route r;
    r.walk = std::move(piece);
    r.entry = r.walk.front();
    r.time_s = cost.time_s;
    r.length_m = cost.length_m;
    r.turns = cost.turns;
    r.walks = 1;
    out.push_back(std::move(r));
  }
  return out;
}

namespace {

/// Splices walk `c` into route walk `r` at the cheapest place: two parallel edges exchanged, else a
/// detour over one lattice edge (there and back). Empty when no lattice edge joins them.
Walk splice(const Lattice& lat, const Walk& r, const Walk& c) {
  const std::size_t m = r.size(), k = c.size();
  long long best = std::numeric_limits<long long>::max();
  Walk out;
  Walk members = c;  // the route nodes next to c are few: only they can take part in a splice
  std::sort(members.begin(), members.end());
  auto touches = [&](int u) {
    const auto& n = lat.adj[static_cast<std::size_t>(u)];
    return std::any_of(n.begin(), n.end(),
                       [&](int w) { return std::binary_search(members.begin(), members.end(), w); });
  };
  std::vector<char> near(m, 0);
  for (std::size_t i = 0; i < m; ++i) near[i] = touches(r[i]) ? 1 : 0;
  if (m >= 2 && k >= 2)
    for (std::size_t i = 0; i < m; ++i) {
      const int u = r[i], v = r[(i + 1) % m];
      if (!near[i] || !near[(i + 1) % m]) continue;
      for (std::size_t j = 0; j < k; ++j) {
        const int a = c[j], b = c[(j + 1) % k];
        for (int flip = 0; flip < 2; ++flip) {
          const int u2 = flip ? b : a, v2 = flip ? a : b;  // joined to u and v
          if (!lat.adjacent(u, u2) || !lat.adjacent(v, v2)) continue;
          const long long delta = static_cast<long long>(lat.weight(u, u2)) + lat.weight(v, v2) -
                                  lat.weight(u, v) - lat.weight(a, b);
          if (delta >= best) continue;
          best = delta;
          out.assign(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(i + 1));
          // around c from u2 to v2 without the edge (a, b)
          if (!flip)
            for (std::size_t s = 0; s < k; ++s) out.push_back(c[(j + k - s) % k]);  // a, back to b
          else
            for (std::size_t s = 0; s < k; ++s) out.push_back(c[(j + 1 + s) % k]);  // b, on to a
          out.insert(out.end(), r.begin() + static_cast<std::ptrdiff_t>(i + 1), r.end());
        }
      }
    }
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = 0; j < k && near[i]; ++j) {
      if (!lat.adjacent(r[i], c[j])) continue;
      const long long delta = 2LL * lat.weight(r[i], c[j]);
      if (delta >= best) continue;
      best = delta;
      out.assign(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(i + 1));
      for (std::size_t s = 0; s < k; ++s) out.push_back(c[(j + s) % k]);
      if (k > 1) out.push_back(c[j]);
      out.push_back(r[i]);
      out.insert(out.end(), r.begin() + static_cast<std::ptrdiff_t>(i + 1), r.end());
    }
  normalise(out);
  return out;
}

int nearest(const Lattice& lat, const Walk& w, Point home) {
  int best = w.front();
  double bd = std::numeric_limits<double>::infinity();
  for (int v : w)
    if (const double d = dist2(lat.pos[static_cast<std::size_t>(v)], home); d < bd || (d == bd && v < best))
      bd = d, best = v;
  return best;
}

}  // namespace

std::vector<Route> stitch(const Lattice& lat, const std::vector<Walk>& walks, Point home, const Uav& uav,
                          double max_time_s, const LegFn& leg, int* split,
                          const std::function<void()>& check) {
  std::vector<int> walk_of(lat.pos.size(), -1);
  std::vector<double> home_d(walks.size());
  for (std::size_t w = 0; w < walks.size(); ++w) {
    for (int v : walks[w]) walk_of[static_cast<std::size_t>(v)] = static_cast<int>(w);
    home_d[w] = dist2(lat.pos[static_cast<std::size_t>(nearest(lat, walks[w], home))], home);
  }
  std::vector<char> done(walks.size(), 0);
  auto closer = [&](int a, int b) {
    return home_d[static_cast<std::size_t>(a)] < home_d[static_cast<std::size_t>(b)] ||
           (home_d[static_cast<std::size_t>(a)] == home_d[static_cast<std::size_t>(b)] && a < b);
  };
  std::vector<Route> routes;
  if (split) *split = 0;
  for (;;) {
    int first = -1;
    for (std::size_t w = 0; w < walks.size(); ++w)
      if (!done[w] && (first < 0 || closer(static_cast<int>(w), first))) first = static_cast<int>(w);
    if (first < 0) break;
    done[static_cast<std::size_t>(first)] = 1;
    Route route;
    route.walk = walks[static_cast<std::size_t>(first)];
    route.entry = nearest(lat, route.walk, home);
    route.walks = 1;
    RouteCost cost = route_cost(lat, route.walk, route.entry, home, uav, leg);
    if (cost.time_s > max_time_s) {  // too long alone: flown in pieces, none spliced into
      if (split) ++*split;
      route.walk = flight_order(lat, route.walk, route.entry, home);
      for (auto& piece : split_route(lat, route, home, uav, max_time_s, leg))
        routes.push_back(std::move(piece));
      continue;
    }
    std::vector<char> rejected(walks.size(), 0);
    for (bool grown = true; grown;) {
      grown = false;
      std::vector<int> next;
      for (int v : route.walk)
        for (int b : lat.adj[static_cast<std::size_t>(v)]) {
          const int w = walk_of[static_cast<std::size_t>(b)];
          if (w >= 0 && !done[static_cast<std::size_t>(w)] && !rejected[static_cast<std::size_t>(w)])
            next.push_back(w);
        }
      std::sort(next.begin(), next.end(), closer);
      next.erase(std::unique(next.begin(), next.end()), next.end());
      for (int w : next) {
        if (check) check();
        Walk merged = splice(lat, route.walk, walks[static_cast<std::size_t>(w)]);
        if (merged.empty()) continue;
        const int entry = nearest(lat, merged, home);
        const RouteCost c = route_cost(lat, merged, entry, home, uav, leg);
        if (c.time_s > max_time_s) {
          rejected[static_cast<std::size_t>(w)] = 1;
          continue;
        }
        route.walk = std::move(merged);
        route.entry = entry;
        ++route.walks;
        cost = c;
        done[static_cast<std::size_t>(w)] = 1;
        grown = true;
        break;
      }
    }
    route.walk = flight_order(lat, route.walk, route.entry, home);
    route.time_s = cost.time_s;
    route.length_m = cost.length_m;
    route.turns = cost.turns;
    routes.push_back(std::move(route));
  }
  return routes;
}

}  // namespace uavcover::smt
