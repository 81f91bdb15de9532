// Internal to src/export/: what several formats share (reading the waypoint model's camera plan, number
// text, clamps and height checks). Not part of the export interface (export/export.hpp).
#pragma once

#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "export/export.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::exporting {

/// Positioned items a waypoint-only format (DJI, Litchi) flies: everything but take-off and landing.
std::vector<const waypoints::MissionItem*> flown_waypoints(const std::vector<waypoints::MissionItem>& items);

/// What the camera does at a flown waypoint, as the MAVLink items after it say (src/photo/photo.hpp):
/// DJI and Litchi translate the same trigger plan into their own actions.
struct CameraAt {
  double leg_trigger_m = 0.0;  ///< a leg starts here, shot every this many metres (distance capture)
  int photos = 0;              ///< single images taken here (leg ends; hover captures)
  double hold_s = 0.0;         ///< hover before shooting
  std::size_t leg_end = 0;     ///< where a leg starts: the waypoint where its shooting stops
  double inside_leg_m = 0.0;   ///< a waypoint inside a leg (terrain following): the leg's trigger distance
};
/// One CameraAt per flown waypoint of `items`, in order.
std::vector<CameraAt> camera_actions(const std::vector<waypoints::MissionItem>& items);

/// The attitude at a flown waypoint, as the MAVLink items say (PathPart::attitude through the waypoint
/// model): DJI, Litchi, KML and GeoJSON write it in their own terms.
struct AttitudeAt {
  double heading_deg = std::numeric_limits<double>::quiet_NaN();  ///< NAV_WAYPOINT param4; NaN = none
  /// The gimbal pitch the camera holds when the UAV leaves this waypoint (the last GIMBAL_MANAGER_PITCHYAW
  /// so far); NaN before any
  double gimbal_pitch_deg = std::numeric_limits<double>::quiet_NaN();
  bool gimbal_changed = false;  ///< a gimbal item follows this waypoint (the pitch changes here)
  bool roi = false;             ///< a region of interest holds when the UAV leaves this waypoint
  double roi_lat = 0, roi_lon = 0, roi_alt = 0;  ///< its position (alt in the items' frame)
};
/// An angle the items carry as a float, to 0.001 deg: -45.3, not -45.29999923706055.
double degrees(double v);
/// One AttitudeAt per flown waypoint of `items`, in order.
std::vector<AttitudeAt> attitude_actions(const std::vector<waypoints::MissionItem>& items);

/// Shortest round-trip text of a number; NaN as "NaN" (how Mission Planner and pymavlink read it).
std::string num(double v);
/// A latitude or longitude with 9 decimals.
std::string coord(double v);
/// A JSON number, or null for NaN (QGroundControl's own convention, e.g. yaw "keep heading").
nlohmann::json jnum(double v);
/// JSON text and a newline; invalid UTF-8 in names (a tampered plan) is replaced rather than thrown on.
std::string dump(const nlohmann::json& doc, int indent);

/// UAV `index`'s mission items in `plan`: opt.items when the checks made them (with opt.altitude
/// resolved, which is then `altitudes`), else made with `altitudes`.
std::vector<waypoints::MissionItem> items_of(const Plan& plan, std::size_t index, const ExportOptions& opt,
                                             const waypoints::AltitudeOptions& altitudes);

/// Adds a warning to opt.warnings when set.
void warn(const ExportOptions& opt, std::string message);

/// The UAV's speed within a consumer's maximum: clamped with a warning.
double speed_within(const Plan& plan, std::size_t index, double max_mps, const char* consumer,
                    const ExportOptions& opt);

/// The items with heights above take-off, for the consumers that take those (DJI WPML relativeToStartPoint,
/// Litchi altitudemode 0): with a DEM, the AMSL altitudes minus the DEM's ground at take-off.
std::vector<waypoints::MissionItem> above_takeoff(const Plan& plan, std::size_t index,
                                                  std::vector<waypoints::MissionItem> items);

/// Refuses waypoint heights above a consumer's maximum (clamping an altitude would break separation).
void check_heights(const Plan& plan, std::size_t index, const std::vector<const waypoints::MissionItem*>& wps,
                   double max_m, const char* consumer);

/// The gimbal pitch of the camera UAV `index` carries: its own (uavs[i].camera), else the mission's.
double gimbal_pitch_of(const Plan& plan, std::size_t index);

}  // namespace uavcover::exporting
