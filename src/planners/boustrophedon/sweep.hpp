// Sweeping one monotone cell: the leg direction with the fewest legs, the legs (half a spacing in
// from the cell's sides), their ends (on the boundary in strict mode, half a footprint beyond the
// area's boundary in coverage mode) and the lawnmower joining them.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "planners/boustrophedon/decomposition.hpp"
#include "uavcover/mission.hpp"

namespace uavcover::planners::boustro {

/// What the legs' ends may touch (local metres, world frame).
struct Surroundings {
  const MultiPolygon* area = nullptr;    ///< the mission area (extensions only leave it)
  const MultiPolygon* no_fly = nullptr;  ///< never entered
  const MultiPolygon* others = nullptr;  ///< other UAVs' regions (coverage mode keeps away)
  EdgeIndex stops;                       ///< edges of area and no-fly zones: extensions stop there
  EdgeIndex no_fly_edges;                ///< connections outside the cell must not cross these
};

struct SweepOptions {
  double spacing = 0.0;
  double footprint = 0.0;
  Mode mode = Mode::Strict;
  bool overhang = true;  ///< coverage mode: extend further where the edge is shallow (one UAV)
  /// The mission's pattern options (docs/patterns.md): turnaround_m, alternate_transects and the camera
  /// off in turns unless capture_in_turnaround. Null: the plain lawnmower, camera on throughout.
  const Pattern* pattern = nullptr;
};

/// Legs at `spacing` (at most) across [xmin, xmax], the outer ones half a spacing in.
std::vector<double> leg_positions(double xmin, double xmax, double spacing);

/// Number of legs across a width.
int leg_count(double width, double spacing);

/// A cell swept in one direction.
struct CellSweep {
  double angle = 0.0;  ///< leg direction, radians counter-clockwise from east
  Monotone mono;       ///< the cell in that direction's frame
  int legs = 0;
};

/// The direction with the fewest legs among the cell's edge directions, a 1-degree scan and
/// `preferred` (the decomposition's, always valid); `fixed` forces one direction.
CellSweep choose_direction(const Monotone& cell, const Frame& frame, double preferred, double spacing,
                           std::optional<double> fixed);

/// Lawnmower paths of a cell: [0] starts at the leftmost leg going up, [1] going down. Each path
/// may be flown backwards, so four entries and exits are offered.
/// With a pattern, `camera_off` receives per path one flag per segment (1: camera off).
std::array<std::vector<Point>, 2> lawnmower(const CellSweep& sweep, const SweepOptions& opt,
                                            const Surroundings& env, const Context& ctx,
                                            std::array<std::vector<std::uint8_t>, 2>* camera_off = nullptr);

}  // namespace uavcover::planners::boustro
