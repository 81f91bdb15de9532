// Region outlines (regions.hpp): the cells a UAV owns, traced as valid polygons. A region whose cells
// touch one another only at a corner, around an enclosed hole, once traced a ring that passed through
// that corner twice: Boost (and plan.json's reader, and the export) refused it as self-intersecting.
#include <gtest/gtest.h>

#include <string>

#include "planners/darp/regions.hpp"

namespace uavcover::test {
namespace {

/// Rows listed top to bottom ('#' owned by UAV 0, '.' not).
MultiPolygon outline(const std::vector<std::string>& pic) {
  const int rows = static_cast<int>(pic.size()), cols = static_cast<int>(pic[0].size());
  std::vector<int> owner(static_cast<std::size_t>(rows * cols), -1);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      if (pic[static_cast<std::size_t>(rows - 1 - r)][static_cast<std::size_t>(c)] == '#')
        owner[r * cols + c] = 0;
  return darp::cells_to_polygons(rows, cols, owner, 0,
                                 [](int c, int r) { return Point(10.0 * c, 10.0 * r); });
}

double owned_area(const std::vector<std::string>& pic) {
  double n = 0;
  for (const auto& row : pic)
    for (char ch : row) n += ch == '#';
  return 100.0 * n;
}

void expect_valid(const std::vector<std::string>& pic) {
  const MultiPolygon mp = outline(pic);
  std::string why;
  EXPECT_TRUE(bg::is_valid(mp, why)) << why;
  EXPECT_NEAR(bg::area(mp), owned_area(pic), 1e-6);
}

TEST(DarpRegions, ClosedLoopThroughADiagonalCornerIsAPolygonWithAHole) {
  // a ring of cells whose two ends touch only at a corner: the enclosed '.' cells are a hole
  expect_valid({"#####",  //
                "#...#",  //
                "#...#",  //
                "##..#",  //
                "..###"});
  // the same with the hole on the other side of the corner (the ends meet the other way)
  expect_valid({"###..",  //
                "#..##",  //
                "#...#",  //
                "#...#",  //
                "#####"});
}

TEST(DarpRegions, StaircaseAlongADiagonalHedge) {
  // cells on both sides of a 45-degree hedge, joined around its ends (the hedged field's pattern)
  expect_valid({"#######",  //
                "#....##",  //
                "#...#.#",  //
                "#..#..#",  //
                "#.#...#",  //
                "##....#",  //
                "#######"});
}

TEST(DarpRegions, CellsTouchingOnlyAtACornerAreSeparatePolygons) {
  const MultiPolygon mp = outline({"#.",  //
                                   ".#"});
  std::string why;
  EXPECT_TRUE(bg::is_valid(mp, why)) << why;
  EXPECT_EQ(mp.size(), 2u);
}

}  // namespace
}  // namespace uavcover::test
