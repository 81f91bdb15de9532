// The corridor and pattern blocks of a mission (docs/patterns.md): parsing, validation, and the
// corridor's covered ground (the centre line buffered by width_m / 2 with flat ends).
#pragma once

#include <nlohmann/json.hpp>

#include "uavcover/mission.hpp"

namespace uavcover::mission {

/// `corridor`: {"line": GeoJSON LineString, "width_m": number}. Throws InputError naming the field.
Corridor parse_corridor(const nlohmann::json& j);

/// The corridor's ground in WGS84: its centre line buffered by width_m / 2, flat ends, mitred joints
/// (round where a bend is sharper than 120 degrees). Throws InputError("corridor.line") when the buffer
/// is not one polygon.
GeoPolygon corridor_polygon(const Corridor& c);

/// The bounds of `pattern.oblique` (docs/patterns.md "Obliques"): the gimbal pitch of the oblique passes
/// (degrees, -90 nadir) and the number of passes.
inline constexpr double kMinObliquePitchDeg = -85.0;
inline constexpr double kMaxObliquePitchDeg = -15.0;
inline constexpr int kMaxObliqueDirections = 8;
/// The far edge of the tilted footprint must stay this far below the horizon: tilt + vfov/2 <= 80 deg
/// (the far edge at most h tan 80 = 5.7 altitudes ahead).
inline constexpr double kMaxObliqueFarEdgeDeg = 80.0;

/// `pattern.oblique`: gimbal_pitch_deg, directions, nadir. Throws InputError naming the field.
Oblique parse_oblique(const nlohmann::json& j);

/// `pattern`: crosshatch, turnaround_m, entry, alternate_transects, capture_in_turnaround.
Pattern parse_pattern(const nlohmann::json& j);

/// The JSON forms written back into the normalised mission.
nlohmann::json corridor_json(const Corridor& c);
nlohmann::json pattern_json(const Pattern& p);

}  // namespace uavcover::mission
