// Safe separation checks (Hong et al. 2021 §2.3): every UAV has its own transition altitude above the
// mission altitude, and no leg flown at mission altitude outside coverage enters another UAV's region.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "uavcover/plan.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::exporting {

/// The UAVs' regions (UavPlan::region_local; for plans without regions, the areas their closed
/// coverage loops enclose).
class RegionMap {
 public:
  explicit RegionMap(const Plan& plan);
  ~RegionMap();
  RegionMap(const RegionMap&) = delete;
  RegionMap& operator=(const RegionMap&) = delete;
  /// UAV index whose region contains the point, -1 when none.
  [[nodiscard]] int owner(Point p) const;
  /// A UAV other than `except` whose region the segment a-b enters deeper than `tol`, else -1.
  [[nodiscard]] int entered_by(Point a, Point b, std::size_t except, double tol) const;

 private:
  std::vector<MultiPolygon> regions_;
  struct Index;  ///< R-tree of the regions' polygons (bounding boxes), so that huge plans check fast
  std::unique_ptr<Index> index_;
};

struct SeparationOptions {
  double min_vertical_m = 1.0;  ///< transition altitudes must differ by at least this
  double tolerance_m = 0.05;    ///< a leg may touch another region's edge up to this depth
};

/// Problems found, one line each (empty = separation holds): shared or too-close transition
/// altitudes, transition altitudes not above the mission altitude, legs at mission altitude (other
/// than coverage legs of one loop) entering another UAV's region.
std::vector<std::string> check_separation(const Plan& plan, const waypoints::AltitudeOptions& opt,
                                          const SeparationOptions& sep = {});

/// Hazards that do not block an export: a UAV's home inside another UAV's region (its take-off and
/// landing cross the coverage layer there; common when all UAVs launch from one depot).
std::vector<std::string> separation_warnings(const Plan& plan);

}  // namespace uavcover::exporting
