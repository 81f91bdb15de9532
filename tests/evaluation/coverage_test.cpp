// Coverage simulation on hand-computable cases.
#include <gtest/gtest.h>

#include <cmath>

#include "evaluation/coverage.hpp"
#include "support/shapes.hpp"
#include "uavcover/error.hpp"

using namespace uavcover;
using namespace uavcover::evaluation;

namespace {

MultiPolygon rect(double x0, double y0, double x1, double y1) {
  return MultiPolygon{uavcover::testing::rect(x0, y0, x1, y1)};
}

PathPart part(std::vector<Point> pts, PartKind kind = PartKind::Coverage) {
  return PathPart{kind, std::move(pts), {}};
}

CoverageOptions opts(double w, double lattice = 1.0) {
  CoverageOptions o;
  o.footprint_m = w;
  o.lattice_m = lattice;
  return o;
}

}  // namespace

TEST(Coverage, LatticeSamplesTheFreeArea) {
  const auto r = evaluate_coverage(rect(0, 0, 100, 50), {}, opts(10));
  EXPECT_EQ(r.samples, 5000u);
  EXPECT_DOUBLE_EQ(r.total.area_m2, 5000.0);
  EXPECT_DOUBLE_EQ(r.total.poc, 0.0);
  ASSERT_EQ(r.total.histogram.size(), 1u);
  EXPECT_DOUBLE_EQ(r.total.histogram[0], 1.0);
}

TEST(Coverage, SingleStraightLegGivesExactPoc) {
  // leg (10,25)-(60,25), w = 10: rectangle x in [5,65], y in [20,30] = 60 x 10 samples of 5000
  const auto r = evaluate_coverage(rect(0, 0, 100, 50), {{part({{10, 25}, {60, 25}})}}, opts(10));
  EXPECT_DOUBLE_EQ(r.total.poc, 600.0 / 5000.0);
  EXPECT_DOUBLE_EQ(r.total.pooc, 0.0);
  EXPECT_EQ(r.total.max_scans, 1);
  EXPECT_DOUBLE_EQ(r.total.length_m, 50.0);
  EXPECT_EQ(r.total.turns, 2);
  ASSERT_EQ(r.uavs.size(), 1u);
  EXPECT_DOUBLE_EQ(r.uavs[0].stats.poc, r.total.poc);
  EXPECT_DOUBLE_EQ(r.uavs[0].area_share, 1.0);
}

TEST(Coverage, TwoParallelLegsOverlapInABandOfHalfTheSpacing) {
  // ds = 10, w = 1.5 ds: bands y in [12.7,27.7] and [22.7,37.7], overlap [22.7,27.7] (0.5 ds),
  // x in [2.7, 97.3] -> 94 columns
  const double ds = 10.0;
  const auto r = evaluate_coverage(rect(0, 0, 100, 50),
                                   {{part({{10.2, 20.2}, {89.8, 20.2}}), part({{10.2, 30.2}, {89.8, 30.2}})}},
                                   opts(1.5 * ds));
  EXPECT_DOUBLE_EQ(r.total.poc, 25.0 * 94 / 5000.0);
  EXPECT_DOUBLE_EQ(r.total.pooc, 5.0 * 94 / 5000.0);
  EXPECT_EQ(r.total.max_scans, 2);
  ASSERT_EQ(r.total.histogram.size(), 3u);
  EXPECT_DOUBLE_EQ(r.total.histogram[1], 20.0 * 94 / 5000.0);
  EXPECT_NEAR(r.total.histogram[0] + r.total.histogram[1] + r.total.histogram[2], 1.0, 1e-12);
}

TEST(Coverage, LegOutsideTheAreaCoversNothing) {
  const auto r = evaluate_coverage(rect(0, 0, 100, 50), {{part({{200, 200}, {300, 200}})}}, opts(10));
  EXPECT_DOUBLE_EQ(r.total.poc, 0.0);
  EXPECT_DOUBLE_EQ(r.total.pooc, 0.0);
  EXPECT_EQ(r.total.max_scans, 0);
  EXPECT_DOUBLE_EQ(r.total.length_m, 100.0);
}

TEST(Coverage, TransitLegsScanOnlyWhenAsked) {
  std::vector<Flight> f{{part({{10, 25}, {60, 25}}, PartKind::Transit)}};
  auto o = opts(10);
  const auto off = evaluate_coverage(rect(0, 0, 100, 50), f, o);
  EXPECT_DOUBLE_EQ(off.total.poc, 0.0);
  EXPECT_DOUBLE_EQ(off.total.length_m, 50.0);
  EXPECT_EQ(off.total.turns, 0);  // transit vertices are not turns
  o.count_transit = true;
  const auto on = evaluate_coverage(rect(0, 0, 100, 50), f, o);
  EXPECT_DOUBLE_EQ(on.total.poc, 600.0 / 5000.0);
}

