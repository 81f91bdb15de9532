// Property checks shared by the DARP planner tests.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "geometry/geometry.hpp"
#include "planners/darp/darp_planner.hpp"
#include "planners/darp/division.hpp"
#include "planners/darp/grid.hpp"
#include "uavcover/error.hpp"

namespace uavcover::test {

inline Polygon rect(double x0, double y0, double x1, double y1) {
  Polygon p;
  p.outer() = {{x0, y0}, {x0, y1}, {x1, y1}, {x1, y0}, {x0, y0}};
  bg::correct(p);
  return p;
}

inline Polygon poly(std::vector<Point> pts) {
  Polygon p;
  pts.push_back(pts.front());
  p.outer().assign(pts.begin(), pts.end());
  bg::correct(p);
  return p;
}

inline darp::Input make_input(const MultiPolygon& area, const MultiPolygon& nfz, std::vector<Point> starts,
                              std::vector<double> shares, double ds, Mode mode, std::uint64_t seed) {
  darp::Input in;
  in.no_fly = geometry::unite(nfz);
  in.free = geometry::free_space(area, in.no_fly);
  in.starts = std::move(starts);
  in.shares = std::move(shares);
  in.ds = ds;
  in.mode = mode;
  in.seed = seed;
  return in;
}

/// Checks every property of a DARP plan; `expect_converged` also demands convergence.
inline void check_plan(const darp::Input& in, const darp::Output& out, bool expect_converged) {
  const int U = static_cast<int>(in.starts.size());
  ASSERT_EQ(static_cast<int>(out.uavs.size()), U);
  // the grid is reproducible from the placement
  const grid::Prepared prep = grid::prepare(in.free, in.no_fly, in.ds, in.mode);
  const grid::Grid g =
      grid::rasterize(prep, out.placement.shift_x_m, out.placement.shift_y_m, out.placement.rotation_deg);
  ASSERT_EQ(g.rows, out.grid.rows);
  ASSERT_EQ(g.cols, out.grid.cols);
  ASSERT_EQ(out.grid.owner.size(), static_cast<std::size_t>(g.rows * g.cols));
  // exclusive and covering: every free cell has exactly one owner, blocked cells none
  std::vector<int> cells(U, 0);
  for (int k = 0; k < g.rows * g.cols; ++k) {
    if (g.free[k]) {
      ASSERT_GE(out.grid.owner[k], 0) << "free cell " << k << " unassigned";
      ASSERT_LT(out.grid.owner[k], U);
      ++cells[out.grid.owner[k]];
    } else {
      ASSERT_EQ(out.grid.owner[k], -1) << "blocked cell " << k << " assigned";
    }
  }
  for (int i = 0; i < U; ++i) EXPECT_EQ(cells[i], out.uavs[i].cells);
  // each UAV's cells form as many 4-connected regions (over the grid's links) as it has loops
  for (int i = 0; i < U; ++i) {
    std::vector<int> seen(g.rows * g.cols, 0);
    int regions = 0;
    std::array<int, 4> nb{};
    for (int k = 0; k < g.rows * g.cols; ++k) {
      if (out.grid.owner[k] != i || seen[k]) continue;
      ++regions;
      std::vector<int> st{k};
      seen[k] = 1;
      while (!st.empty()) {
        const int u = st.back();
        st.pop_back();
        const int m = g.neighbours(u, nb);
        for (int j = 0; j < m; ++j)
          if (!seen[nb[j]] && out.grid.owner[nb[j]] == i) seen[nb[j]] = 1, st.push_back(nb[j]);
      }
    }
    EXPECT_EQ(regions, static_cast<int>(out.uavs[i].loops.size())) << "UAV " << i;
  }
  // start cells: a start inside a free cell lies in its UAV's region (distinct start cells)
  std::vector<int> start_cell(U, -1);
  for (int i = 0; i < U; ++i) {
    const Point q = g.local_to_q(in.starts[i]);
    const int c = static_cast<int>(std::floor((q.x() - g.x0) / g.dn));
    const int r = static_cast<int>(std::floor((q.y() - g.y0) / g.dn));
    if (r >= 0 && r < g.rows && c >= 0 && c < g.cols && g.free[g.idx(r, c)]) start_cell[i] = g.idx(r, c);
  }
  for (int i = 0; i < U; ++i) {
    bool shared = false;
    for (int j = 0; j < U; ++j) shared |= j != i && start_cell[j] == start_cell[i];
    if (start_cell[i] >= 0 && !shared) {
      EXPECT_EQ(out.grid.owner[start_cell[i]], i) << "UAV " << i;
    }
  }
  // shares
  if (expect_converged) {
    EXPECT_TRUE(out.converged);
  }
  if (out.converged) {
    double ssum = 0;
    for (double s : in.shares) ssum += s;
    for (int i = 0; i < U; ++i) {
      const double target = in.shares[i] / ssum * g.free_cells;
      EXPECT_LE(std::fabs(cells[i] - target), darp::tolerance(target) + 1e-9) << "UAV " << i;
    }
  } else {
    EXPECT_FALSE(out.warnings.empty());
  }
  // loops: closed, inside the free area (strict), never into a no-fly zone
  for (int i = 0; i < U; ++i)
    for (const auto& loop : out.uavs[i].loops) {
      ASSERT_GE(loop.size(), 5u);
      EXPECT_TRUE(bg::equals(loop.front(), loop.back()));
      for (std::size_t k = 1; k < loop.size(); ++k) {
        if (in.mode == Mode::Strict) {
          EXPECT_TRUE(geometry::segment_within(in.free, loop[k - 1], loop[k], 0.5))
              << "UAV " << i << " segment " << k << " leaves the free area";
        }
        EXPECT_FALSE(geometry::segment_enters(in.no_fly, loop[k - 1], loop[k], 0.5))
            << "UAV " << i << " segment " << k << " enters a no-fly zone";
      }
    }
  // paths of different UAVs never meet
  using Seg = bg::model::segment<Point>;
  for (int i = 0; i < U; ++i)
    for (int j = i + 1; j < U; ++j)
      for (const auto& la : out.uavs[i].loops)
        for (const auto& lb : out.uavs[j].loops) {
          bg::model::box<Point> ba, bb;
          bg::envelope(Polyline(la.begin(), la.end()), ba);
          bg::envelope(Polyline(lb.begin(), lb.end()), bb);
          if (!bg::intersects(ba, bb)) continue;
          for (std::size_t a = 1; a < la.size(); ++a)
            for (std::size_t b = 1; b < lb.size(); ++b)
              ASSERT_FALSE(bg::intersects(Seg(la[a - 1], la[a]), Seg(lb[b - 1], lb[b])))
                  << "UAVs " << i << " and " << j << " cross";
        }
}

inline bool same_output(const darp::Output& a, const darp::Output& b) {
  if (a.grid.owner != b.grid.owner || a.uavs.size() != b.uavs.size()) return false;
  if (a.placement.shift_x_m != b.placement.shift_x_m || a.placement.rotation_deg != b.placement.rotation_deg)
    return false;
  for (std::size_t i = 0; i < a.uavs.size(); ++i) {
    if (a.uavs[i].loops.size() != b.uavs[i].loops.size()) return false;
    for (std::size_t l = 0; l < a.uavs[i].loops.size(); ++l) {
      const auto& x = a.uavs[i].loops[l];
      const auto& y = b.uavs[i].loops[l];
      if (x.size() != y.size()) return false;
      for (std::size_t k = 0; k < x.size(); ++k)
        if (x[k].x() != y[k].x() || x[k].y() != y[k].y()) return false;
    }
  }
  return true;
}

}  // namespace uavcover::test
