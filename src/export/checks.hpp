// Internal to src/export/: the checks every export of a plan passes before any format is written, run
// once per export (not once per format): usable UAV ids, altitudes separable under the ceiling, the
// separation check, no flight through a no-fly zone, and the autopilots' upload rules.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "export/export.hpp"
#include "sorties/sorties.hpp"

namespace uavcover::exporting {

/// UAV ids are used unchanged in file names: the parser's id rule, checked again here for plan
/// folders that did not come through it.
bool usable_id(const std::string& id);

/// The autopilots' upload rules (src/autopilot/rules.hpp) on the MAVLink items of UAV `i` of `p` (what the
/// .plan, .waypoints, CSV and `uavcover upload` carry): a rule the autopilots refuse the mission for
/// refuses the export; the limits that depend on the vehicle's configuration (item capacity, PX4's
/// distance parameters) warn, for the autopilot the export is for.
void check_consumers(const Plan& p, std::size_t i, const std::vector<waypoints::MissionItem>& items,
                     const std::string& autopilot, std::vector<std::string>& warnings);

/// The items UAV `i`'s mission in `p` puts in the vehicle for `autopilot` (a profile name): ArduPilot's
/// with home as item 0, PX4's as exported, DJI's and Litchi's waypoints (issue 31's capacity split).
std::size_t stored_items(const Plan& p, std::size_t i, const std::string& autopilot,
                         const waypoints::AltitudeOptions& altitude);

/// What the checks found a plan's export may write.
struct CheckedPlan {
  std::string autopilot;           ///< export_autopilot()
  std::vector<std::size_t> flown;  ///< the UAVs with coverage, in plan order (idle ones are skipped)
  /// With per_sortie: each flown UAV's sorties (cut now when the plan has none, e.g. built by hand).
  std::map<std::size_t, std::vector<Sortie>> sorties;
  /// Each flown UAV's mission items in the plan, and with per_sortie in each of its sorties (by the
  /// sortie's position in `sorties`), as the checks made them: the writers' ExportOptions::items.
  std::map<std::size_t, std::vector<waypoints::MissionItem>> items;
  std::map<std::pair<std::size_t, std::size_t>, std::vector<waypoints::MissionItem>> sortie_items;
};

/// Runs every check of an export of `plan` with `opt`; resolves opt.altitude (resolve_altitudes) in
/// place and appends the warnings to `warnings`. Throws InputError naming the field for the first problem.
CheckedPlan check_plan(const Plan& plan, ExportOptions& opt, std::vector<std::string>& warnings);

}  // namespace uavcover::exporting
