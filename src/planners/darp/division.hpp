// DARP area division on one connected component of the free grid (Kapoutsis et al. 2017, with the
// proportional objective of Apostolidis et al. 2022 eq. 11): evaluation matrices from geodesic
// distances, multiplicative correction toward each share, connectivity matrices C_i, a small random
// factor, and a tolerance that relaxes over retries. Large grids, and divisions that miss a share, are
// balanced by additively weighted waves instead (division.cpp, Waves): connected by construction, one
// pass over the cells per iteration whatever the number of participants; a border rebalance (a flow on
// the graph of adjacent regions, moving leaves of per-region spanning trees) then brings every region
// to its share where the waves' weights stall (unequal shares).
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
  /// per participant (empty: none): 1 when its start cell only marks where a UAV from outside the
  /// component enters (a take-off point outside the area, a UAV joining another component), so the final
  /// single-cell transfers may hand that cell to another region
  std::vector<char> movable;
  int max_iterations = 4000;  ///< per attempt
  int attempts = 3;           ///< tolerance relaxes from attempt to attempt
  std::uint64_t seed = 0;
  /// Polled every iteration: true ends the search with the best connected division so far.
  std::function<bool()> stop_early;
};

struct DivisionResult {
  std::vector<int> owner;    ///< per entry of `cells`: participant index
  std::vector<int> counts;   ///< cells per participant
  bool converged = false;    ///< every participant within tolerance(its target)
  int iterations = 0;        ///< in total, over all attempts
  double max_deviation = 0;  ///< max |count - target| in cells
  bool stopped = false;      ///< stop_early() ended the search
};

/// `progress(fraction)` is called every iteration (it may throw to abort).
/// Every returned region is 4-connected over the grid's links and contains its start cell (a region with a
/// movable start: at least one cell).
DivisionResult divide(const grid::Grid& g, const DivisionInput& in,
                      const std::function<void(double)>& progress = {});

/// Tolerance (cells) of a participant wanting `target` cells: 2 % of its own target, at least one cell.
double tolerance(double target);

}  // namespace uavcover::darp
