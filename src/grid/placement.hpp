// Grid placement optimisation (Apostolidis et al. 2022 §2.2): maximise J = a*J1 + b*J2 - c*J3 over
// the shift (sx, sy) in [0, dn)^2 and rotation theta in [0, 90) degrees, by a coarse pre-scan
// followed by simulated annealing restarted from the best distinct pre-scan points.
#pragma once

#include <cstdint>
#include <functional>

#include "grid/grid.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::grid {

struct PlacementOptions {
  int evaluations = 1500;  ///< total budget (pre-scan + annealing)
  bool optimise = true;    ///< false: the single placement (0, 0, 0)
  std::uint64_t seed = 0;
  Weights weights{};
  /// The best `rerank` distinct candidates of the search are re-ranked with the finer coverage
  /// estimate (coverage_proxy at ds/8) in place of the coarse one; <= 1 keeps the search's best.
  int rerank = 24;
};

struct PlacementResult {
  Placement placement;    ///< sx, sy, theta, J and its terms, evaluations used
  double coverage = 0.0;  ///< coverage_proxy of the chosen grid
  Grid grid;              ///< the grid at the best placement
};

/// `progress(fraction)` is called now and then.
PlacementResult optimise_placement(const Prepared& prep, const PlacementOptions& options,
                                   const std::function<void(double)>& progress = {});

}  // namespace uavcover::grid
