#include "planners/smt/schedule.hpp"

#include <algorithm>
#include <functional>
#include <numeric>

namespace uavcover::smt {

double makespan(std::vector<double> times_s, int uavs) {
  if (uavs <= 0 || times_s.empty()) return 0.0;
  std::sort(times_s.begin(), times_s.end(), std::greater<>());
  std::vector<double> load(static_cast<std::size_t>(uavs), 0.0);
  for (double t : times_s) *std::min_element(load.begin(), load.end()) += t;
  return *std::max_element(load.begin(), load.end());
}

int min_uavs(const std::vector<double>& times_s, double wall_clock_s) {
  if (times_s.empty()) return 1;
  if (*std::max_element(times_s.begin(), times_s.end()) > wall_clock_s) return 0;
  const int n = static_cast<int>(times_s.size());
  for (int m = 1; m < n; ++m)
    if (makespan(times_s, m) <= wall_clock_s) return m;
  return n;
}

}  // namespace uavcover::smt
