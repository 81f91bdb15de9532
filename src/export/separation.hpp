// Safe separation checks (Hong et al. 2021 §2.3): every UAV has its own transition altitude above the
// mission altitude, and no leg flown at mission altitude outside coverage enters another UAV's region.
#pragma once

#include <string>
#include <vector>

#include "export/mission_items.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::exporting {

/// Which UAV's region a local point lies in, from Plan::grid (mega-cell owners). The grid's frame
/// convention is confirmed against each UAV's own coverage waypoints; when it cannot be confirmed
/// the regions fall back to the areas enclosed by the UAVs' coverage loops.
class RegionMap {
 public:
  explicit RegionMap(const Plan& plan);
  /// UAV index owning the point, -1 when none (blocked, outside the grid).
  [[nodiscard]] int owner(Point p) const;
  [[nodiscard]] bool uses_grid() const { return use_grid_; }

 private:
  [[nodiscard]] int grid_owner(Point p, int mode) const;
  const Plan* plan_;
  bool use_grid_ = false;
  int mode_ = 0;
  std::vector<MultiPolygon> loops_;  // fallback regions, per UAV
};

struct SeparationOptions {
  double min_vertical_m = 1.0;  ///< transition altitudes must differ by at least this
  double sample_step_m = 0.5;   ///< leg sampling step for the region test (also capped at cell/4)
};

/// Problems found, one line each (empty = separation holds): shared or too-close transition
/// altitudes, transition altitudes not above the mission altitude, legs at mission altitude (other
/// than coverage legs of one loop) entering another UAV's region.
std::vector<std::string> check_separation(const Plan& plan, const AltitudeOptions& opt,
                                          const SeparationOptions& sep = {});

/// Hazards that do not block an export: a UAV's home inside another UAV's region (its take-off and
/// landing cross the coverage layer there; common when all UAVs launch from one depot).
std::vector<std::string> separation_warnings(const Plan& plan);

}  // namespace uavcover::exporting
