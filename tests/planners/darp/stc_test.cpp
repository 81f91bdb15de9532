// Spanning Tree Coverage loops (issue 3, paper §2.3.2).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <set>

#include "geometry/geometry.hpp"
#include "planners/darp/grid.hpp"
#include "planners/darp/stc.hpp"

namespace uavcover::stc {
namespace {

using grid::Grid;

/// A synthetic grid: `mask` rows top to bottom, '#' free; all links between free neighbours.
Grid make_grid(const std::vector<std::string>& mask, double ds = 10, double theta = 0) {
  Grid g;
  g.ds = ds;
  g.dn = 2 * ds;
  g.theta_deg = theta;
  g.cos_t = std::cos(theta * M_PI / 180);
  g.sin_t = std::sin(theta * M_PI / 180);
  g.rows = static_cast<int>(mask.size());
  g.cols = static_cast<int>(mask[0].size());
  g.free.assign(g.rows * g.cols, 0);
  g.link.assign(g.rows * g.cols, 0);
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) g.free[g.idx(r, c)] = mask[g.rows - 1 - r][c] == '#';
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      const int k = g.idx(r, c);
      if (!g.free[k]) continue;
      ++g.free_cells;
      if (c + 1 < g.cols && g.free[k + 1]) g.link[k] |= 1;
      if (r + 1 < g.rows && g.free[k + g.cols]) g.link[k] |= 2;
    }
  return g;
}

std::vector<int> all_free(const Grid& g) {
  std::vector<int> v;
  for (int k = 0; k < g.rows * g.cols; ++k)
    if (g.free[k]) v.push_back(k);
  return v;
}

/// Expands the loop into unit steps (in sub-cell indices) and checks it is a Hamiltonian cycle
/// over the sub-cells of `cells`, moving only between 4-neighbours.
void check_hamiltonian(const Grid& g, const std::vector<int>& cells, const Loop& loop) {
  ASSERT_GE(loop.points.size(), 5u);
  ASSERT_TRUE(bg::equals(loop.points.front(), loop.points.back()));
  EXPECT_EQ(loop.turns, static_cast<int>(loop.points.size()) - 1);
  auto sub_of = [&](Point p) {
    const Point q = g.local_to_q(p);
    const double i = (q.x() - g.x0) / g.ds - 0.5, j = (q.y() - g.y0) / g.ds - 0.5;
    EXPECT_NEAR(i, std::round(i), 1e-6);
    EXPECT_NEAR(j, std::round(j), 1e-6);
    return std::pair<int, int>(static_cast<int>(std::lround(i)), static_cast<int>(std::lround(j)));
  };
  std::set<std::pair<int, int>> expected;
  for (int k : cells) {
    const int r = k / g.cols, c = k % g.cols;
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) expected.insert({2 * c + i, 2 * r + j});
  }
  std::map<std::pair<int, int>, int> visits;
  for (std::size_t k = 1; k < loop.points.size(); ++k) {
    auto [i0, j0] = sub_of(loop.points[k - 1]);
    auto [i1, j1] = sub_of(loop.points[k]);
    ASSERT_TRUE(i0 == i1 || j0 == j1) << "diagonal leg";
    const int di = (i1 > i0) - (i1 < i0), dj = (j1 > j0) - (j1 < j0);
    for (int i = i0, j = j0; i != i1 || j != j1; i += di, j += dj) ++visits[{i, j}];
  }
  EXPECT_EQ(visits.size(), expected.size());
  for (const auto& [s, n] : visits) {
    EXPECT_EQ(n, 1) << "sub-cell " << s.first << "," << s.second << " visited " << n << " times";
    EXPECT_TRUE(expected.count(s)) << "sub-cell " << s.first << "," << s.second << " outside the region";
  }
  // consecutive vertices turn (only turning waypoints are output)
  const auto& p = loop.points;
  const std::size_t n = p.size() - 1;
  for (std::size_t k = 0; k < n; ++k) {
    const Point a = p[(k + n - 1) % n], b = p[k], c = p[(k + 1) % n];
    const double cross = (b.x() - a.x()) * (c.y() - b.y()) - (b.y() - a.y()) * (c.x() - b.x());
    EXPECT_GT(std::fabs(cross), 1e-6) << "vertex " << k << " is not a turn";
  }
}

TEST(Stc, SingleCellIsASquare) {
  const Grid g = make_grid({"#"});
  const Loop l = plan_loop(g, all_free(g), {0, 0});
  check_hamiltonian(g, all_free(g), l);
  EXPECT_EQ(l.turns, 4);
}

