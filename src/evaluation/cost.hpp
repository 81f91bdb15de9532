// Mission time and cost model (Apostolidis et al. 2022 §3.2, eq. 15-22).
#pragma once

#include <vector>

#include "uavcover/mission.hpp"

namespace uavcover::evaluation {

struct CostOptions {
  double deployment_base_min = 5.0;  ///< eq. 18: DT = base + per_uav * n
  double deployment_per_uav_min = 3.0;
  double battery_change_min = 3.0;    ///< eq. 19 and 22: minutes per battery change
  double fcm_eur_per_min = 0.017228;  ///< eq. 21: flight cost per minute
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
