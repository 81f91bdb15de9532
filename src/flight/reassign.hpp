// Reassignment of a failed UAV's remaining coverage (issue 12; Hong et al. 2021 §2.3 describe it,
// docs/flights.md): the uncovered remainder of its region is re-planned with the mission's planner over
// the UAVs still flying, cut into battery sorties, with each helper's own transition altitude.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "export/mission_items.hpp"
#include "uavcover/context.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::flight {

/// A helper UAV and what it has left.
struct Helper {
  std::size_t index = 0;          ///< into plan.uavs
  double battery_fraction = 1.0;  ///< of a full battery left now (0..1); later sorties start full
};

/// What one helper flies in addition to its own plan.
struct ReassignedWork {
  std::string uav;
  std::size_t index = 0;                                      ///< into plan.uavs
  std::vector<PathPart> parts;                                ///< the sub-plan's parts for this UAV
  std::vector<Sortie> sorties;                                ///< battery sorties of that work
  std::vector<std::vector<exporting::MissionItem>> missions;  ///< one per sortie, at its transition altitude
  double coverage_length_m = 0.0;
  int waypoints = 0;  ///< coverage waypoints
};

struct Reassignment {
  std::string failed_uav;
  int last_reached = -1;                 ///< the failed UAV's last reached coverage waypoint (global)
  std::vector<int> remaining_waypoints;  ///< its coverage waypoints not flown (global indices)
  std::vector<GeoPolygon> area;          ///< the remainder re-planned (WGS84)
  double area_m2 = 0.0;
  std::vector<ReassignedWork> work;  ///< one per helper that got some
  std::vector<std::string> warnings;
};

/// The remainder of UAV `failed` after it reached coverage waypoint `last_reached` (-1: none): its
/// region minus the footprint swept along its coverage up to that waypoint, re-planned with
/// plan.mission's planner and seed over `helpers` (shares by remaining battery), cut into sorties.
/// InputError when `failed` or a helper is out of range, or no helper is given. Empty work when nothing
/// is left to cover.
Reassignment reassign(const Plan& plan, std::size_t failed, int last_reached,
                      const std::vector<Helper>& helpers, const exporting::AltitudeOptions& altitude = {},
                      const Context& ctx = {});

}  // namespace uavcover::flight
