#include "geometry/millimetres.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>

#include "geometry/geometry.hpp"
#include "support/shapes.hpp"

using namespace uavcover;

using uavcover::testing::rect;

namespace {

/// A 300 m field crossed by 1 m hedges along x - y = c every 27 m
/// (tests/planners/darp/hedge_region_test.cpp).
MultiPolygon hedged_field_free() {
  const double W = 300, gap = 27, m = 6, half = std::sqrt(0.5);
  MultiPolygon hedges;
  for (double c = -W + gap; c < W - gap; c += gap) {
    const double y0 = std::max(m, m - c), y1 = std::min(W - m, W - m - c);
    if (y1 - y0 <= 20) continue;
    Polygon h;
    h.outer() = {{y0 + c - half, y0}, {y1 + c - half, y1}, {y1 + c + half, y1}, {y0 + c + half, y0}};
    h.outer().push_back(h.outer().front());
    bg::correct(h);
    hedges.push_back(std::move(h));
  }
  return geometry::free_space(MultiPolygon{rect(0, 0, W, W)}, hedges);
}

/// 2n x 2n cells of side `cell` on a grid rotated by `deg` about (150, 150), shifted by `shift`; `parity` 0
/// or 1 picks one colour of the checkerboard (cells touching at corners), 2 takes all.
MultiPolygon rotated_cells(double cell, int n, double deg, double shift, int parity) {
  const double a = deg * std::numbers::pi / 180, ca = std::cos(a), sa = std::sin(a);
  auto at = [&](double u, double v) {
    return Point(150 + ca * (u + shift) - sa * (v + shift), 150 + sa * (u + shift) + ca * (v + shift));
  };
  MultiPolygon cells;
  for (int i = -n; i < n; ++i)
    for (int j = -n; j < n; ++j) {
      if (parity != 2 && ((i + j) & 1) != parity) continue;
      Polygon q;
      const double u = i * cell, v = j * cell;
      q.outer() = {at(u, v), at(u, v + cell), at(u + cell, v + cell), at(u + cell, v), at(u, v)};
      cells.push_back(std::move(q));
    }
  return cells;
}

}  // namespace

TEST(Millimetres, PointsRoundToTheNearestMillimetre) {
  EXPECT_EQ(geometry::to_mm(Point(1.2344, -0.0006)).x(), 1234);
  EXPECT_EQ(geometry::to_mm(Point(1.2344, -0.0006)).y(), -1);
  const Point back = geometry::from_mm(geometry::to_mm(Point(123.4567, -98.7654)));
  EXPECT_NEAR(back.x(), 123.457, 1e-12);
  EXPECT_NEAR(back.y(), -98.765, 1e-12);
  // polygons come back corrected (Boost's clockwise outer rings) with their holes
  Polygon ring_with_hole = rect(0, 0, 10, 10);
  ring_with_hole.inners().push_back({{2, 2}, {2, 4}, {4, 4}, {4, 2}, {2, 2}});
  bg::correct(ring_with_hole);
  const MultiPolygon round_trip = geometry::from_mm(geometry::to_mm(MultiPolygon{ring_with_hole}));
  ASSERT_EQ(round_trip.size(), 1u);
  ASSERT_EQ(round_trip[0].inners().size(), 1u);
  EXPECT_TRUE(bg::is_valid(round_trip));
  EXPECT_NEAR(bg::area(round_trip), 96.0, 1e-9);
}

TEST(Millimetres, RectanglesAlongCollinearEdges) {
  // overlapping along collinear edges (footprint rectangles of adjacent sweep legs), touching along one
  const MultiPolygon a{rect(0, 0, 10, 4)}, b{rect(5, 0, 15, 4)}, c{rect(10, 0, 20, 4)};
  const MultiPolygon ab = geometry::intersection_mm(a, b);
  EXPECT_NEAR(bg::area(ab), 20.0, 1e-9);
  EXPECT_TRUE(bg::is_valid(ab));
  EXPECT_NEAR(bg::area(geometry::intersection_mm(a, c)), 0.0, 1e-9);
}

// Cells on rotated grids clipped by the hedged field: every piece is valid, the two colours of a
// checkerboard of cells (two owners' cells) give pieces that overlap by rounding slivers only, lie in the
// free area and together make the free area. The checks run on millimetres too (the pieces' vertices are
// whole millimetres): on doubles, Boost's overlay of these pieces is what cannot be trusted.
TEST(Millimetres, HedgedCellsClipIntoValidPieces) {
  const MultiPolygon free = hedged_field_free();
  const geometry::MmMultiPolygon free_mm = geometry::to_mm(free);
  for (const double deg : {7.3, 45.0}) {
    SCOPED_TRACE(::testing::Message() << "rotation " << deg);
    const MultiPolygon black = rotated_cells(8, 27, deg, 1.37, 0), white = rotated_cells(8, 27, deg, 1.37, 1);
    const MultiPolygon pb = geometry::intersection_mm(black, free),
                       pw = geometry::intersection_mm(white, free);
    ASSERT_GT(pb.size(), 100u);
    for (const MultiPolygon* p : {&pb, &pw})
      for (const Polygon& piece : *p) {
        std::string why;
        EXPECT_TRUE(bg::is_valid(piece, why)) << why;
      }
    const geometry::MmMultiPolygon b_mm = geometry::to_mm(pb), w_mm = geometry::to_mm(pw);
    std::int64_t both = 0;
    for (const auto& b : b_mm)
      for (const auto& w : w_mm)
        if (bg::intersects(bg::return_envelope<bg::model::box<geometry::MmPoint>>(b),
                           bg::return_envelope<bg::model::box<geometry::MmPoint>>(w))) {
          geometry::MmMultiPolygon bw;
          bg::intersection(b, w, bw);
          both += bg::area(bw);
        }
    // where a hedge crosses an edge the two colours share, each clip rounds the crossing on its own: the
    // pieces overlap by slivers under a millimetre wide, nothing more
    EXPECT_LT(static_cast<double>(both), 0.71 * bg::perimeter(b_mm));
    geometry::MmMultiPolygon outside;
    // a vertex rounded to the nearest millimetre lies at most 0.71 mm off the free area's edge
    bg::difference(b_mm, free_mm, outside);
    EXPECT_LT(static_cast<double>(bg::area(outside)), 0.71 * bg::perimeter(b_mm));
    // the grid (a 432 m square about the field's centre) covers the field
    EXPECT_NEAR(bg::area(pb) + bg::area(pw), bg::area(free),
                0.0008 * (bg::perimeter(pb) + bg::perimeter(pw)));
  }
}
