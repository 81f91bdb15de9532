// DARP area division on one connected component of the free grid (Kapoutsis et al. 2017, with the
// proportional objective of Apostolidis et al. 2022 eq. 11): evaluation matrices from geodesic
// distances, multiplicative correction toward each share, connectivity matrices C_i, a small random
// factor, and a tolerance that relaxes over retries.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "planners/darp/grid.hpp"

namespace uavcover::darp {

struct DivisionInput {
  std::vector<int> cells;       ///< grid cell indices of one connected component
  std::vector<int> starts;      ///< per participant: distinct cells of the component
  std::vector<double> targets;  ///< per participant: wanted cell count (sums to cells.size())
  int max_iterations = 4000;    ///< per attempt
  int attempts = 3;             ///< tolerance relaxes from attempt to attempt
  std::uint64_t seed = 0;
  /// Polled every iteration: true ends the search with the best connected division so far.
  std::function<bool()> stop_early;
};

struct DivisionResult {
  std::vector<int> owner;    ///< per entry of `cells`: participant index
  std::vector<int> counts;   ///< cells per participant
  bool converged = false;    ///< within max(2 cells, 1 %) of every target
  int iterations = 0;        ///< in total, over all attempts
  double max_deviation = 0;  ///< max |count - target| in cells
};

/// `progress(fraction)` is called every iteration (it may throw to abort).
/// Every returned region is 4-connected over the grid's links and contains its start cell.
DivisionResult divide(const grid::Grid& g, const DivisionInput& in,
                      const std::function<void(double)>& progress = {});

/// Final tolerance (cells) a division must meet to count as converged.
double tolerance(std::size_t cells);

}  // namespace uavcover::darp
