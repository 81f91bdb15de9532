// Flight-ready exports of a plan, one function per format, plus export_plan() writing them all.
// Files go to OUT/export/<id>.<ext> (one per UAV), trajectories to OUT/trajectory/<id>.csv.
#pragma once

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "export/mission_items.hpp"
#include "trajectory/trajectory.hpp"
#include "uavcover/artifact.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::exporting {

struct ExportOptions {
  AltitudeOptions altitude;
  trajectory::Options trajectory;
  int qgc_firmware_type = 12;  ///< MAV_AUTOPILOT: 12 PX4, 3 ArduPilot
  int qgc_vehicle_type = 2;    ///< MAV_TYPE: 2 quadrotor
  bool kmz = false;            ///< also write <id>.kmz next to <id>.kml
  std::string kml_altitude_mode = "relativeToGround";
  int dji_drone_enum = 77;  ///< wpml:droneEnumValue (77 = Mavic 3 Enterprise series)
  int dji_drone_sub_enum = 0;
  bool check_separation = true;  ///< refuse to export when check_separation() finds problems
  std::vector<std::string>* warnings =
      nullptr;  ///< when set, receives separation_warnings() and format limits
};

/// The formats export_plan() knows, in a fixed order.
const std::vector<std::string>& known_formats();

/// Per-UAV RFC 7946 FeatureCollection: area and no-fly-zone polygons, the UAV's path parts.
nlohmann::json uav_geojson(const Plan& plan, std::size_t index);
/// RFC 7946 checks (positions [lon, lat] in range, closed rings of >= 4 positions, CCW exteriors,
/// CW holes, LineStrings of >= 2 positions). Returns the problems found, empty when valid.
std::vector<std::string> validate_geojson(const nlohmann::json& doc);

/// QGroundControl .plan (JSON) for UAV `index`.
nlohmann::json qgc_plan(const Plan& plan, std::size_t index, const ExportOptions& opt = {});
/// Mission Planner "QGC WPL 110" text (tab-separated, row 0 home).
std::string wpl_text(const Plan& plan, std::size_t index, const ExportOptions& opt = {});
/// KML document: area, no-fly zones, the UAV's 3D path as a LineString.
std::string kml_text(const Plan& plan, std::size_t index, const ExportOptions& opt = {});
/// DJI WPML: {"wpmz/template.kml", "wpmz/waylines.wpml"} contents.
std::map<std::string, std::string> dji_wpml(const Plan& plan, std::size_t index,
                                            const ExportOptions& opt = {});
/// Litchi mission CSV (export_plan() warns when it holds more than the 99 waypoints Litchi accepts).
std::string litchi_csv(const Plan& plan, std::size_t index, const ExportOptions& opt = {});
/// Plain CSV of the mission items (seq,role,command,frame,lat,lon,alt_m,param1..param4).
std::string waypoints_csv(const Plan& plan, std::size_t index, const ExportOptions& opt = {});

/// Writes a ZIP archive (KMZ) with the given entries, atomically.
void write_zip(const std::filesystem::path& path, const std::map<std::string, std::string>& entries);

/// The requested formats for every UAV as artifacts (export/<id>.<ext>, trajectory/<id>.csv).
Artifacts export_artifacts(const Plan& plan, const std::vector<std::string>& formats,
                           const ExportOptions& opt = {});

/// Writes the requested formats (names from known_formats(); entries may hold comma-separated lists)
/// for every UAV. Throws InputError naming --format for an unknown format, std::runtime_error when
/// the separation check fails or a file cannot be written. Returns the files written.
std::vector<std::filesystem::path> export_plan(const Plan& plan, const std::vector<std::string>& formats,
                                               const std::filesystem::path& out_dir,
                                               const ExportOptions& opt = {});

}  // namespace uavcover::exporting
