// The plan: what uavcover gives back for a mission, whatever planner made it.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "uavcover/geometry.hpp"
#include "uavcover/mission.hpp"

namespace uavcover {

enum class PartKind { Coverage, Transit };

/// How a part is flown where a pattern asks for more than the mission's defaults (docs/patterns.md):
/// structure layers at their own height facing the wall, oblique passes with a fixed heading and a tilted
/// gimbal. Every field empty: the mission's altitude, heading along the track, the camera's gimbal pitch.
struct Attitude {
  std::optional<double> altitude_m = {};        ///< the part's height above take-off
  std::vector<double> heading_deg = {};         ///< per vertex: where the camera faces (deg from north)
  std::optional<double> gimbal_pitch_deg = {};  ///< -90 = nadir
  std::optional<Point> roi = {};                ///< region of interest (local metres) the camera looks at
  /// Camera trigger distance along this part (m); empty: the mission camera's ground spacing at altitude.
  std::optional<double> trigger_distance_m = {};
  [[nodiscard]] bool empty() const {
    return !altitude_m && heading_deg.empty() && !gimbal_pitch_deg && !roi && !trigger_distance_m;
  }
};

/// One piece of a UAV's flight, in flight order. Coverage parts are polylines of turning waypoints
/// (a closed loop repeats its first vertex). Transit parts connect start, coverage parts and return.
struct PathPart {
  PartKind kind = PartKind::Coverage;
  std::vector<Point> local;   ///< ENU metres
  std::vector<LonLat> wgs84;  ///< the same vertices in WGS84
  /// Coverage parts: one flag per segment of `local` (local.size() - 1), 1 where the camera is off (turns
  /// and turnarounds, docs/patterns.md); empty: the camera is on over every segment.
  std::vector<std::uint8_t> camera_off = {};
  [[nodiscard]] bool camera_on(std::size_t segment) const {
    return segment >= camera_off.size() || camera_off[segment] == 0;
  }
  Attitude attitude = {};  ///< coverage parts of patterns (structure, oblique); empty: the defaults
  /// Resume with overlap (issue 31, Mission::resume_backoff_m): the leading vertices of a sortie's first
  /// coverage piece that re-fly the stretch before its first waypoint, flown like the rest (the part's
  /// height, camera on) but not counted as coverage waypoints. 0 in a plan's own parts.
  std::size_t lead_in = 0;
};

/// One battery's flight of a UAV (docs/sorties.md): from take-off (the UAV's start) at its transition
/// altitude to the sortie's first coverage waypoint, its piece of the coverage, and back. Waypoint
/// indices are global over the UAV's coverage waypoints (the vertices of its coverage parts, in flight
/// order, counted as UavPlan::turns counts them). A sortie that ends inside a coverage polyline shares
/// that waypoint with the next sortie, so every coverage leg is flown by exactly one sortie.
struct Sortie {
  int index = 0;           ///< 0-based, in flight order
  int first_waypoint = 0;  ///< global index of its first coverage waypoint
  int last_waypoint = 0;   ///< global index of its last coverage waypoint (inclusive)
  /// In flight order: transit out from take-off (absent when take-off is the first waypoint), coverage
  /// pieces with the plan's transits between them, transit back to take-off (absent likewise).
  std::vector<PathPart> parts;
  double length_m = 0.0;      ///< all parts
  int turns = 0;              ///< coverage waypoints (last - first + 1)
  double duration_min = 0.0;  ///< eq. 15 of length_m and turns with the UAV's speed and c1, c2
};

struct UavPlan {
  std::string id;
  double share_requested = 0.0;
  double share_actual = 0.0;           ///< the planner's measure, else the region's share of the free area
  std::vector<GeoPolygon> region;      ///< the UAV's region (exclusive, inside the free area), WGS84
  MultiPolygon region_local;           ///< the same in local metres
  int regions = 0;                     ///< connected pieces of the region flown
  std::vector<PathPart> parts;         ///< in flight order
  double coverage_length_m = 0.0;      ///< length of the coverage parts
  double length_m = 0.0;               ///< total, with transit
  int turns = 0;                       ///< waypoints (turns) of the coverage parts
  double transition_altitude_m = 0.0;  ///< its own altitude for transit (Hong et al. 2021 §2.3)
  /// Battery sorties (docs/sorties.md), filled by plan() for every planner; empty for an idle UAV.
  std::vector<Sortie> sorties;
  /// Expected finish time (minutes from take-off to the last touchdown, all sorties, under the mission's
  /// wind; issue 32): eq. 15, the battery changes and vertical_time_s.
  double expected_finish_min = 0.0;
  /// Seconds its missions climb or descend beyond their horizontal flight (take-off, descents to the
  /// coverage height, climbs back, landing) at the UAV's climb_mps / descent_mps (docs/wind.md).
  double vertical_time_s = 0.0;
  nlohmann::json diagnostics = nlohmann::json::object();  ///< the planner's, opaque
};

struct Plan {
  Mission mission;
  LonLat origin;        ///< the local frame's origin (area centroid)
  std::string planner;  ///< the planner that made it (mission.planner)
  std::vector<UavPlan> uavs;
  std::vector<std::string> warnings;
  /// False when the planner stopped at the time limit and this is its best complete plan so far.
  bool complete = true;
  nlohmann::json diagnostics = nlohmann::json::object();  ///< the planner's, opaque (DARP: placement, grid)
  double compute_time_s = 0.0;
  double free_area_m2 = 0.0;
  /// `"planner": "auto"` (issue 32): which planner won, why, and what the others gave; null otherwise.
  nlohmann::json selection = nullptr;
  /// Altitude layers (issue 32): the vertical separation left in every pair of UAVs; null when unused.
  nlohmann::json separation = nullptr;
  /// Rally points (issue 31, docs/fence-rally.md): the mission's `rally`, or with `propose_rally` the
  /// planner's proposal (one per UAV, free ground near its work); what the exports and uploads carry.
  std::vector<LonLat> rally = {};
};

}  // namespace uavcover
