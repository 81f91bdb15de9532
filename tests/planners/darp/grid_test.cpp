// Grid rasterisation, placement index and placement search (issue 3, paper §2.1-2.2).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/geometry.hpp"
#include "planners/darp/grid.hpp"
#include "planners/darp/placement.hpp"

namespace uavcover::grid {
namespace {

Polygon rect(double x0, double y0, double x1, double y1) {
  Polygon p;
  p.outer() = {{x0, y0}, {x0, y1}, {x1, y1}, {x1, y0}, {x0, y0}};
  bg::correct(p);
  return p;
}

Prepared prep_of(const MultiPolygon& area, const MultiPolygon& nfz, double ds, Mode mode) {
  const MultiPolygon no_fly = geometry::unite(nfz);
  return prepare(geometry::free_space(area, no_fly), no_fly, ds, mode);
}

TEST(Grid, RectangleFitsExactly) {
  const Prepared p = prep_of({rect(0, 0, 200, 120)}, {}, 20, Mode::Strict);
  const Grid g = rasterize(p, 0, 0, 0);
  EXPECT_EQ(g.rows, 3);
  EXPECT_EQ(g.cols, 5);
  EXPECT_EQ(g.free_cells, 15);
  const Score s = score(p, g);
  EXPECT_NEAR(s.J1, 15 * 1600.0 / (200 * 120), 1e-9);
  EXPECT_NEAR(s.J2, 1.0, 1e-9);
  EXPECT_NEAR(s.J3, 0.0, 1e-9);
  EXPECT_EQ(s.components, 1);
  EXPECT_NEAR(coverage_proxy(p, g), 1.0, 1e-9);
  EXPECT_NEAR(g.coverage_estimate, 1.0, 1e-9);
  // all links inside the rectangle exist
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      EXPECT_EQ((g.link[g.idx(r, c)] & 1) != 0, c + 1 < g.cols);
      EXPECT_EQ((g.link[g.idx(r, c)] & 2) != 0, r + 1 < g.rows);
    }
}

TEST(Grid, ShiftMovesThePolygonOverTheGrid) {
  const Prepared p = prep_of({rect(0, 0, 200, 120)}, {}, 20, Mode::Strict);
  // shifted by half a sub-cell the last sub-cell centres fall outside: one column and row fewer
  const Grid g = rasterize(p, 10, 10, 0);
  EXPECT_EQ(g.free_cells, 8);
  // frames round-trip
  const Point a{37, -12};
  const Grid h = rasterize(p, 13, 7, 33);
  const Point b = h.local_to_q(a), c = h.q_to_local(b.x(), b.y());
  EXPECT_NEAR(c.x(), a.x(), 1e-9);
  EXPECT_NEAR(c.y(), a.y(), 1e-9);
}

// Scanline classification equals point-in-polygon on every sub-cell centre (strict mode, no
// boundary crossing), over random polygons, shifts and rotations.
TEST(Grid, ScanlineMatchesPointInPolygon) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  for (int t = 0; t < 30; ++t) {
    // star-shaped random polygon around the origin
    Polygon poly;
    const int n = 5 + t % 9;
    for (int k = 0; k < n; ++k) {
      const double a = 2 * M_PI * k / n, r = 150 + 250 * u(rng);
      poly.outer().push_back({r * std::cos(a), r * std::sin(a)});
    }
    poly.outer().push_back(poly.outer().front());
    bg::correct(poly);
    MultiPolygon nfz;
    if (t % 2) nfz.push_back(rect(-40, -30, 30 + 40 * u(rng), 40));
    const Prepared p = prep_of({poly}, nfz, 15, Mode::Strict);
    const MultiPolygon free = geometry::free_space({poly}, geometry::unite(nfz));
    const Grid g = rasterize(p, 30 * u(rng), 30 * u(rng), 90 * u(rng));
    for (int r = 0; r < g.rows; ++r)
      for (int c = 0; c < g.cols; ++c) {
        bool all_in = true;
        for (int j = 0; j < 2; ++j)
          for (int i = 0; i < 2; ++i) all_in &= bg::within(g.sub_centre(2 * c + i, 2 * r + j), free);
        // the segment check may block more, never less
        if (g.free[g.idx(r, c)]) {
          EXPECT_TRUE(all_in) << "t=" << t << " cell " << r << "," << c;
        }
      }
    // and free cells are almost all cells with all centres inside (only notches differ)
    int inside = 0;
    for (int r = 0; r < g.rows; ++r)
      for (int c = 0; c < g.cols; ++c) {
        bool all_in = true;
        for (int j = 0; j < 2; ++j)
          for (int i = 0; i < 2; ++i) all_in &= bg::within(g.sub_centre(2 * c + i, 2 * r + j), free);
        inside += all_in;
      }
    EXPECT_LE(g.free_cells, inside);
    EXPECT_GE(g.free_cells, inside - 2 * n - 8) << "t=" << t;
  }
}

