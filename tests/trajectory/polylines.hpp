// Seeded random 3D polylines for the trajectory tests: short and long legs, acute turns, reversals.
#pragma once

#include <algorithm>
#include <random>
#include <vector>

#include "trajectory/trajectory.hpp"

namespace uavcover::trajectory::polylines {

/// 2 + trial % 9 legs of up to 30 m per axis from the origin (a third of the trials with legs of 5 % to
/// 100 % of that), never below z = 0.
inline std::vector<Vec3> random_polyline(std::mt19937_64& rng, int trial) {
  std::uniform_real_distribution<double> coord(-30, 30), len(0.05, 1.0);
  std::vector<Vec3> w{{0, 0, 0}};
  const int n = 2 + trial % 9;
  for (int i = 0; i < n; ++i) {
    const double f = trial % 3 == 0 ? len(rng) : 1.0;  // some polylines have very short legs
    w.push_back({w.back()[0] + f * coord(rng), w.back()[1] + f * coord(rng),
                 std::max(0.0, w.back()[2] + f * coord(rng) / 3)});
  }
  return w;
}

}  // namespace uavcover::trajectory::polylines
