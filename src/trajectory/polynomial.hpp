// Internal to src/trajectory: Method::Polynomial (polynomial.cpp), used by the Trajectory.
#pragma once

#include <vector>

#include "trajectory/trajectory.hpp"

namespace uavcover::trajectory::detail {

/// The bounds Method::Polynomial keeps (LimitReport's v_min .. a_max), Options' defaults resolved.
/// Throws InputError naming "order", "v_mean", "v_min" or "a_min" for a value no trajectory can meet.
LimitReport polynomial_bounds(const Limits& limits, const Options& options);

struct PolyTrajectory {
  std::vector<PolySegment> segments;
  LimitReport report;
};

/// The piecewise polynomial through `waypoints` (>= 2, no two consecutive equal), at rest at both ends,
/// within the bounds: durations length / v_mean, stretched until every bound holds (docs/trajectory.md).
PolyTrajectory polynomial(const std::vector<Vec3>& waypoints, const Limits& limits, const Options& options);

/// The state at time t in [0, the end] (clamped); Sample::piece is the segment's index.
Sample polynomial_at(const std::vector<PolySegment>& segments, int order, double t);

}  // namespace uavcover::trajectory::detail
