// DARP paths keep grid::kClearance from every no-fly zone, however thin (regression: a path 1 mm beside
// a 1 m wide zone landed inside it once its waypoints were rounded to 1e-7 degrees, and the export
// refused the plan).
#include <gtest/gtest.h>

#include <cmath>

#include "planners/darp/darp_props.hpp"

namespace uavcover::test {
namespace {

using Seg = bg::model::segment<Point>;

/// The smallest distance between any loop segment of the plan and the no-fly zones.
double min_clearance(const darp::Output& out, const MultiPolygon& no_fly) {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& u : out.uavs)
    for (const auto& loop : u.loops)
      for (std::size_t k = 1; k < loop.size(); ++k)
        d = std::min(d, bg::distance(Seg(loop[k - 1], loop[k]), no_fly));
  return d;
}

darp::Options fixed_grid() {
  darp::Options o;
  o.optimise_placement = false;  // the grid at shift 0, rotation 0: sub-cell centres at x, y = 2, 6, 10, ...
  return o;
}

TEST(DarpClearance, ThinZoneOneMillimetreBesideThePathLine) {
  // a 1 m wide zone whose edge runs 1 mm beside the path line x = 6
  for (Mode mode : {Mode::Strict, Mode::Coverage}) {
    const MultiPolygon area{rect(0, 0, 200, 200)}, nfz{rect(6.001, 20, 7.001, 180)};
    const darp::Input in = make_input(area, nfz, {{-10, -10}}, {1.0}, 4, mode, 1);
    const darp::Output out = darp::run(in, fixed_grid(), Context{});
    check_plan(in, out, true);
    EXPECT_GE(min_clearance(out, in.no_fly), grid::kClearance - 1e-9)
        << (mode == Mode::Strict ? "strict" : "coverage");
  }
}

TEST(DarpClearance, ThinZoneTouchingASubCellCentre) {
  // a 1 m wide diagonal hedge whose corner sits 1 mm from the sub-cell centre (10, 10)
  for (Mode mode : {Mode::Strict, Mode::Coverage}) {
    const MultiPolygon area{rect(0, 0, 120, 120)};
    const MultiPolygon nfz{poly({{10.001, 10.0}, {11.0, 9.3}, {100, 98.3}, {99.0, 99.0}})};
    const darp::Input in = make_input(area, nfz, {{-10, -10}, {130, 130}}, {0.5, 0.5}, 4, mode, 2);
    const darp::Output out = darp::run(in, fixed_grid(), Context{});
    check_plan(in, out, false);
    EXPECT_GE(min_clearance(out, in.no_fly), grid::kClearance - 1e-9)
        << (mode == Mode::Strict ? "strict" : "coverage");
  }
}

TEST(DarpClearance, DiagonalHedgesOnAnOptimisedGrid) {
  // 1 m wide hedges at 45 degrees every 14 m (the web benchmark's field, smaller), placement searched
  MultiPolygon area{rect(0, 0, 120, 120)}, nfz;
  const double half = std::sqrt(0.5);
  for (double c = -120 + 14; c < 120 - 14; c += 14) {
    const double y0 = std::max(6.0, 6.0 - c), y1 = std::min(114.0, 114.0 - c);
    if (y1 - y0 <= 20) continue;
    nfz.push_back(poly({{y0 + c - half, y0}, {y0 + c + half, y0}, {y1 + c + half, y1}, {y1 + c - half, y1}}));
  }
  for (Mode mode : {Mode::Strict, Mode::Coverage}) {
    const darp::Input in = make_input(area, nfz, {{-20, -20}, {120, 120}}, {0.5, 0.5}, 4, mode, 3);
    darp::Options o;
    o.placement_evaluations = 300;
    const darp::Output out = darp::run(in, o, Context{});
    check_plan(in, out, false);
    EXPECT_GE(min_clearance(out, in.no_fly), grid::kClearance - 1e-9)
        << (mode == Mode::Strict ? "strict" : "coverage");
  }
}

}  // namespace
}  // namespace uavcover::test
