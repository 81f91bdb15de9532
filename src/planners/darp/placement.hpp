// Grid placement optimisation (Apostolidis et al. 2022 §2.2): maximise J = a*J1 + b*J2 - c*J3 over
// the shift (sx, sy) in [0, dn)^2 and rotation theta in [0, 90) degrees, by a coarse pre-scan
// followed by simulated annealing restarted from the best distinct pre-scan points.
#pragma once

#include <cstdint>
#include <functional>

#include "planners/darp/grid.hpp"

namespace uavcover::grid {

/// Result of the grid placement optimisation (paper §2.2, eq. 7-10).
struct Placement {
  double shift_x_m = 0.0;
  double shift_y_m = 0.0;
  double rotation_deg = 0.0;
  double J = 0.0, J1 = 0.0, J2 = 0.0, J3 = 0.0;
  long evaluations = 0;
};

struct PlacementOptions {
  /// Total budget (pre-scan + annealing); grids of more than 2e7 / evaluations free cells get
  /// max(64, 2e7 / free cells) instead (placement.cpp, kPlacementWork).
  int evaluations = 1500;
  bool optimise = true;  ///< false: the single placement (0, 0, 0)
  std::uint64_t seed = 0;
  Weights weights{};
  /// The best `rerank` distinct candidates of the search are re-ranked with the finer coverage
  /// estimate (coverage_proxy at ds/8) in place of the coarse one; <= 1 keeps the search's best.
  int rerank = 24;
  /// Polled between evaluations: true ends the search early with the best placement so far.
  std::function<bool()> stop_early;
  /// Called with every placement the search evaluates (shift x, shift y, rotation, its score), in order;
  /// lets a caller see the candidates the chosen one was picked from.
  std::function<void(double, double, double, const Score&)> on_evaluation;
};

struct PlacementResult {
  Placement placement;    ///< sx, sy, theta, J and its terms, evaluations used
  double coverage = 0.0;  ///< coverage_proxy of the chosen grid
  Grid grid;              ///< the grid at the best placement
};

/// `progress(fraction)` is called every few evaluations (it may throw to abort).
PlacementResult optimise_placement(const Prepared& prep, const PlacementOptions& options,
                                   const std::function<void(double)>& progress = {});

}  // namespace uavcover::grid
