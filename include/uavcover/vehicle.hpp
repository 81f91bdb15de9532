// Vehicle profiles (issue 31, docs/vehicle-limits.md): what each flight software takes in one mission
// (item capacity, speed and height limits, fence and rally support), in one table for the mission parser
// (the names), the exports (the limits they clamp or refuse), the capacity split and `uavcover upload`.
// Each number names where it comes from; docs/vehicle-limits.md lists the sources.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "uavcover/mission.hpp"

namespace uavcover {

struct VehicleProfile {
  std::string_view name;   ///< "px4", "ardupilot", "dji", "litchi"
  std::string_view label;  ///< for messages
  /// Mission items one upload holds. For the MAVLink autopilots this counts the items the vehicle
  /// stores, ArduPilot's home (item 0) included; for DJI and Litchi it counts waypoints.
  std::size_t max_items = 0;
  bool items_configurable = false;  ///< board-dependent: the mission's max_mission_items overrides it
  double max_speed_mps = 0.0;       ///< the fastest mission speed the software flies (or takes)
  /// The highest waypoint above take-off the format takes; 0: no limit in the software.
  double max_height_m = 0.0;
  bool mavlink = false;        ///< uploads over the MAVLink mission protocol (`uavcover upload`, flights)
  bool fence = false;          ///< takes a geofence (MAV_MISSION_TYPE_FENCE or the .plan geoFence)
  bool rally = false;          ///< takes rally points (MAV_MISSION_TYPE_RALLY or the .plan rallyPoints)
  bool terrain_frame = false;  ///< heights relative to terrain (MAV_FRAME_GLOBAL_TERRAIN_ALT)
  /// Fence vertices one polygon may have in the vehicle (0: no own limit).
  std::size_t max_fence_vertices = 0;
};

/// The profiles, in the order docs/vehicle-limits.md and the README list them.
inline constexpr std::array<VehicleProfile, 4> kVehicleProfiles{{
    // PX4: dataman's mission storage on NuttX boards (DM_KEY_WAYPOINTS_OFFBOARD_x_MAX 500);
    // MPC_XY_VEL_MAX default 12 m/s; GF_MAX_VER_DIST default 0 = no height limit; fence and rally over
    // MAVLink (mission types 1 and 2); frame 10 refused in a mission (mavlink_mission.cpp); polygon fences up
    // to 64 vertices in QGC's PX4 plug-in (kPx4MaxFenceVertices)
    {"px4", "PX4", 500, false, 12.0, 0.0, true, true, true, false, 64},
    // ArduPilot: AP_Mission::num_commands_max() depends on the board's storage (about 700 on common
    // boards; set max_mission_items); WPNAV_SPEED at most 2000 cm/s; LOCATION_ALT_MAX_M 83 000 m;
    // AC_PolyFence_loader takes fence and rally items; terrain frame stored as terrain altitude
    {"ardupilot", "ArduPilot", 700, true, 20.0, 83000.0, true, true, true, true, 0},
    // DJI WPML (Pilot 2, FlightHub 2) and the Mobile SDK's waypoint V2 missions: altitude [-200, 500] m
    // above take-off, speeds up to 15 m/s (globalTransitionalSpeed, autoFlightSpeed); the waypoint V2
    // mission takes at most 65535 waypoints; no fence or rally points in the route
    {"dji", "DJI WPML", 65535, false, 15.0, 500.0, false, false, false, false, 0},
    // Litchi: a mission holds at most 99 waypoints (DJI waypoint V1: [2, 99]); CSV speed 0..15 m/s,
    // altitude -200..500 m
    {"litchi", "Litchi", 99, false, 15.0, 500.0, false, false, false, false, 0},
}};

/// The profile called `name`, or nullptr.
constexpr const VehicleProfile* vehicle_profile(std::string_view name) {
  for (const auto& p : kVehicleProfiles)
    if (p.name == name) return &p;
  return nullptr;
}

/// The profiles' names for a message that lists them: "px4", "ardupilot", "dji", "litchi".
inline std::string vehicle_profile_names() {
  std::string out;
  for (const auto& p : kVehicleProfiles) out += (out.empty() ? "\"" : ", \"") + std::string(p.name) + "\"";
  return out;
}

/// The item capacity of `profile` with a mission's max_mission_items: where the board decides
/// (ArduPilot) the override is the capacity; elsewhere it can only lower the software's own limit.
constexpr std::size_t mission_capacity(const VehicleProfile& profile, std::optional<int> override_items) {
  if (!override_items || *override_items <= 0) return profile.max_items;
  const auto n = static_cast<std::size_t>(*override_items);
  return profile.items_configurable || n < profile.max_items ? n : profile.max_items;
}

/// The profile UAV `index` flies: its own `autopilot`, else the mission's, else "px4".
inline std::string_view uav_autopilot(const Mission& mission, std::size_t index) {
  const Uav& u = mission.uavs.at(index);
  if (!u.autopilot.empty()) return u.autopilot;
  return mission.autopilot.empty() ? std::string_view("px4") : std::string_view(mission.autopilot);
}

}  // namespace uavcover
