#include <gtest/gtest.h>

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
