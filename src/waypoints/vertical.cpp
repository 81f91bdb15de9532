#include "waypoints/vertical.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "evaluation/cost.hpp"
#include "geodesy/local_frame.hpp"
#include "terrain/terrain.hpp"
#include "uavcover/error.hpp"

namespace uavcover::waypoints {

std::vector<double> vertical_extra_s(const Plan& plan, std::size_t index,
                                     const std::vector<MissionItem>& items) {
  const Uav& u = plan.mission.uavs.at(index);
  const HeightGrid* ground = terrain::grid(plan.mission);
  const geodesy::LocalFrame frame(plan.origin);
  const LonLat home = u.start_resolved;
  const Point home_local = frame.to_local(home);
  // heights in one frame: above mean sea level with a DEM, else above take-off
  const double home_z = ground != nullptr ? ground->at(home) : 0.0;
  auto height = [&](const MissionItem& it, LonLat p) {
    const double alt = static_cast<double>(it.alt);
    if (it.frame == kFrameGlobal) return alt;
    if (it.frame == kFrameGlobalTerrainAlt) return (ground != nullptr ? ground->at(p) : home_z) + alt;
    return home_z + alt;  // relative to home
  };
  Point at = home_local;
  double z = home_z;
  auto leg = [&](Point to, double to_z) {
    const double horizontal_s =
        evaluation::air_distance_m(at, to, u.speed_mps, plan.mission.wind) / u.speed_mps;
    const double dz = to_z - z;
    const double vertical_s = dz > 0 ? dz / u.climb_mps : -dz / u.descent_mps;
    at = to;
    z = to_z;
    return std::max(0.0, vertical_s - horizontal_s);
  };
  std::vector<double> out(items.size(), 0.0);
  for (std::size_t k = 0; k < items.size(); ++k) {
    const MissionItem& it = items[k];
    if (it.command == kNavReturnToLaunch) {
      out[k] = leg(home_local, z) + leg(home_local, home_z);
      continue;
    }
    if (!has_position(it)) continue;
    const LonLat p{it.lon, it.lat};
    const Point q = frame.to_local(p);
    if (it.command == kNavTakeoff)
      out[k] = leg(at, height(it, p));  // straight up where it stands
    else if (it.command == kNavLand)
      out[k] = leg(q, z) + leg(q, height(it, p));
    else
      out[k] = leg(q, height(it, p));
  }
  return out;
}

double vertical_time_s(const Plan& plan, std::size_t index, const std::vector<MissionItem>& items) {
  const auto e = vertical_extra_s(plan, index, items);
  return std::accumulate(e.begin(), e.end(), 0.0);
}

AltitudeOptions whole_flight_altitudes(const Plan& plan) {
  AltitudeOptions alt;
  try {
    (void)resolve_altitudes(alt, altitude_slots(plan), plan.mission.altitude_m);
  } catch (const InputError&) {
    alt.transition_ceiling_m = 0;
  }
  return alt;
}

double uav_vertical_time_s(const Plan& plan, std::size_t index, const AltitudeOptions& opt) {
  const UavPlan& up = plan.uavs.at(index);
  if (up.sorties.empty())
    return up.parts.empty() ? 0.0 : vertical_time_s(plan, index, mission_items(plan, index, up.parts, opt));
  double t = 0.0;
  for (const auto& s : up.sorties)
    t += vertical_time_s(plan, index, mission_items(plan, index, s.parts, opt));
  return t;
}

}  // namespace uavcover::waypoints
