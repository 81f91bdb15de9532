#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "geometry/geometry.hpp"
#include "support/shapes.hpp"

using namespace uavcover;

using uavcover::testing::rect;

TEST(Geometry, FreeSpaceSubtractsNoFlyZones) {
  const MultiPolygon area{rect(0, 0, 100, 100)};
  const MultiPolygon nfz{rect(40, 40, 60, 60)};
  const auto free = geometry::free_space(area, nfz);
  EXPECT_NEAR(bg::area(free), 10000 - 400, 1e-6);
}

TEST(Geometry, SegmentWithinAndEnters) {
  const MultiPolygon area{rect(0, 0, 100, 100)};
  EXPECT_TRUE(geometry::segment_within(area, {10, 10}, {90, 90}, 0.5));
  EXPECT_TRUE(geometry::segment_within(area, {0, 50}, {100.3, 50}, 0.5));
  EXPECT_FALSE(geometry::segment_within(area, {10, 10}, {110, 10}, 0.5));
  const MultiPolygon nfz{rect(40, 40, 60, 60)};
  EXPECT_TRUE(geometry::segment_enters(nfz, {0, 50}, {100, 50}, 0.1));
  EXPECT_FALSE(geometry::segment_enters(nfz, {0, 40}, {100, 40}, 0.1));  // along the boundary
  EXPECT_FALSE(geometry::segment_enters(nfz, {0, 30}, {100, 30}, 0.1));
}

TEST(Geometry, RouteAroundAvoidsObstacles) {
  const MultiPolygon nfz{rect(40, 20, 60, 80), rect(70, -50, 75, 45)};
  const Point a{0, 50}, b{100, 50};
  const auto path = geometry::route_around(nfz, a, b);
  ASSERT_GE(path.size(), 3u);
  EXPECT_EQ(bg::distance(path.front(), a), 0);
  EXPECT_EQ(bg::distance(path.back(), b), 0);
  for (std::size_t i = 1; i < path.size(); ++i)
    EXPECT_FALSE(geometry::segment_enters(nfz, path[i - 1], path[i], 1e-6)) << i;
  // not absurdly long: direct is 100 m, the detour around the 60 m tall block is < 200 m
  EXPECT_LT(geometry::length(path), 200.0);
  EXPECT_EQ(geometry::route_around(nfz, {0, 0}, {30, 0}).size(), 2u);
}

TEST(Geometry, CountTurns) {
  EXPECT_EQ(geometry::count_turns({{0, 0}, {10, 0}, {20, 0}, {20, 10}, {0, 10}}), 2);
  EXPECT_EQ(geometry::count_turns({{0, 0}, {10, 0}}), 0);
}

namespace {

/// n axis-aligned rectangles at seeded random places in a 1 km square, overlapping heavily.
uavcover::MultiPolygon random_boxes(int n, unsigned seed) {
  std::uint64_t state = seed;
  auto rnd = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / static_cast<double>(1ULL << 53);
  };
  uavcover::MultiPolygon out;
  const double side = 2.5 * 1000.0 / std::sqrt(static_cast<double>(n));
  for (int i = 0; i < n; ++i) {
    const double x = 1000 * rnd(), y = 1000 * rnd(), w = side * (0.5 + rnd()), h = side * (0.5 + rnd());
    out.push_back(rect(x, y, x + w, y + h));
  }
  return out;
}

}  // namespace

TEST(Geometry, UniteALargeClusterPairwiseGivesTheSameArea) {
  // 2 000 overlapping boxes form one cluster: united pairwise (the sequential way took quadratic time)
  const auto boxes = random_boxes(2000, 7);
  const auto united = geometry::unite(boxes);
  ASSERT_FALSE(united.empty());
  double sum = 0;
  for (const auto& p : united) {
    EXPECT_TRUE(bg::is_valid(p));
    sum += bg::area(p);
  }
  // the reference: the same boxes added one by one
  uavcover::MultiPolygon sequential;
  for (const auto& b : boxes) {
    uavcover::MultiPolygon next;
    bg::union_(sequential, b, next);
    sequential = std::move(next);
  }
  const double expected = bg::area(sequential);
  EXPECT_NEAR(sum, expected, 1e-9 * expected);  // and the parts do not overlap: their areas add up
  // every box lies inside the union
  for (std::size_t i = 0; i < boxes.size(); i += 97) EXPECT_TRUE(bg::covered_by(boxes[i], united)) << i;
}
