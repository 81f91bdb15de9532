// Flight-ready exports of a plan as bytes: one function per format, plus export_artifacts() producing
// them all as uavcover::Artifact (names export/<id>.<ext> and trajectory/<id>.csv, the UAV id
// unchanged). Only src/io/ writes files. Each exporter keeps to its consumer's limits (see
// docs/exports.md): it clamps with a warning where that is safe (speeds), refuses with InputError
// where it is not (altitudes, no-fly zones) and skips idle UAVs with a warning.
#pragma once

#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "autopilot/fence.hpp"
#include "trajectory/trajectory.hpp"
#include "uavcover/artifact.hpp"
#include "uavcover/plan.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::exporting {

/// The consumers' limits the exporters keep to.
namespace limits {
inline constexpr std::size_t kLitchiMaxWaypoints = 99;  ///< waypoints in one Litchi mission
inline constexpr double kLitchiMaxSpeed = 15.0;         ///< Litchi CSV speed(m/s) column: 0..15
inline constexpr double kLitchiMaxAltitude = 500.0;     ///< Litchi CSV altitude(m): -200..500
inline constexpr double kDjiMaxSpeed = 15.0;    ///< WPML globalTransitionalSpeed [0,15]; waypoint speed max
inline constexpr double kDjiMaxHeight = 500.0;  ///< DJI waypoint altitude range [-200, 500] m above take-off
inline constexpr double kPx4DefaultMaxSpeed = 12.0;  ///< PX4 MPC_XY_VEL_MAX default (m/s)
inline constexpr double kArduPilotMaxSpeed = 20.0;   ///< ArduPilot WPNAV_SPEED max 2000 cm/s
}  // namespace limits

struct ExportOptions {
  waypoints::AltitudeOptions altitude;
  trajectory::Options trajectory;
  /// The trajectory format: 0 = the segment form (trajectory::segments_csv, the default); > 0 = the
  /// trajectory sampled every this many seconds (trajectory::trajectory_csv). Same file name either way.
  double trajectory_step_s = 0;
  /// The flight software the files are for: "px4", "ardupilot", "dji" or "litchi" (issue 31's interface);
  /// empty = "px4". Sets the .plan firmwareType.
  std::string autopilot;
  /// QGC .plan firmwareType (MAV_AUTOPILOT: 12 PX4, 3 ArduPilot); -1 = from the autopilot (3 for
  /// "ardupilot", 12 otherwise). An explicit value wins (the CLI's --firmware-type).
  int qgc_firmware_type = -1;
  int qgc_vehicle_type = 2;  ///< MAV_TYPE: 2 quadrotor
  /// .plan inclusion fence: distance kept around everything flown
  double geofence_margin_m = autopilot::kFenceMarginM;
  bool kmz = false;                                    ///< also export <id>.kmz next to <id>.kml
  std::string kml_altitude_mode = "relativeToGround";  ///< clampToGround, relativeToGround or absolute
  int dji_drone_enum = 77;       ///< wpml:droneEnumValue (77 = Mavic 3 Enterprise series)
  int dji_drone_sub_enum = 0;    ///< wpml:droneSubEnumValue (77: 0 M3E, 1 M3T, 2 M3M)
  int dji_payload_enum = -1;     ///< wpml:payloadEnumValue; -1 = the declared drone's own camera
  bool check_separation = true;  ///< refuse to export when check_separation() finds problems
  /// One file per battery sortie (docs/sorties.md) for qgc, wpl, kml (kmz), dji, litchi and csv:
  /// export/<id>.s<k>.<ext>, k = 1, 2, ... in flight order, each a whole mission (take-off, transit at
  /// the UAV's transition altitude, its coverage, return) in place of export/<id>.<ext>. geojson and
  /// trajectory stay one file per UAV.
  bool per_sortie = false;
  /// Missions split to the vehicle's item capacity (issue 31, docs/vehicle-limits.md): like per_sortie
  /// (export/<id>.s<k>.<ext>), each sortie cut further where its mission holds more items than the
  /// profile (autopilot, else the UAV's or the mission's) stores; implies per_sortie.
  bool split_capacity = false;
  std::vector<std::string>* warnings = nullptr;  ///< when set, receives every warning (clamps, skips)
  /// The mission items of the UAV being written, for the plan (or sortie) being written, as the checks
  /// made them (CheckedExport sets it for each writer call: the items are made once per UAV per export,
  /// not once per format); null: the writer makes them.
  const std::vector<waypoints::MissionItem>* items = nullptr;
  /// When set, the trajectory formats keep each UAV's trajectory here (by UAV id) and make it once per
  /// export: the trajectory CSV and its plot share it, and a caller that reports the trajectories (the
  /// CLI's summary) reads them instead of making them again.
  std::map<std::string, trajectory::Trajectory>* trajectories = nullptr;
};

