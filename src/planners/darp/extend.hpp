// Leg extension (issue 16): an STC loop runs through sub-cell centres, so a band along the area's
// boundary (the partial mega-cells the grid leaves out) stays uncovered. Where a loop makes a U-turn
// at its region's edge and the mega-cell beyond is not free, both legs of the U-turn are lengthened
// along their own direction (the turn's two vertices move; no vertex is added, so the turn count
// stays), as far as the swept footprint (w = 1.5 ds, reaching w/2 past the leg's end) needs to reach
// the boundary straight ahead, so the leg ends w/2 inside it; a leg end already outside the area
// (coverage mode) stays. Never into a no-fly zone (kept grid::kClearance away), and in strict mode
// never out of the free area.
// The moved turn stays inside the part of the non-free cell that its own cell claims: the whole cell
// when it is that cell's only free neighbour, otherwise the triangle facing it (depth < ds / 2), so that
// extensions from different cells (and UAVs) never meet.
// Legs that run along the region's outer edge (issue 16, "shift") move outward across their own direction
// instead (shift()): an edge parallel to the legs is out of reach of any U-turn.
#pragma once

#include <memory>
#include <vector>

#include "planners/darp/grid.hpp"

namespace uavcover::darp {

class LegExtender {
 public:
  /// `free`: the free area `prep` was made from.
  LegExtender(const grid::Prepared& prep, const grid::Grid& g, const MultiPolygon& free);
  ~LegExtender();
  LegExtender(const LegExtender&) = delete;
  LegExtender& operator=(const LegExtender&) = delete;

  /// Extends the U-turns of one closed loop (last == first, local frame) in place; returns how many
  /// turns moved.
  int extend(std::vector<Point>& loop) const;

  /// Shifts the legs that run along a region's outer edge outward, across their own direction: a leg on
  /// the outer sub-cell lane of its mega-cells with no free cell beyond moves by up to 0.45 ds (it stays
  /// in its own mega-cell, and its swath still meets the inner lane's) until its swath (w/2 = 0.75 ds to
  /// either side) reaches the boundary beside it. Both of its vertices move, so its neighbours only get
  /// longer or shorter: no vertex is added. The same limits as extend() (no-fly zones, strict mode), and
  /// every moved segment keeps 0.05 ds from every other segment of `loops` (all UAVs' loops, closed,
  /// local frame). `swaths` (one per loop, or empty): a loop's UAV's own footprint width w, 0 for the
  /// mission's; such a leg moves by at most w - ds (its swath, w/2 to either side, still meets the inner
  /// lane's) until w/2 reaches the boundary. Returns how many legs moved.
  int shift(const std::vector<std::vector<Point>*>& loops, const std::vector<double>& swaths = {}) const;

 private:
  struct Index;
  const grid::Grid& g_;
  const MultiPolygon& free_;
  Mode mode_;
  /// Whether segment a-b keeps grid::kClearance from the no-fly zones and, in strict mode, stays
  /// inside the free area.
  [[nodiscard]] bool clear(Point a, Point b) const;
  std::unique_ptr<Index> no_fly_;    ///< the no-fly zones' edges
  std::unique_ptr<Index> boundary_;  ///< the free area's edges
};

}  // namespace uavcover::darp
