#include "planners/boustrophedon/ordering.hpp"

#include <algorithm>
#include <limits>

#include "planners/boustrophedon/geom.hpp"

namespace uavcover::planners::boustro {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Best ways for a fixed order (dynamic programming over the four ways of each cell).
/// The first leg's distance is counted `first_weight` times (a fixed entry weighs it heavily); the tour
/// ends at `home`.
double best_ways(const std::vector<CellEnds>& cells, const std::vector<int>& order, Point start, Point home,
                 double first_weight, std::vector<int>* ways) {
  const std::size_t n = order.size();
  if (n == 0) return 0.0;
  std::vector<std::array<double, 4>> cost(n);
  std::vector<std::array<int, 4>> from(n);
  const CellEnds& c0 = cells[static_cast<std::size_t>(order[0])];
  for (int v = 0; v < 4; ++v)
    cost[0][static_cast<std::size_t>(v)] = first_weight * dist(start, c0.entry[static_cast<std::size_t>(v)]);
  for (std::size_t i = 1; i < n; ++i) {
    const CellEnds& prev = cells[static_cast<std::size_t>(order[i - 1])];
    const CellEnds& cur = cells[static_cast<std::size_t>(order[i])];
    for (std::size_t v = 0; v < 4; ++v) {
      double best = kInf;
      int arg = 0;
      for (std::size_t u = 0; u < 4; ++u) {
        const double c = cost[i - 1][u] + dist(prev.exit[u], cur.entry[v]);
        if (c < best) best = c, arg = static_cast<int>(u);
      }
      cost[i][v] = best;
      from[i][v] = arg;
    }
  }
  const CellEnds& last = cells[static_cast<std::size_t>(order[n - 1])];
  double best = kInf;
  int arg = 0;
  for (std::size_t v = 0; v < 4; ++v) {
    const double c = cost[n - 1][v] + dist(last.exit[v], home);
    if (c < best) best = c, arg = static_cast<int>(v);
  }
  if (ways) {
    ways->assign(n, 0);
    for (std::size_t i = n; i-- > 0;) {
      (*ways)[i] = arg;
      arg = from[i][static_cast<std::size_t>(arg)];
    }
  }
  return best;
}

}  // namespace

Tour order_cells(const std::vector<CellEnds>& cells, Point start, const Context& ctx) {
  return order_cells(cells, start, start, 1.0, ctx);
}

Tour order_cells(const std::vector<CellEnds>& cells, Point start, Point home, double first_weight,
                 const Context& ctx) {
  Tour t;
  const std::size_t n = cells.size();
  if (n == 0) return t;
  // greedy: nearest entry next
  std::vector<bool> used(n, false);
  Point here = start;
  for (std::size_t k = 0; k < n; ++k) {
    double best = kInf;
    std::size_t arg = 0, way = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (used[i]) continue;
      for (std::size_t v = 0; v < 4; ++v) {
        const double d = dist(here, cells[i].entry[v]);
        if (d < best) best = d, arg = i, way = v;
      }
    }
    used[arg] = true;
    t.order.push_back(static_cast<int>(arg));
    here = cells[arg].exit[way];
  }
  double cost = best_ways(cells, t.order, start, home, first_weight, nullptr);
  // 2-opt (reverse a block) and or-opt (move a block of 1-3 cells); a deterministic move budget
  long budget = 4'000'000 / static_cast<long>(std::max<std::size_t>(n, 1));
  bool improved = n > 1;
  while (improved && budget > 0) {
    improved = false;
    for (std::size_t i = 0; i < n && budget > 0; ++i) {
      ctx.check();
      for (std::size_t j = i + 1; j < n && budget > 0; ++j, --budget) {
        std::vector<int> cand = t.order;
        std::reverse(cand.begin() + static_cast<std::ptrdiff_t>(i),
                     cand.begin() + static_cast<std::ptrdiff_t>(j) + 1);
        const double c = best_ways(cells, cand, start, home, first_weight, nullptr);
        if (c < cost - 1e-9) {
          cost = c;
          t.order = std::move(cand);
          improved = true;
        }
      }
      for (std::size_t len = 1; len <= 3 && i + len <= n; ++len)
        for (std::size_t j = 0; j + len <= n && budget > 0; ++j, --budget) {
          if (j == i) continue;
          std::vector<int> cand = t.order;
          std::vector<int> block(cand.begin() + static_cast<std::ptrdiff_t>(i),
                                 cand.begin() + static_cast<std::ptrdiff_t>(i + len));
          cand.erase(cand.begin() + static_cast<std::ptrdiff_t>(i),
                     cand.begin() + static_cast<std::ptrdiff_t>(i + len));
          if (j > cand.size()) continue;
          cand.insert(cand.begin() + static_cast<std::ptrdiff_t>(j), block.begin(), block.end());
          const double c = best_ways(cells, cand, start, home, first_weight, nullptr);
          if (c < cost - 1e-9) {
            cost = c;
            t.order = std::move(cand);
            improved = true;
          }
        }
    }
  }
  best_ways(cells, t.order, start, home, first_weight, &t.variant);
  t.transit_m = best_ways(cells, t.order, start, home, 1.0, nullptr);
  return t;
}

}  // namespace uavcover::planners::boustro
