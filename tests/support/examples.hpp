// Planned examples and error helpers shared by the tests.
#pragma once

#include <cmath>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "support/files.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover::testing {

/// examples/olive-grove.json planned once (3 UAVs, DARP, seed 42).
inline const Plan& olive_grove_plan() {
  static const Plan p = plan(
      parse_mission(slurp(std::filesystem::path(UAVCOVER_SOURCE_DIR) / "examples" / "olive-grove.json")));
  return p;
}

/// The olive grove plan with the same paths, where UAV `uav` carries its own camera (uavs[i].camera)
/// seeing `footprint_m` across at the mission's altitude (50 m; the mission's camera sees 74.5 m).
inline Plan olive_grove_with_own_camera(std::size_t uav, double footprint_m) {
  auto j = nlohmann::json::parse(
      slurp(std::filesystem::path(UAVCOVER_SOURCE_DIR) / "examples" / "olive-grove.json"));
  const double altitude = j["camera"]["altitude_m"].get<double>();
  j["uavs"][uav]["camera"] = {
      {"altitude_m", altitude},
      {"hfov_deg", 2.0 * std::atan(footprint_m / (2.0 * altitude)) * 180.0 / std::numbers::pi},
      {"overlap", 0.5}};
  const Mission parsed = parse_mission(j.dump());
  Plan p = olive_grove_plan();
  p.mission.uavs[uav].camera = parsed.uavs[uav].camera;
  p.mission.uavs[uav].camera_geometry = parsed.uavs[uav].camera_geometry;
  return p;
}

/// The field an InputError thrown by `f` names, or "(no InputError)".
inline std::string input_error_field(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.field();
  }
  return "(no InputError)";
}

}  // namespace uavcover::testing
