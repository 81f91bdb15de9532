// Sorties on UAVs: the fewest UAVs that fly a set of routes within a wall-clock time.
#pragma once

#include <vector>

namespace uavcover::smt {

/// Longest-processing-time-first schedule of `times_s` on `uavs` UAVs; returns the makespan.
double makespan(std::vector<double> times_s, int uavs);

/// The fewest UAVs whose longest-processing-time-first schedule ends within `wall_clock_s`
/// (0: impossible, a route alone is longer). Battery changes between sorties are not counted.
int min_uavs(const std::vector<double>& times_s, double wall_clock_s);

}  // namespace uavcover::smt
