#include "evaluation/cost.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "geometry/geometry.hpp"
#include "uavcover/error.hpp"

namespace uavcover::evaluation {

double ground_speed_mps(double airspeed_mps, const std::optional<Wind>& wind, double dx, double dy) {
  const double len = std::hypot(dx, dy);
  if (!wind || wind->speed_mps == 0.0 || len == 0.0) return airspeed_mps;
  const double w = wind->speed_mps;
  if (w >= airspeed_mps) throw InputError("wind.speed_mps", "must be below the UAV's speed_mps");
  // the wind travels towards from_deg + 180 (bearing clockwise from north: east = sin, north = cos)
  const double to = (wind->from_deg + 180.0) * M_PI / 180.0;
  const double wx = std::sin(to), wy = std::cos(to);
  const double cos_phi = (dx * wx + dy * wy) / len;
  const double sin_phi = (dx * wy - dy * wx) / len;
  return w * cos_phi + std::sqrt(airspeed_mps * airspeed_mps - w * w * sin_phi * sin_phi);
}

double air_distance_m(Point a, Point b, double airspeed_mps, const std::optional<Wind>& wind) {
  const double len = bg::distance(a, b);
  if (!wind || wind->speed_mps == 0.0 || len == 0.0) return len;
  return len * airspeed_mps / ground_speed_mps(airspeed_mps, wind, b.x() - a.x(), b.y() - a.y());
}

double air_length_m(const std::vector<Point>& line, double airspeed_mps, const std::optional<Wind>& wind) {
  if (!wind || wind->speed_mps == 0.0) return geometry::length(line);
  double s = 0.0;
  for (std::size_t i = 1; i < line.size(); ++i) s += air_distance_m(line[i - 1], line[i], airspeed_mps, wind);
  return s;
}

namespace {
void check_uav(const Uav& u, std::size_t i) {
  const std::string f = "uavs[" + std::to_string(i) + "]";
  if (!(u.speed_mps > 0.0) || !std::isfinite(u.speed_mps)) throw InputError(f + ".speed_mps", "must be > 0");
  if (!(u.endurance_min > 0.0) || !std::isfinite(u.endurance_min))
    throw InputError(f + ".endurance_min", "must be > 0");
}
}  // namespace

double flight_duration_min(double length_m, int turns, const Uav& uav) {
  const double v = uav.speed_mps;
  if (!(v > 0.0)) throw InputError("speed_mps", "must be > 0");
  const double seconds = length_m / v + turns * uav.turn_c1 * v / (uav.turn_c2 + std::abs(v));
  return seconds / 60.0;
}

CostResult evaluate_cost_from_durations(const std::vector<double>& durations_min,
                                        const std::vector<Uav>& uavs, double area_m2, const CostOptions& o,
                                        const std::vector<int>* batteries) {
  if (batteries != nullptr && batteries->size() != uavs.size())
    throw InputError("uavs", "one battery count per UAV is needed");
  if (durations_min.size() != uavs.size())
    throw InputError("uavs", "one flight duration per UAV is needed (" +
                                 std::to_string(durations_min.size()) + " durations, " +
                                 std::to_string(uavs.size()) + " UAVs)");
  CostResult r;
  r.n_uavs = static_cast<int>(uavs.size());
  const double n = r.n_uavs;
  const double sqrt_area = std::sqrt(std::max(area_m2, 0.0));
  for (std::size_t i = 0; i < uavs.size(); ++i) {
    check_uav(uavs[i], i);
    UavCost c;
    c.flight_duration_min = std::max(durations_min[i], 0.0);
    // eq. 16; a tiny tolerance keeps 25.0000000001 min on one battery
    c.batteries =
        std::max(1, static_cast<int>(std::ceil(c.flight_duration_min / uavs[i].endurance_min - 1e-9)));
    if (c.flight_duration_min <= 0.0) c.batteries = 0;
    // given counts replace eq. 16; a negative entry keeps it (a UAV without sorties)
    if (batteries != nullptr && (*batteries)[i] >= 0) c.batteries = (*batteries)[i];
    // eq. 19: each change crosses twice a distance proportional to sqrt(area), plus the change itself
    const double per_change = 2.0 * sqrt_area / (3.0 * uavs[i].speed_mps * 60.0) + o.battery_change_min * n;
    c.change_battery_delay_min = std::max(c.batteries - 1, 0) * per_change;
    r.batteries_per_uav = std::max(r.batteries_per_uav, c.batteries);
    r.flight_time_min = std::max(r.flight_time_min, c.flight_duration_min);
    r.change_battery_delay_min = std::max(r.change_battery_delay_min, c.change_battery_delay_min);
    r.uavs.push_back(c);
  }
  r.single_battery = r.batteries_per_uav <= 1;
  r.deployment_time_min = o.deployment_base_min + o.deployment_per_uav_min * n;               // eq. 18
  r.total_time_min = r.flight_time_min + r.deployment_time_min + r.change_battery_delay_min;  // eq. 20
  // eq. 22
  r.flight_cost_eur = (r.total_time_min - r.deployment_time_min -
                       std::max(r.batteries_per_uav - 1, 0) * o.battery_change_min) *
                      n * o.fcm_eur_per_min;
  return r;
}

CostResult evaluate_cost(const std::vector<double>& lengths_m, const std::vector<int>& turns,
                         const std::vector<Uav>& uavs, double area_m2, const CostOptions& options) {
  if (lengths_m.size() != uavs.size() || turns.size() != uavs.size())
    throw InputError("uavs", "one length and one turn count per UAV are needed");
  std::vector<double> d;
  for (std::size_t i = 0; i < uavs.size(); ++i) {
    check_uav(uavs[i], i);
    d.push_back(flight_duration_min(lengths_m[i], turns[i], uavs[i]));
  }
  return evaluate_cost_from_durations(d, uavs, area_m2, options);
}

}  // namespace uavcover::evaluation
