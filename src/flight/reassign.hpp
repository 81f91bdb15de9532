// Reassignment of a failed UAV's remaining coverage (issue 12; Hong et al. 2021 §2.3 describe it,
// docs/flights.md): the uncovered remainder of its region is re-planned with the mission's planner over
// the UAVs still flying, cut into battery sorties, with each helper's own transition altitude.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "uavcover/context.hpp"
#include "uavcover/plan.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::flight {

/// A helper UAV and what it has left.
struct Helper {
  std::size_t index = 0;          ///< into plan.uavs
  double battery_fraction = 1.0;  ///< of a full battery left now (0..1); later sorties start full
  /// Where its new work starts (the reassignment "from the air": its live position). Unset: its take-off
  /// point (the work is flown after its current sortie lands).
  std::optional<LonLat> depot{};
};

/// What one helper flies in addition to its own plan.
struct ReassignedWork {
  std::string uav;
  std::size_t index = 0;  ///< into plan.uavs
  /// The sub-plan's parts for this UAV; `local` in the full plan's frame (plan.origin).
  std::vector<PathPart> parts;
  /// Battery sorties of that work (local likewise); waypoint indices count the work's coverage
  /// waypoints (0..waypoints-1). Empty when one leg does not fit a battery (a warning says so; the
  /// work is then one mission).
  std::vector<Sortie> sorties;
  /// One per sortie, at the helper's transition altitude of the full plan; MissionItem::waypoint counts
  /// as `sorties` do.
  std::vector<std::vector<waypoints::MissionItem>> missions;
  double coverage_length_m = 0.0;
  int waypoints = 0;  ///< coverage waypoints
};

struct Reassignment {
  std::string failed_uav;
  int last_reached = -1;                 ///< the failed UAV's last reached coverage waypoint (global)
  std::vector<int> remaining_waypoints;  ///< its coverage waypoints not flown (global indices)
  /// The remainder (WGS84). The sub-mission plans it grown by half the largest helper's footprint
  /// within the free area, so that the planners' grids reach its edges (docs/flights.md).
  std::vector<GeoPolygon> area;
  double area_m2 = 0.0;
  std::vector<ReassignedWork> work;  ///< one per helper that got some
  std::vector<std::string> warnings;
};

/// The failed UAV's region (local metres) minus the evaluator's footprint of that UAV
/// (evaluation::footprint_for(plan.mission, failed): its own camera's, else the mission's) swept along
/// its coverage legs up to waypoint `last_reached`, without pieces smaller than one footprint square. Empty
/// when `last_reached` is its last waypoint. InputError naming "failed" or "last_reached" when out of range.
MultiPolygon remainder_area(const Plan& plan, std::size_t failed, int last_reached, const Context& ctx = {});

/// The remainder of UAV `failed` after it reached coverage waypoint `last_reached` (-1: none): its
/// region minus the footprint swept along its coverage up to that waypoint, re-planned with
/// plan.mission's planner and seed over `helpers` (shares by remaining battery, each with its own
/// camera), cut into sorties.
/// A helper without a depot starts from its take-off point with a full battery (its missions are
/// uploaded after its current sortie lands); battery_fraction sets the shares. A helper with a depot
/// (from the air) has its work planned from there: its first mission takes off (climbs or descends to
/// its transition altitude) at the depot, its sorties are cut for the battery it has left
/// (endurance x battery_fraction, conservative for the later ones, which start full from home).
/// InputError naming "failed", "last_reached", "helpers", "helpers[i].index" (out of range, the failed
/// UAV, twice), "helpers[i].battery_fraction" (outside (0, 1]), "helpers[i].depot" (not a finite
/// position on the globe) or "altitude.*". Empty work when nothing is left to cover. ctx: progress
/// ("reassign", "reassign/<plan stage>") and stops (Cancelled).
Reassignment reassign(const Plan& plan, std::size_t failed, int last_reached,
                      const std::vector<Helper>& helpers, const waypoints::AltitudeOptions& altitude = {},
                      const Context& ctx = {});

}  // namespace uavcover::flight