TEST(Grid, CoverageModeUsesCellCentres) {
  // a triangle: coverage mode keeps cells whose centre is inside, strict mode fewer
  Polygon tri;
  tri.outer() = {{0, 0}, {400, 0}, {0, 300}, {0, 0}};
  bg::correct(tri);
  const Prepared ps = prep_of({tri}, {}, 20, Mode::Strict);
  const Prepared pc = prep_of({tri}, {}, 20, Mode::Coverage);
  const Grid gs = rasterize(ps, 0, 0, 0), gc = rasterize(pc, 0, 0, 0);
  EXPECT_GT(gc.free_cells, gs.free_cells);
  for (int r = 0; r < gc.rows; ++r)
    for (int c = 0; c < gc.cols; ++c)
      EXPECT_EQ(gc.free[gc.idx(r, c)] != 0, bg::within(gc.cell_centre(r, c), tri)) << r << "," << c;
}

TEST(Grid, NoFlyZoneBlocksCellsInBothModes) {
  // a small pylon at a sub-cell centre of cell (1,1): blocked in both modes
  for (Mode m : {Mode::Strict, Mode::Coverage}) {
    const Prepared p = prep_of({rect(0, 0, 200, 200)}, {rect(45, 45, 55, 55)}, 20, m);
    const Grid g = rasterize(p, 0, 0, 0);
    EXPECT_FALSE(g.free[g.idx(1, 1)]);
    EXPECT_EQ(g.free_cells, 24);
  }
}

TEST(Grid, ThinNoFlyZoneBetweenCentresBlocksCellOrLink) {
  // a 2 m wide wall crossing the square path of cell (1,1) between its sub-cell centres
  {
    const Prepared p = prep_of({rect(0, 0, 200, 200)}, {rect(59, 35, 61, 65)}, 20, Mode::Coverage);
    const Grid g = rasterize(p, 0, 0, 0);
    EXPECT_FALSE(g.free[g.idx(1, 1)]);
  }
  // a wall on the border between cells (1,1) and (1,2) cuts their connectors only
  {
    const Prepared p = prep_of({rect(0, 0, 200, 200)}, {rect(79, 45, 81, 75)}, 20, Mode::Strict);
    const Grid g = rasterize(p, 0, 0, 0);
    EXPECT_TRUE(g.free[g.idx(1, 1)]);
    EXPECT_TRUE(g.free[g.idx(1, 2)]);
    EXPECT_FALSE(g.link[g.idx(1, 1)] & 1);
    EXPECT_TRUE(g.link[g.idx(0, 1)] & 1);
  }
}

TEST(Grid, DisconnectedGridIsPenalised) {
  // a wall through the whole field cuts the free space in two
  const Prepared p = prep_of({rect(0, 0, 200, 200)}, {rect(79, -10, 81, 210)}, 20, Mode::Strict);
  const Grid g = rasterize(p, 0, 0, 0);
  std::vector<int> label;
  EXPECT_EQ(components(g, label), 2);
  const Score s = score(p, g);
  EXPECT_EQ(p.free_parts, 2);  // the free space itself is two polygons: no penalty
  EXPECT_NEAR(s.J, Weights{}.a * s.J1 + Weights{}.b * s.J2 - Weights{}.c * s.J3, 1e-12);
  // a notch that disconnects the grid without splitting the polygon is penalised
  Polygon u;
  u.outer() = {{0, 0}, {200, 0}, {200, 200}, {105, 200}, {105, 30}, {95, 30}, {95, 200}, {0, 200}, {0, 0}};
  bg::correct(u);
  const Prepared q = prep_of({u}, {}, 20, Mode::Strict);
  const Grid h = rasterize(q, 0, 0, 0);
  const Score t = score(q, h);
  EXPECT_GT(t.components, 1);
  EXPECT_NEAR(t.J, Weights{}.a * t.J1 + Weights{}.b * t.J2 - Weights{}.c * t.J3 - 0.5, 1e-12);
}