/// The formats export_artifacts() knows, in a fixed order: the names of the table export/formats.hpp.
const std::vector<std::string>& known_formats();

/// The format names in `formats` (entries may hold comma-separated lists; case and blanks ignored;
/// duplicates dropped). Throws InputError naming "formats" for an unknown format or an empty list.
std::vector<std::string> parse_formats(const std::vector<std::string>& formats);

/// True when the UAV has no coverage part (nothing to fly but take-off and return).
bool idle(const UavPlan& uav);

/// Per-UAV RFC 7946 FeatureCollection: area and no-fly-zone polygons, the UAV's path parts.
nlohmann::json uav_geojson(const Plan& plan, std::size_t index);
/// RFC 7946 checks (positions [lon, lat] in range, closed rings of >= 4 positions, CCW exteriors,
/// CW holes, LineStrings of >= 2 positions). Returns the problems found, empty when valid.
std::vector<std::string> validate_geojson(const nlohmann::json& doc);

/// The autopilot the export is for: opt.autopilot, else "px4". Throws InputError naming "autopilot"
/// for an unknown value. (`plan` is for the mission's own "autopilot" field, not added yet.)
std::string export_autopilot(const Plan& plan, const ExportOptions& opt);
/// The .plan firmwareType: opt.qgc_firmware_type when >= 0, else 3 (MAV_AUTOPILOT_ARDUPILOTMEGA) for
/// ArduPilot and 12 (MAV_AUTOPILOT_PX4) for the others.
int qgc_firmware_type(const Plan& plan, const ExportOptions& opt);

/// QGroundControl .plan (JSON) for UAV `index`, with a geofence PX4 accepts (geofence.hpp).
nlohmann::json qgc_plan(const Plan& plan, std::size_t index, const ExportOptions& opt = {});
/// Mission Planner "QGC WPL 110" text (tab-separated, row 0 home).
std::string wpl_text(const Plan& plan, std::size_t index, const ExportOptions& opt = {});
/// KML document: area, no-fly zones, the UAV's 3D path as a LineString.
std::string kml_text(const Plan& plan, std::size_t index, const ExportOptions& opt = {});
/// DJI WPML: {"wpmz/template.kml", "wpmz/waylines.wpml"} contents.
std::map<std::string, std::string> dji_wpml(const Plan& plan, std::size_t index,
                                            const ExportOptions& opt = {});
/// Litchi mission CSV: one text per mission of at most 99 waypoints (consecutive missions share
/// their joining waypoint).
std::vector<std::string> litchi_csv(const Plan& plan, std::size_t index, const ExportOptions& opt = {});
/// Plain CSV of the mission items (seq,role,command,frame,lat,lon,alt_m,param1..param4).
std::string waypoints_csv(const Plan& plan, std::size_t index, const ExportOptions& opt = {});

struct CheckedPlan;

/// An export of `plan` with `opt` whose checks (ids, altitudes, separation, no-fly zones, the autopilots'
/// upload rules: the same as export_artifacts') have run once; any number of formats are then written
/// from it without running them again (issue 27: the checks once per plan, not once per format).
/// Holds `plan` by reference: it must outlive this.
class CheckedExport {
 public:
  /// Throws InputError naming the field for the first problem.
  CheckedExport(const Plan& plan, const ExportOptions& opt);
  ~CheckedExport();
  CheckedExport(CheckedExport&&) noexcept;
  CheckedExport& operator=(CheckedExport&&) = delete;
  /// The checks' warnings (altitudes, separation hazards, idle UAVs skipped, upload limits).
  [[nodiscard]] const std::vector<std::string>& warnings() const;
  /// The files of `formats` (parse_formats()) for every flown UAV; the writers' warnings (clamped
  /// speeds, ...) are appended to `warnings` when given. Throws InputError for an unknown format or when
  /// two files would have one name; nothing is produced then.
  [[nodiscard]] Artifacts write(const std::vector<std::string>& formats,
                                std::vector<std::string>* warnings = nullptr) const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

/// Every requested format (names from known_formats(), see parse_formats()) for every UAV that has
/// coverage parts, as artifacts. Throws InputError for an unknown format, unusable options, UAV ids
/// that are not file names, altitudes that cannot be separated under the ceiling or kept within a
/// consumer's limits, a failed separation check or a flight through a no-fly zone; nothing is
/// produced then.
Artifacts export_artifacts(const Plan& plan, const std::vector<std::string>& formats,
                           const ExportOptions& opt = {});

}  // namespace uavcover::exporting
