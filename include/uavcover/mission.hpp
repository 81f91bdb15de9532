// The mission: what the operator asks for (mission file version 1, see docs/mission-format.md).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "uavcover/geometry.hpp"
#include "uavcover/terrain.hpp"

namespace uavcover {

enum class Mode { Strict, Coverage };

/// Camera block. Either (hfov_deg, overlap) -> paper eq. 14, or the QGroundControl
/// convention (sensor_width_mm, focal_length_mm, image_width_px, side_overlap).
struct Camera {
  double altitude_m = 0.0;
  std::optional<double> hfov_deg;
  std::optional<double> overlap;
  std::optional<double> sensor_width_mm;
  std::optional<double> focal_length_mm;
  std::optional<double> image_width_px;
  std::optional<double> side_overlap;
  // Photogrammetry (docs/photogrammetry.md). The image's width lies across the flight direction.
  double front_overlap = 0.75;     ///< along-track overlap of consecutive images, [0, 0.95]
  std::optional<double> vfov_deg;  ///< paper convention: vertical FOV (default: 4:3 of hfov's footprint)
  std::optional<double> sensor_height_mm;  ///< QGC convention: sensor height (default: 3/4 of the width)
  std::optional<double> image_height_px;   ///< QGC convention: image height (default: 3/4 of the width)
  std::optional<double> min_trigger_interval_s;  ///< the camera cannot shoot faster than this
  double gimbal_pitch_deg = -90.0;               ///< set before the first leg; -90 = nadir
  std::string capture = "distance";              ///< "distance" (fly and shoot) or "hover" (stop and shoot)
  double image_size_mb = 8.0;                    ///< storage per image, for the estimate
};

/// What a camera block gives on the ground (parse_mission derives it for the mission's camera and for
/// each UAV's own camera, with the same formulas: docs/mission-format.md).
struct CameraGeometry {
  double footprint_m = 0.0;              ///< footprint width across the flight direction
  double along_track_footprint_m = 0.0;  ///< footprint along the flight direction
  double spacing_m = 0.0;                ///< line spacing its overlap asks for
  double trigger_distance_m = 0.0;       ///< along-track footprint * (1 - front_overlap)
  std::optional<double> gsd_m;           ///< ground sample distance (QGC camera convention)
};

/// Defaults for optional per-UAV fields (documented in docs/mission-format.md).
struct UavDefaults {
  static constexpr double speed_mps = 5.0;
  static constexpr double max_accel_mps2 = 2.0;
  static constexpr double endurance_min = 25.0;
  static constexpr double turn_c1 = 3.0;  // eq. 15 turn-delay constant c1 (s)
  static constexpr double turn_c2 = 1.0;  // eq. 15 turn-delay constant c2 (m/s)
  // vertical speeds of the whole-flight time (issue 32, docs/wind.md): PX4's MPC_Z_V_AUTO_UP (3 m/s)
  // and ArduPilot's WPNAV_SPEED_DN (150 cm/s) defaults
  static constexpr double climb_mps = 3.0;
  static constexpr double descent_mps = 1.5;
};

struct Uav {
  std::string id;
  std::optional<LonLat> start;  ///< given by the user; empty -> seeded random start
  LonLat start_resolved{};      ///< the start actually used (given or drawn)
  double share = 0.0;           ///< normalised, sums to 1 over all UAVs
  double speed_mps = UavDefaults::speed_mps;
  double max_accel_mps2 = UavDefaults::max_accel_mps2;
  double endurance_min = UavDefaults::endurance_min;
  double turn_c1 = UavDefaults::turn_c1;
  double turn_c2 = UavDefaults::turn_c2;
  double climb_mps = UavDefaults::climb_mps;      ///< vertical speed up in missions (take-off, climbs)
  double descent_mps = UavDefaults::descent_mps;  ///< vertical speed down (descents, landing)
  /// Heterogeneous cameras: this UAV's own camera (same block as the mission's, same altitude);
  /// empty: the mission's camera. `camera_geometry` is derived from it by parse_mission.
  std::optional<Camera> camera;
  std::optional<CameraGeometry> camera_geometry;
  /// `"share": "auto"` (issue 32, docs/mission-format.md): the share is derived from the UAV's area rate.
  bool share_auto = false;
  /// Vehicle profile (issue 31, docs/vehicle-limits.md): "px4", "ardupilot", "dji" or "litchi"; empty:
  /// the mission's `autopilot`.
  std::string autopilot = {};
};

inline constexpr double kDefaultBatteryReserve = 0.2;

/// A corridor (docs/patterns.md), given instead of `area`: the centre line buffered by width_m / 2 with
/// flat ends is the covered ground (parse_mission puts that polygon into Mission::area).
struct Corridor {
  std::vector<LonLat> line;  ///< the centre line, at least two distinct vertices
  double width_m = 0.0;
};

/// A structure (facade) scan (docs/patterns.md), given instead of `area`: orbit layers at standoff_m
/// from the footprint's walls, the camera facing the wall.
struct Structure {
  GeoPolygon footprint;      ///< the building's outline (normalised: closed, CCW)
  double height_m = 0.0;     ///< wall height above the ground at take-off
  double standoff_m = 0.0;   ///< horizontal distance from the wall to the orbit
  bool top = false;          ///< a nadir pass over the roof
  double safe_height_m = 5;  ///< the bottom layer flies at least this high above the ground
};

/// Smart-Oblique-style passes (docs/patterns.md): the pattern block's `oblique`.
struct Oblique {
  double gimbal_pitch_deg = -45.0;  ///< camera pitch on the oblique passes (-90 = nadir)
  int directions = 4;               ///< oblique passes, each with a fixed heading
  bool nadir = true;                ///< a nadir grid as well
};

/// The mission's wind (issue 32): a steady wind for the time model and the sweep direction.
struct Wind {
  double speed_mps = 0.0;
  double from_deg = 0.0;  ///< where the wind blows from, degrees clockwise from true north
};

/// The pattern options (docs/patterns.md): the mission's `pattern` block.
struct Pattern {
  std::optional<Oblique> oblique = {};  ///< oblique passes (with or without the nadir grid)
  bool crosshatch = false;              ///< a second sweep of each UAV's part at 90 degrees to the first
  double turnaround_m = 0.0;            ///< legs extend beyond their ends by this much, camera off
  std::string entry = "auto";           ///< first leg's start: auto (nearest the start), nw, ne, sw, se
  bool alternate_transects = false;     ///< every other lane, then back for the rest
  bool capture_in_turnaround = false;   ///< camera on in turns and turnarounds
};

/// A parsed, validated, normalised mission. Produced by parse_mission().
struct Mission {
  std::string name;
  std::vector<GeoPolygon> area;          ///< normalised: closed rings, outer CCW, holes CW
  std::vector<GeoPolygon> no_fly_zones;  ///< normalised likewise (holes of `area` are moved here)
  std::optional<Camera> camera;
  double spacing_m = 0.0;                         ///< scanning density ds (given or from the camera)
  std::optional<double> gsd_m;                    ///< ground sample distance (QGC camera convention)
  std::optional<double> footprint_m;              ///< camera footprint width on the ground
  std::optional<double> along_track_footprint_m;  ///< camera footprint along the flight direction
  std::optional<double> trigger_distance_m;       ///< along-track footprint * (1 - front_overlap)
  double altitude_m = 40.0;                       ///< mission altitude
  std::string altitude_source = "default";        ///< "camera", "altitude_m" or "default"
  std::vector<Uav> uavs;
  Mode mode = Mode::Strict;
  std::string planner = "darp";
  /// The planner's parameters, validated against its schema with every default filled in.
  nlohmann::json planner_params = nlohmann::json::object();
  std::uint64_t seed = 0;
  /// Share of each battery's endurance kept in reserve when a UAV's coverage is cut into sorties
  /// (docs/sorties.md): a sortie lasts at most endurance_min * (1 - battery_reserve).
  double battery_reserve = kDefaultBatteryReserve;
  std::string source_format = "uavcover-v1";  ///< or "mcpp-optimized-darp"
  /// Ground from a DEM (docs/photogrammetry.md): absent = flat ground, heights relative to take-off.
  std::optional<Terrain> terrain;
  /// A corridor mission (docs/patterns.md): `area` is its buffered polygon.
  std::optional<Corridor> corridor = {};
  /// The pattern block; absent: the planners' own sweeps, camera on over every coverage segment.
  std::optional<Pattern> pattern = {};
  /// A structure (facade) scan (docs/patterns.md): given instead of `area`.
  std::optional<Structure> structure = {};
  /// A steady wind (issue 32): the time model uses each leg's ground speed under it.
  std::optional<Wind> wind = {};
  /// `"planner": "auto"` (issue 32): what the best plan is: "time", "poc", "turns" or "length".
  std::string objective = "time";
  /// Transition altitudes (issue 32): "hong" (one per UAV, Hong et al. 2021 §2.3) or "layers" (the
  /// conflict graph's colouring: only UAVs whose transits cross others' work or transits differ).
  std::string transition_altitudes = "hong";
  /// Rally points (issue 31, docs/fence-rally.md): safe landing points, each inside the area's
  /// bounding box margin and outside every no-fly zone. Empty: none given (the exports then write the
  /// planner's proposed points when `propose_rally` is set).
  std::vector<LonLat> rally = {};
  /// Propose one rally point per UAV (free ground near its work, away from the no-fly zones).
  bool propose_rally = false;
  /// Resume with overlap (issue 31, docs/sorties.md): a resumed flight, and every battery sortie after
  /// the first, starts this far before its first waypoint along the path. Absent: one photo base
  /// (trigger_distance_m), or 0 without a camera.
  std::optional<double> resume_backoff_m = {};
  /// Vehicle profile (issue 31, docs/vehicle-limits.md) every UAV without its own flies: "px4",
  /// "ardupilot", "dji", "litchi"; empty: none named (exports default to px4).
  std::string autopilot = {};
  /// The profile's mission item capacity overridden (ArduPilot's depends on the board); empty: the
  /// profile's.
  std::optional<int> max_mission_items = {};
};

struct ParseOptions {
  /// Upper bound on grid cells (sub-cells of size ds) the free-area bounding box may need.
  std::size_t max_cells = 4'000'000;
};

/// Parses and validates a mission file (uavcover v1 or mCPP-optimized-DARP input, detected
/// automatically). Throws InputError naming the field and the problem.
Mission parse_mission(std::string_view json_text, const ParseOptions& options = {});

/// Serialises the normalised mission back to uavcover v1 JSON text.
std::string mission_to_json(const Mission& mission, int indent = 1);

}  // namespace uavcover
