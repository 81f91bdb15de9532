#include "planners/darp/stc.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace uavcover::stc {

namespace {

struct Dsu {
  std::vector<int> p;
  explicit Dsu(int n) : p(n) { std::iota(p.begin(), p.end(), 0); }
  int find(int x) {
    while (p[x] != x) x = p[x] = p[p[x]];
    return x;
  }
  bool unite(int a, int b) {
    a = find(a), b = find(b);
    if (a == b) return false;
    p[a] = b;
    return true;
  }
};

struct TreeEdge {
  int a, b;  // local cell ids, b is right of / above a
  bool horizontal;
  int row, col;  // local row/col of a
};

struct Local {
  int r0 = 0, c0 = 0, h = 0, w = 0;  // bounding box of the region in cells
  std::vector<int> cells;            // local ids
  std::vector<TreeEdge> edges;
};

/// Walks the sub-cell cycle around the tree given by `tree_flags` (bit 0 right, 1 up, 2 left,
/// 3 down) and returns the sequence of turning sub-nodes (local sub coordinates, packed y*SW+x).
std::vector<int> circumnavigate(const Local& loc, const std::vector<std::uint8_t>& tree) {
  const int SW = 2 * loc.w, SH = 2 * loc.h;
  std::vector<std::array<int, 2>> nb(static_cast<std::size_t>(SW) * SH, {-1, -1});
  auto add = [&](int u, int v) {
    (nb[u][0] < 0 ? nb[u][0] : nb[u][1]) = v;
    (nb[v][0] < 0 ? nb[v][0] : nb[v][1]) = u;
  };
  for (int k : loc.cells) {
    const int lr = k / loc.w, lc = k % loc.w;
    const int BL = (2 * lr) * SW + 2 * lc, BR = BL + 1, TL = BL + SW, TR = TL + 1;
    const std::uint8_t f = tree[k];
    if (!(f & 8)) add(BL, BR);
    if (!(f & 2)) add(TL, TR);
    if (!(f & 4)) add(BL, TL);
    if (!(f & 1)) add(BR, TR);
    if (f & 1) add(BR, BR + 1), add(TR, TR + 1);
    if (f & 2) add(TL, TL + SW), add(TR, TR + SW);
  }
  const int start = (2 * (loc.cells[0] / loc.w)) * SW + 2 * (loc.cells[0] % loc.w);
  std::vector<int> seq;
  seq.reserve(loc.cells.size() * 4);
  int prev = -1, cur = start;
  do {
    seq.push_back(cur);
    const int next = nb[cur][0] != prev ? nb[cur][0] : nb[cur][1];
    if (next < 0) throw std::logic_error("stc: broken sub-cell cycle");
    prev = cur;
    cur = next;
  } while (cur != start && seq.size() <= loc.cells.size() * 4);
  std::vector<int> turning;
  const int m = static_cast<int>(seq.size());
  for (int i = 0; i < m; ++i) {
    const int a = seq[(i + m - 1) % m], b = seq[i], c = seq[(i + 1) % m];
    if (b - a != c - b) turning.push_back(b);
  }
  return turning;
}

}  // namespace

Loop plan_loop(const grid::Grid& g, const std::vector<int>& cells, Point entry, int orientations) {
  Loop out;
  if (cells.empty()) return out;
  Local loc;
  int r1 = -1, c1 = -1;
  loc.r0 = loc.c0 = std::numeric_limits<int>::max();
  for (int k : cells) {
    const int r = k / g.cols, c = k % g.cols;
    loc.r0 = std::min(loc.r0, r), loc.c0 = std::min(loc.c0, c);
    r1 = std::max(r1, r), c1 = std::max(c1, c);
  }
  loc.h = r1 - loc.r0 + 1;
  loc.w = c1 - loc.c0 + 1;
  std::vector<std::uint8_t> in(static_cast<std::size_t>(loc.h) * loc.w, 0);
  for (int k : cells) {
    const int lk = (k / g.cols - loc.r0) * loc.w + (k % g.cols - loc.c0);
    in[lk] = 1;
  }
  for (int lk = 0; lk < loc.h * loc.w; ++lk) {
    if (!in[lk]) continue;
    loc.cells.push_back(lk);
    const int lr = lk / loc.w, lc = lk % loc.w;
    const int k = g.idx(lr + loc.r0, lc + loc.c0);
    if ((g.link[k] & 1) && lc + 1 < loc.w && in[lk + 1]) loc.edges.push_back({lk, lk + 1, true, lr, lc});
    if ((g.link[k] & 2) && lr + 1 < loc.h && in[lk + loc.w])
      loc.edges.push_back({lk, lk + loc.w, false, lr, lc});
  }

  std::vector<int> best;
  std::vector<TreeEdge> order = loc.edges;
  std::vector<std::uint8_t> tree(in.size());
  orientations = std::clamp(orientations, 1, kOrientations);
  for (int o = 0; o < orientations; ++o) {
    // o&1: preferred direction (0 horizontal rows joined by vertical links, 1 the transpose);
    // o&2: link position ascending/descending; o&4: secondary order reversed.
    const bool pref_h = !(o & 1);
    const int s1 = (o & 2) ? -1 : 1, s2 = (o & 4) ? -1 : 1;
    std::stable_sort(order.begin(), order.end(), [&](const TreeEdge& x, const TreeEdge& y) {
      const bool xp = x.horizontal == pref_h, yp = y.horizontal == pref_h;
      if (xp != yp) return xp;
      if (xp) return false;
      // links: vertical links ordered by column (then row), horizontal ones by row (then column)
      const int xk1 = pref_h ? x.col : x.row, yk1 = pref_h ? y.col : y.row;
      if (xk1 != yk1) return s1 * xk1 < s1 * yk1;
      const int xk2 = pref_h ? x.row : x.col, yk2 = pref_h ? y.row : y.col;
      return s2 * xk2 < s2 * yk2;
    });
    Dsu dsu(static_cast<int>(in.size()));
    std::fill(tree.begin(), tree.end(), 0);
    for (const auto& e : order) {
      if (!dsu.unite(e.a, e.b)) continue;
      if (e.horizontal) {
        tree[e.a] |= 1;
        tree[e.b] |= 4;
      } else {
        tree[e.a] |= 2;
        tree[e.b] |= 8;
      }
    }
    std::vector<int> turning = circumnavigate(loc, tree);
    if (best.empty() || turning.size() < best.size()) {
      best = std::move(turning);
      out.orientation = o;
    }
    order = loc.edges;
  }

  // start at the turning vertex nearest the entry point
  const int SW = 2 * loc.w;
  auto to_local = [&](int s) { return g.sub_centre(s % SW + 2 * loc.c0, s / SW + 2 * loc.r0); };
  std::size_t first = 0;
  double bd = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < best.size(); ++i) {
    const Point p = to_local(best[i]);
    const double d = (p.x() - entry.x()) * (p.x() - entry.x()) + (p.y() - entry.y()) * (p.y() - entry.y());
    if (d < bd) bd = d, first = i;
  }
  out.points.reserve(best.size() + 1);
  for (std::size_t i = 0; i <= best.size(); ++i)
    out.points.push_back(to_local(best[(first + i) % best.size()]));
  out.turns = static_cast<int>(best.size());
  return out;
}

}  // namespace uavcover::stc
