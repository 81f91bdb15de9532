// Mission time and cost model (Apostolidis et al. 2022 §3.2, eq. 15-22).
#pragma once

#include <optional>
#include <vector>

#include "uavcover/mission.hpp"

namespace uavcover::evaluation {

struct CostOptions {
  double deployment_base_min = 5.0;  ///< eq. 18: DT = base + per_uav * n
  double deployment_per_uav_min = 3.0;
  double battery_change_min = 3.0;    ///< eq. 19 and 22: minutes per battery change
  double fcm_eur_per_min = 0.017228;  ///< eq. 21: flight cost per minute
  /// A steady wind (issue 32, docs/wind.md): eq. 15 times every leg at its ground speed. Empty in
  /// evaluate_plan: the plan's mission's wind.
  std::optional<Wind> wind = {};
};

struct UavCost {
  double flight_duration_min = 0.0;       ///< eq. 15 (or given directly)
  int batteries = 0;                      ///< eq. 16: ceil(duration / endurance)
  double change_battery_delay_min = 0.0;  ///< eq. 19 for this UAV
};

struct CostResult {
  int n_uavs = 0;
  std::vector<UavCost> uavs;
  int batteries_per_uav = 0;              ///< the maximum over the UAVs
  double flight_time_min = 0.0;           ///< eq. 17: the longest flight duration
  double deployment_time_min = 0.0;       ///< eq. 18
  double change_battery_delay_min = 0.0;  ///< eq. 19 (the largest over the UAVs)
  double total_time_min = 0.0;            ///< eq. 20
  double flight_cost_eur = 0.0;           ///< eq. 22
  bool single_battery = true;             ///< every UAV finishes on one battery
};

/// eq. 15 in minutes: length/speed + turns * c1 * speed / (c2 + |speed|) (c1 in s, c2 in m/s).
double flight_duration_min(double length_m, int turns, const Uav& uav);

/// Ground speed (m/s) along a leg of local direction (dx east, dy north) for a UAV holding its airspeed
/// `airspeed_mps` and crabbing into `wind` (issue 32): v_g = w cos(phi) + sqrt(v^2 - (w sin(phi))^2), phi the
/// angle between the leg and the wind's direction of travel. No wind (or a zero-length leg): the airspeed.
/// Throws InputError("wind.speed_mps") when the wind is not slower than the airspeed.
double ground_speed_mps(double airspeed_mps, const std::optional<Wind>& wind, double dx, double dy);

/// The air distance of the leg a -> b (m): |ab| * airspeed / ground speed, the distance the UAV flies
/// through the moving air. eq. 15's length / speed with it is the leg's time at its ground speed, so
/// every caller of flight_duration_min() times a flight in wind by passing air lengths. No wind:
/// bg::distance(a, b) exactly.
double air_distance_m(Point a, Point b, double airspeed_mps, const std::optional<Wind>& wind);

/// air_distance_m() summed over a polyline's legs; no wind: geometry::length(line) exactly.
double air_length_m(const std::vector<Point>& line, double airspeed_mps, const std::optional<Wind>& wind);

/// eq. 16-22 from flight durations given directly (one per UAV, minutes). `area_m2` is the ROI
/// area used by the change-battery delay (eq. 19). `batteries`, when given (one per UAV, e.g. the
/// plan's sortie counts, docs/sorties.md), replaces eq. 16's ceil(duration / endurance). Throws
/// InputError on sizes that do not match or on a non-positive speed/endurance.
CostResult evaluate_cost_from_durations(const std::vector<double>& durations_min,
                                        const std::vector<Uav>& uavs, double area_m2,
                                        const CostOptions& options = {},
                                        const std::vector<int>* batteries = nullptr);

/// eq. 15-22 from each UAV's flown length (coverage + transit) and turns.
CostResult evaluate_cost(const std::vector<double>& lengths_m, const std::vector<int>& turns,
                         const std::vector<Uav>& uavs, double area_m2, const CostOptions& options = {});

}  // namespace uavcover::evaluation