TEST(Stc, RectangleNeedsFewTurns) {
  for (auto [w, h] : {std::pair{7, 10}, std::pair{10, 3}, std::pair{1, 8}, std::pair{12, 12}}) {
    const Grid g = make_grid(std::vector<std::string>(h, std::string(w, '#')));
    const Loop l = plan_loop(g, all_free(g), {0, 0});
    check_hamiltonian(g, all_free(g), l);
    // a boustrophedon on the sub-cells: two turns per lane across the short side, plus the spine
    EXPECT_LE(l.turns, 4 * std::min(w, h) + 4) << w << "x" << h;
  }
}

TEST(Stc, IrregularRegionsAreCoveredOnce) {
  std::mt19937_64 rng(5);
  for (int t = 0; t < 40; ++t) {
    // random blob grown from the centre
    const int W = 6 + t % 9, H = 5 + t % 7;
    std::vector<std::string> m(H, std::string(W, '.'));
    std::uniform_int_distribution<int> ur(0, H - 1), uc(0, W - 1);
    m[H / 2][W / 2] = '#';
    for (int k = 0; k < W * H; ++k) {
      const int r = ur(rng), c = uc(rng);
      const bool near = (r > 0 && m[r - 1][c] == '#') || (r + 1 < H && m[r + 1][c] == '#') ||
                        (c > 0 && m[r][c - 1] == '#') || (c + 1 < W && m[r][c + 1] == '#');
      if (near) m[r][c] = '#';
    }
    const Grid g = make_grid(m, 7.5, 17.0 * t);
    const Loop l = plan_loop(g, all_free(g), {0, 0});
    SCOPED_TRACE(t);
    check_hamiltonian(g, all_free(g), l);
  }
}

TEST(Stc, LoopStartsAtTheTurnNearestTheEntry) {
  const Grid g = make_grid({"####", "####", "####"});
  for (Point entry : {Point{-50, -50}, Point{200, 100}, Point{40, 70}}) {
    const Loop l = plan_loop(g, all_free(g), entry);
    double best = 1e18;
    for (const auto& p : l.points) best = std::min(best, bg::distance(p, entry));
    EXPECT_NEAR(bg::distance(l.points.front(), entry), best, 1e-9);
  }
}

TEST(Stc, FollowsTheLinksOnly) {
  // two rows joined only at the left end: the loop must not use the missing links
  Grid g = make_grid({"#####", "#####"});
  for (int c = 1; c < 5; ++c) g.link[g.idx(0, c)] &= ~2;
  const Loop l = plan_loop(g, all_free(g), {0, 0});
  check_hamiltonian(g, all_free(g), l);
  // no leg crosses between the rows except at column 0 (x in [0, 20))
  for (std::size_t k = 1; k < l.points.size(); ++k) {
    const Point a = g.local_to_q(l.points[k - 1]), b = g.local_to_q(l.points[k]);
    if ((a.y() < 20) != (b.y() < 20)) {
      EXPECT_LT(a.x(), 20);
    }
  }
}

TEST(Stc, OneTreeOrientationCostsTurnsTheSearchSaves) {
  // the paper's Fig. 9: without choosing the tree's orientation a tall strip is swept in short rows
  const Grid strip = make_grid(std::vector<std::string>(12, "##"));
  const Loop one = plan_loop(strip, all_free(strip), {0, 0}, 1);
  const Loop best = plan_loop(strip, all_free(strip), {0, 0});
  check_hamiltonian(strip, all_free(strip), one);
  EXPECT_EQ(one.orientation, 0);
  EXPECT_GE(one.turns, 2 * best.turns) << one.turns << " vs " << best.turns;

  // on random blobs one orientation is a Hamiltonian loop too, never with fewer turns, and often more
  std::mt19937_64 rng(11);
  int more = 0;
  for (int t = 0; t < 30; ++t) {
    const int W = 5 + t % 8, H = 4 + t % 6;
    std::vector<std::string> m(H, std::string(W, '.'));
    std::uniform_int_distribution<int> ur(0, H - 1), uc(0, W - 1);
    m[H / 2][W / 2] = '#';
    for (int k = 0; k < 2 * W * H; ++k) {
      const int r = ur(rng), c = uc(rng);
      if ((r > 0 && m[r - 1][c] == '#') || (r + 1 < H && m[r + 1][c] == '#') ||
          (c > 0 && m[r][c - 1] == '#') || (c + 1 < W && m[r][c + 1] == '#'))
        m[r][c] = '#';
    }
    const Grid g = make_grid(m);
    SCOPED_TRACE(t);
    const Loop a = plan_loop(g, all_free(g), {0, 0}, 1), b = plan_loop(g, all_free(g), {0, 0});
    check_hamiltonian(g, all_free(g), a);
    EXPECT_GE(a.turns, b.turns);
    more += a.turns > b.turns;
  }
  EXPECT_GE(more, 10);
}

}  // namespace
}  // namespace uavcover::stc
