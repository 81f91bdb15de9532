// Leg extension (extend.hpp): U-turns at the region's edge move toward the boundary. The extended loops
// keep every DARP property (check_plan: inside the free area in strict mode, out of no-fly zones, no
// crossing between UAVs), keep grid::kClearance from the zones, add no turn, and cover more.
#include <gtest/gtest.h>

#include <cmath>

#include "evaluation/coverage.hpp"
#include "planners/darp/darp_props.hpp"

namespace uavcover::test {
namespace {

using Seg = bg::model::segment<Point>;

struct Field {
  MultiPolygon area, nfz;
  std::vector<Point> starts;
  std::vector<double> shares;
};

/// A field with slanted edges (the grid never fits them) and no-fly zones close to its boundary.
Field slanted() {
  return {{poly({{0, 0}, {610, 40}, {700, 380}, {380, 560}, {30, 470}})},
          {rect(300, 15, 330, 60), poly({{640, 200}, {700, 230}, {660, 260}}), rect(150, 250, 170, 270)},
          {{20, 20}, {650, 300}, {300, 520}},
          {0.3, 0.3, 0.4}};
}

darp::Output run(const darp::Input& in, bool extend, bool shift = false) {
  darp::Options o;
  o.placement_evaluations = 200;
  o.extend_legs = extend;
  o.shift_legs = shift;
  return darp::run(in, o, Context{});
}

double poc(const darp::Input& in, const darp::Output& out) {
  std::vector<evaluation::Flight> flights;
  for (const auto& u : out.uavs) {
    evaluation::Flight f;
    for (const auto& loop : u.loops) f.push_back({PartKind::Coverage, loop, {}});
    flights.push_back(std::move(f));
  }
  evaluation::CoverageOptions opt;
  opt.footprint_m = 1.5 * in.ds;
  opt.lattice_m = 2;
  return evaluation::evaluate_coverage(in.free, flights, opt).total.poc;
}

/// Every segment of `loop` keeps grid::kClearance from the no-fly zones; strict: never out of the area.
void expect_clear(const darp::Input& in, const std::vector<Point>& loop, std::size_t uav) {
  for (std::size_t k = 1; k < loop.size(); ++k) {
    EXPECT_GE(bg::distance(Seg(loop[k - 1], loop[k]), in.no_fly), grid::kClearance - 1e-9);
    if (in.mode == Mode::Strict) {
      EXPECT_TRUE(geometry::segment_within(in.free, loop[k - 1], loop[k], 0.02))
          << "UAV " << uav << " leaves the area";
    }
  }
}

class Extension : public ::testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(Extension, KeepsThePropertiesAndTheTurnsAndCoversMore) {
  const auto [mode_i, seed] = GetParam();
  const Mode mode = mode_i == 0 ? Mode::Strict : Mode::Coverage;
  const Field f = slanted();
  const darp::Input in =
      make_input(f.area, f.nfz, f.starts, f.shares, 20, mode, static_cast<std::uint64_t>(seed));
  const darp::Output plain = run(in, false), ext = run(in, true);
  check_plan(in, ext, false);  // strict: inside the free area; both: out of the zones, no crossing
  ASSERT_EQ(plain.grid.owner, ext.grid.owner) << "extension changes the paths only";
  int moved = 0;
  for (std::size_t i = 0; i < ext.uavs.size(); ++i) {
    ASSERT_EQ(plain.uavs[i].loops.size(), ext.uavs[i].loops.size());
    for (std::size_t l = 0; l < ext.uavs[i].loops.size(); ++l) {
      const auto& a = plain.uavs[i].loops[l];
      const auto& b = ext.uavs[i].loops[l];
      ASSERT_EQ(a.size(), b.size()) << "the same turning vertices";
      for (std::size_t k = 0; k + 1 < b.size(); ++k) {
        if (bg::distance(a[k], b[k]) < 1e-9) continue;
        ++moved;
        // only a leg end inside the area moves (one outside, in coverage mode, covers beyond it already)
        EXPECT_TRUE(bg::within(a[k], in.free)) << "UAV " << i << " vertex " << k << " moved from outside";
        // a vertex moves along one of its legs, away from the loop (the leg gets longer)
        const Point& p = a[(k + a.size() - 2) % (a.size() - 1)];
        const Point& n = a[k + 1];
        const double ux = b[k].x() - a[k].x(), uy = b[k].y() - a[k].y();
        const double along_in = std::fabs((a[k].x() - p.x()) * uy - (a[k].y() - p.y()) * ux);
        const double along_out = std::fabs((n.x() - a[k].x()) * uy - (n.y() - a[k].y()) * ux);
        EXPECT_TRUE(along_in < 1e-6 * bg::distance(p, a[k]) * std::hypot(ux, uy) + 1e-9 ||
                    along_out < 1e-6 * bg::distance(n, a[k]) * std::hypot(ux, uy) + 1e-9)
            << "UAV " << i << " vertex " << k << " leaves its legs' lines";
      }
      expect_clear(in, b, i);
    }
  }
  EXPECT_GT(moved, 0) << "a field with slanted edges has U-turns to extend";
  EXPECT_GT(poc(in, ext), poc(in, plain));
}

INSTANTIATE_TEST_SUITE_P(ModesAndSeeds, Extension,
                         ::testing::Combine(::testing::Values(0, 1), ::testing::Values(1, 2)));

TEST(Extension, StrictRectangleOnItsGridIsUnchanged) {
  // a rectangle the grid fits exactly: the U-turns sit ds/2 from the boundary, nothing to extend
  const darp::Input in = make_input({rect(0, 0, 400, 240)}, {}, {{-10, -10}}, {1.0}, 20, Mode::Strict, 1);
  darp::Options o;
  o.optimise_placement = false;
  const darp::Output ext = darp::run(in, o, Context{});
  o.extend_legs = false;
  o.shift_legs = false;
  const darp::Output plain = darp::run(in, o, Context{});
  EXPECT_TRUE(same_output(plain, ext));
}

// Leg shifting (LegExtender::shift): legs along a region's outer edge move outward, across their own
// direction, toward the boundary beside them.
class Shift : public ::testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(Shift, KeepsThePropertiesAndTheTurnsAndCoversMore) {
  const auto [mode_i, seed] = GetParam();
  const Mode mode = mode_i == 0 ? Mode::Strict : Mode::Coverage;
  const Field f = slanted();
  const darp::Input in =
      make_input(f.area, f.nfz, f.starts, f.shares, 20, mode, static_cast<std::uint64_t>(seed));
  const darp::Output ext = run(in, true), both = run(in, true, true);
  check_plan(in, both, false);  // strict: inside the free area; both: out of the zones, no crossing
  ASSERT_EQ(ext.grid.owner, both.grid.owner) << "shifting changes the paths only";
  int moved = 0;
  for (std::size_t i = 0; i < both.uavs.size(); ++i) {
    ASSERT_EQ(ext.uavs[i].loops.size(), both.uavs[i].loops.size());
    for (std::size_t l = 0; l < both.uavs[i].loops.size(); ++l) {
      const auto& a = ext.uavs[i].loops[l];
      const auto& b = both.uavs[i].loops[l];
      ASSERT_EQ(a.size(), b.size()) << "the same turning vertices";
      for (std::size_t k = 0; k + 1 < b.size(); ++k) {
        const double d = bg::distance(a[k], b[k]);
        if (d < 1e-9) continue;
        ++moved;
        // at most 0.45 ds across each of its two legs
        EXPECT_LE(d, 0.45 * in.ds * std::sqrt(2.0) + 1e-9) << "UAV " << i << " vertex " << k;
      }
      expect_clear(in, b, i);
    }
  }
  if (mode == Mode::Strict) {
    // coverage mode's cells reach past the boundary (their centre inside): there, some grids leave no
    // band that a shifted leg would cover (seed 2); LegsAlongTheEdgesReachTheBoundary covers that mode
    EXPECT_GT(moved, 0) << "a field with slanted edges has legs along its edges";
    EXPECT_GT(poc(in, both), poc(in, ext));
  } else {
    EXPECT_GE(poc(in, both), poc(in, ext));
  }
}

INSTANTIATE_TEST_SUITE_P(ModesAndSeeds, Shift,
                         ::testing::Combine(::testing::Values(0, 1), ::testing::Values(1, 2)));

TEST(Shift, LegsAlongTheEdgesReachTheBoundary) {
  // the grid (shift 0, rotation 0, ds 20) leaves a 20 m band along the right and top edges: the outer
  // lanes run 40 m from the boundary, their swath reaches 15 m. Extension covers the band at the U-turns;
  // shifting the legs along the band by 5 m covers the rest, in both modes, with the same turns.
  for (const Mode mode : {Mode::Strict, Mode::Coverage}) {
    const darp::Input in = make_input({rect(0, 0, 410, 250)}, {}, {{-10, -10}}, {1.0}, 20, mode, 1);
    darp::Options o;
    o.optimise_placement = false;
    o.shift_legs = false;
    const darp::Output ext = darp::run(in, o, Context{});
    o.shift_legs = true;
    const darp::Output both = darp::run(in, o, Context{});
    check_plan(in, both, true);
    ASSERT_EQ(ext.uavs[0].loops[0].size(), both.uavs[0].loops[0].size());
    EXPECT_LT(poc(in, ext), 0.995);
    EXPECT_GT(poc(in, both), 0.9999);
  }
}

}  // namespace
}  // namespace uavcover::test