TEST(Placement, ImprovesOnTheDefaultAndIsDeterministic) {
  Polygon poly;
  poly.outer() = {{0, 0}, {530, 90}, {610, 420}, {140, 470}, {-60, 260}, {0, 0}};
  bg::correct(poly);
  const Prepared p = prep_of({poly}, {}, 20, Mode::Strict);
  PlacementOptions o;
  o.seed = 3;
  const PlacementResult a = optimise_placement(p, o), b = optimise_placement(p, o);
  const Score s0 = score(p, rasterize(p, 0, 0, 0), o.weights);
  EXPECT_GE(score(p, a.grid, o.weights).key, s0.key);
  EXPECT_EQ(a.placement.shift_x_m, b.placement.shift_x_m);
  EXPECT_EQ(a.placement.rotation_deg, b.placement.rotation_deg);
  EXPECT_EQ(a.grid.free, b.grid.free);
  EXPECT_GE(a.placement.shift_x_m, 0);
  EXPECT_LT(a.placement.shift_x_m, 40);
  EXPECT_GE(a.placement.rotation_deg, 0);
  EXPECT_LT(a.placement.rotation_deg, 90);
  EXPECT_LE(a.placement.evaluations, o.evaluations);
  EXPECT_GT(a.placement.evaluations, o.evaluations / 2);
  const Score sa = score(p, a.grid, o.weights);
  EXPECT_NEAR(a.placement.J, sa.J, 1e-12);
  EXPECT_NEAR(a.placement.J1, sa.J1, 1e-12);
  // the first edge runs at about 9.6 degrees: the best grid follows it
  const double th = a.placement.rotation_deg;
  EXPECT_LT(std::min(std::fabs(th - 9.64), std::fabs(th - 9.64 - 90)), 6.0) << th;
}

// A stop_early that fires (the time limit, less the time the finishing stages need) is asked before
// every evaluation, not every 8th, and ends the re-ranking too: the search evaluates once more at most
// and the result is the best placement seen, on its own grid.
TEST(Placement, StopEarlyIsAskedBeforeEveryEvaluationAndEndsTheReranking) {
  Polygon poly;
  poly.outer() = {{0, 0}, {530, 90}, {610, 420}, {140, 470}, {-60, 260}, {0, 0}};
  bg::correct(poly);
  const Prepared p = prep_of({poly}, {}, 20, Mode::Strict);
  for (const int fire_at : {1, 3, 11}) {
    PlacementOptions o;
    o.seed = 3;
    int asked = 0, asked_after = 0;
    o.stop_early = [&] {
      ++asked;
      if (asked > fire_at) ++asked_after;
      return asked >= fire_at;
    };
    const PlacementResult r = optimise_placement(p, o);
    // asked before the 2nd, 3rd, ... evaluation; the one it fired before is still made
    EXPECT_EQ(r.placement.evaluations, fire_at + 1) << fire_at;
    EXPECT_EQ(asked_after, 0) << "asked again after it fired (the re-ranking ran): " << fire_at;
    const Score s = score(p, r.grid, o.weights);
    EXPECT_NEAR(r.placement.J, s.J, 1e-12);
    EXPECT_GE(s.key, score(p, rasterize(p, 0, 0, 0), o.weights).key);
  }
  // never firing: the whole budget, then the re-ranking asks once per candidate
  PlacementOptions o;
  o.seed = 3;
  int asked = 0;
  o.stop_early = [&] { return ++asked < 0; };
  const PlacementResult full = optimise_placement(p, o);
  EXPECT_GT(asked, full.placement.evaluations - 1);
  PlacementOptions plain;
  plain.seed = 3;
  const PlacementResult same = optimise_placement(p, plain);
  EXPECT_EQ(full.grid.free, same.grid.free);
  EXPECT_EQ(full.placement.rotation_deg, same.placement.rotation_deg);
}

TEST(Placement, DisabledKeepsTheIdentity) {
  const Prepared p = prep_of({rect(0, 0, 300, 200)}, {}, 20, Mode::Strict);
  PlacementOptions o;
  o.optimise = false;
  const PlacementResult r = optimise_placement(p, o);
  EXPECT_EQ(r.placement.evaluations, 1);
  EXPECT_EQ(r.placement.rotation_deg, 0);
  EXPECT_EQ(r.grid.free_cells, 5 * 7);
}

}  // namespace
}  // namespace uavcover::grid