TEST(Coverage, ObliqueLegCoversItsRectangle) {
  // a 45-degree leg of length 100 with w = 20: (100 + 20) * 20 = 2400 m^2 in a large area
  const auto r = evaluate_coverage(rect(-100, -100, 200, 200), {{part({{0, 0}, {70.710678, 70.710678}})}},
                                   opts(20, 0.5));
  const double covered = r.total.poc * r.total.area_m2;
  EXPECT_NEAR(covered, 2400.0, 2400.0 * 0.01);
}

TEST(Coverage, HolesAreNotSampled) {
  MultiPolygon a = rect(0, 0, 100, 100);
  Polygon hole;
  for (Point p : {Point{40, 40}, Point{60, 40}, Point{60, 60}, Point{40, 60}, Point{40, 40}})
    bg::append(hole.outer(), p);
  a[0].inners().push_back(hole.outer());
  bg::correct(a);
  // a leg through the hole: only the parts outside the hole count
  const auto r = evaluate_coverage(a, {{part({{5, 50}, {95, 50}})}}, opts(10));
  EXPECT_EQ(r.samples, 10000u - 400u);
  EXPECT_DOUBLE_EQ(r.total.poc, (100.0 - 20.0) * 10 / 9600.0);
  int outside = 0;
  for (int v : r.scans) outside += v < 0 ? 1 : 0;
  EXPECT_EQ(outside, 400);
}

TEST(Coverage, TurnsCountTheStartTwiceAndNormalise) {
  // a closed loop of 4 corners + the return to the start: 5 waypoints, as the paper counts
  std::vector<Point> loop{{10, 10}, {90, 10}, {90, 40}, {10, 40}, {10, 10}};
  const auto r = evaluate_coverage(rect(0, 0, 100, 50), {{part(loop)}}, opts(10));
  EXPECT_EQ(r.total.turns, 5);
  EXPECT_DOUBLE_EQ(r.total.length_m, 220.0);
  EXPECT_DOUBLE_EQ(r.total.turns_per_1000m2, 1.0);
  EXPECT_DOUBLE_EQ(r.total.length_per_1000m2, 44.0);
  // corners are swept by both legs meeting there
  EXPECT_GE(r.total.max_scans, 2);
}

TEST(Coverage, AreaShareSplitsTheLattice) {
  // UAV 0 sweeps the left half, UAV 1 the right half, 10 m overlap column shared
  const auto r = evaluate_coverage(rect(0, 0, 100, 20),
                                   {{part({{10, 10}, {45, 10}})}, {part({{45, 10}, {90, 10}})}}, opts(20));
  ASSERT_EQ(r.uavs.size(), 2u);
  EXPECT_NEAR(r.uavs[0].area_share + r.uavs[1].area_share, 1.0, 1e-12);
  // covered x: [0,55] by 0 and [35,100] by 1; shared [35,55] split -> 45 and 55 of 100
  EXPECT_NEAR(r.uavs[0].area_share, 0.45, 1e-9);
  EXPECT_NEAR(r.uavs[1].area_share, 0.55, 1e-9);
  EXPECT_DOUBLE_EQ(r.total.poc, 1.0);
  EXPECT_DOUBLE_EQ(r.total.pooc, 0.2);
  EXPECT_DOUBLE_EQ(r.uavs[0].stats.poc, 0.55);
}

TEST(Coverage, AdaptiveLatticeFollowsTheArea) {
  CoverageOptions o;
  o.footprint_m = 30;
  const auto small = evaluate_coverage(rect(0, 0, 100, 100), {}, o);
  EXPECT_DOUBLE_EQ(small.lattice_m, 0.5);  // 0.25 m^2 per sample
  const auto km = evaluate_coverage(rect(0, 0, 1000, 1000), {}, o);
  EXPECT_NEAR(km.lattice_m, 1.0, 1e-9);
  EXPECT_EQ(km.samples, 1000000u);
  o.max_samples = 10000;
  const auto capped = evaluate_coverage(rect(0, 0, 1000, 1000), {}, o);
  EXPECT_LE(capped.samples, 10000u);
  EXPECT_GT(capped.samples, 8000u);
}

TEST(Coverage, SquareKilometreWithManyLegs) {
  // boustrophedon over 1 km^2 at ds = 20, w = 30: everything covered, half overlapped
  std::vector<Point> pts;
  for (int k = 0; k < 50; ++k) {
    const double y = 10 + 20 * k;
    if (k % 2 == 0)
      pts.insert(pts.end(), {Point{10, y}, Point{990, y}});
    else
      pts.insert(pts.end(), {Point{990, y}, Point{10, y}});
  }
  const auto r = evaluate_coverage(rect(0, 0, 1000, 1000), {{part(pts)}}, opts(30, 1.0));
  EXPECT_DOUBLE_EQ(r.total.poc, 1.0);
  EXPECT_NEAR(r.total.pooc, 0.5, 0.03);
}

TEST(Coverage, RejectsBadFootprint) {
  EXPECT_THROW(evaluate_coverage(rect(0, 0, 10, 10), {}, opts(0)), InputError);
  EXPECT_THROW(evaluate_coverage(rect(0, 0, 10, 10), {}, opts(-1)), InputError);
}
