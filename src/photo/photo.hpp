// Photogrammetry (issue 18, docs/photogrammetry.md): where the camera shoots along a plan, how many
// images it takes, and the overlaps and storage that gives. One place for the trigger rules, used by the
// MAVLink-family mission items, the DJI and Litchi exports, plan.json and the evaluation.
//
// Every coverage leg (the straight segment between two consecutive coverage waypoints of a coverage
// part) is shot on its own: the first image at its start, then one every trigger distance d, and the
// last at its end, so a leg of length L takes ceil(L / d) + 1 images. Nothing is shot in transit. Where a
// leg starts at the corner where the previous shot leg ended (nothing flown between them), that corner's
// image is taken once for both legs: the camera refuses a second trigger at the same place (issue 34).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "uavcover/geometry.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::photo {

/// Images on one leg of length `length_m` at trigger distance `trigger_m`: ceil(L / d) + 1 (a leg of
/// length 0 still takes 1).
int leg_images(double length_m, double trigger_m);

/// Where the images of a leg from `a` to `b` are taken (local metres): at a, every `trigger_m`, and at b.
std::vector<Point> leg_shots(const Point& a, const Point& b, double trigger_m);

/// Hold time at each shot in "hover" capture (QGroundControl's Survey: a waypoint with this hold time,
/// then one MAV_CMD_IMAGE_START_CAPTURE image).
inline constexpr double kHoverHoldS = 4.0;

struct UavImages {
  std::string id;
  int legs = 0;
  /// Images the autopilot takes: per leg ceil(L / d) + 1, less one at each shared corner (a leg that
  /// starts where the previous shot leg ended: that image is taken once, see mission_items()).
  int images = 0;
  int shared_corners = 0;           ///< corners shot once for two legs
  int oblique_images = 0;           ///< of `images`, those on parts with a tilted gimbal (docs/patterns.md)
  double trigger_distance_m = 0.0;  ///< its camera's (uavs[i].camera, else the mission's)
  double footprint_across_m = 0.0;  ///< its camera's across-track footprint
  double trigger_interval_s = 0.0;  ///< trigger distance / the UAV's speed
  double hover_time_s = 0.0;        ///< "hover" capture: images * kHoverHoldS (0 otherwise)
  double storage_mb = 0.0;
};

struct Estimate {
  std::string capture;              ///< "distance" or "hover"
  double trigger_distance_m = 0.0;  ///< along-track footprint * (1 - front_overlap)
  double footprint_across_m = 0.0;  ///< across the flight direction
  double footprint_along_m = 0.0;   ///< along it
  std::optional<double> gsd_m;      ///< QGroundControl camera convention only
  double side_overlap = 0.0;        ///< achieved: 1 - spacing / the mission camera's across-track footprint
  double front_overlap =
      0.0;  ///< achieved: 1 - mean (distance between shots / its camera's along-track footprint)
  double gimbal_pitch_deg = -90.0;
  int images = 0;
  int oblique_images = 0;  ///< of `images`, those on parts with a tilted gimbal (docs/patterns.md)
  double storage_mb = 0.0;
  std::vector<UavImages> uavs;
};

/// The estimate for a plan whose mission has a camera; empty without one.
std::optional<Estimate> estimate(const Plan& plan);

/// plan.json's and the evaluation's "images" block.
nlohmann::json to_json(const Estimate& estimate);

}  // namespace uavcover::photo
