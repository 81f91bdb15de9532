// Internal to src/sim: what the simulated vehicle's files share (sim_vehicle.cpp: the link, the
// mission protocol and telemetry; dynamics.cpp: commands' effects, flight, battery and failures;
// fleet.cpp: the fleet's clock). Constants from MAVLink and PX4.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "sim/sim_vehicle.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::sim::detail {

inline constexpr double kGround = 0.05;  // metres: at or below this the vehicle is on the ground
inline constexpr double kBatteryCapacityMah = 5000.0;
inline constexpr double kSwapRadiusM = 5.0;  // arming this close to home swaps a used battery
inline constexpr double kCellsFull = 4.2, kCellsEmpty = 3.3;
inline constexpr int kCells = 4;

// PX4 custom mode: main mode in bits 16..23, sub mode in bits 24..31 (px4_custom_mode.h).
inline constexpr std::uint32_t px4_mode(std::uint32_t main, std::uint32_t sub) {
  return (main << 16) | (sub << 24);
}
inline constexpr std::uint32_t kPx4Auto = 4;
inline constexpr std::uint32_t kPx4Ready = 1, kPx4Loiter = 3, kPx4Mission = 4, kPx4Rtl = 5, kPx4Land = 6;

// MAV_MODE_FLAG
inline constexpr std::uint8_t kCustomModeEnabled = 1, kAutoEnabled = 4, kGuidedEnabled = 8,
                              kStabilizeEnabled = 16, kSafetyArmed = 128;
// MAV_STATE
inline constexpr std::uint8_t kStandby = 3, kActive = 4, kCritical = 5, kEmergency = 6;

inline double norm(const Vec3& a) { return std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z); }
inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }

inline bool is_global(std::uint8_t frame) {
  return frame == 0 || frame == 3 || frame == 5 || frame == 6 || frame == 10 || frame == 11;
}
inline bool is_amsl(std::uint8_t frame) { return frame == 0 || frame == 5; }
/// MAV_FRAME_GLOBAL_TERRAIN_ALT (10) and its _INT form (11): heights above the ground.
inline bool is_terrain(std::uint8_t frame) { return frame == 10 || frame == 11; }

// The navigation commands flown (the others are done at once).
inline bool is_nav(std::uint16_t command) {
  return command == waypoints::kNavWaypoint || command == waypoints::kNavTakeoff ||
         command == waypoints::kNavLand || command == waypoints::kNavReturnToLaunch ||
         (command >= 17 && command <= 19) || command == 82;
}

inline bool for_me(std::uint8_t target, std::uint8_t sysid) { return target == 0 || target == sysid; }

template <typename T>
inline T clamp_to(double v) {
  const double lo = static_cast<double>(std::numeric_limits<T>::min());
  const double hi = static_cast<double>(std::numeric_limits<T>::max());
  return static_cast<T>(std::llround(std::clamp(v, lo, hi)));
}

}  // namespace uavcover::sim::detail
