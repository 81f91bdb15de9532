// Structure (facade) scans (docs/patterns.md, issue 30): the camera's geometry on a wall at a distance,
// and the facade evaluator. The wall surface (the footprint's perimeter x [0, height_m], and the roof with
// `top`) is sampled at about 0.5 m; a sample is seen by a photo when it lies inside the photo's view
// frustum (its position at the trigger, heading, gimbal pitch, horizontal and vertical fields of view),
// faces the camera (at most 60 degrees from the sample's normal), is not hidden by the building and is at
// most twice the design distance away.
#pragma once

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "uavcover/plan.hpp"

namespace uavcover::evaluation {

/// A camera block's angular geometry, for photos taken at a distance (the wall, not the ground).
struct FacadeCamera {
  double hfov_rad = 0.0;       ///< across the image's width (horizontal on the wall: along the orbit)
  double vfov_rad = 0.0;       ///< across its height (vertical on the wall: across the layers)
  double side_overlap = 0.0;   ///< fraction in [0, 1): between layers
  double front_overlap = 0.0;  ///< fraction: between consecutive photos along a layer
  std::optional<double> image_width_px;
  /// Width and height the image covers on a plane facing the camera at `distance_m`.
  [[nodiscard]] double width_at(double distance_m) const;
  [[nodiscard]] double height_at(double distance_m) const;
  /// Ground (wall) sample distance at `distance_m`, m/px; empty without the image width in pixels.
  [[nodiscard]] std::optional<double> gsd_at(double distance_m) const;
};

/// The camera's fields of view (hfov_deg, or sensor_width_mm / focal_length_mm; vfov_deg, or
/// sensor_height_mm, or image_height_px / image_width_px of the sensor width, else 3:4 of the width's
/// footprint as camera.cpp) and overlaps (the paper's `overlap` po is on both sides: po / 2).
FacadeCamera facade_camera(const Camera& camera);

/// Views per sample and what they add up to.
struct FacadeStats {
  int samples = 0;
  double covered_share = 0.0;         ///< share of samples seen by at least one photo
  std::array<int, 4> views = {};      ///< samples seen by 0, 1, 2, 3 or more photos
  std::array<double, 4> shares = {};  ///< the same as shares of the samples
  double share_3plus = 0.0;           ///< seen by 3 or more (what photogrammetry wants)
  int images = 0;                     ///< photos taken (every coverage part the camera shoots)
};

struct FacadeCoverage {
  double sample_m = 0.5;  ///< requested sample spacing (each wall's columns and the rows are at most this)
  int wall_samples = 0, roof_samples = 0;
  double wall_area_m2 = 0.0, roof_area_m2 = 0.0;
  double standoff_m = 0.0;
  double max_range_m = 0.0;  ///< samples further than this from a photo are not counted as seen by it
  FacadeStats total;
  std::vector<FacadeStats> uavs;  ///< one per plan UAV, each on its own
  std::vector<std::string> uav_ids;
  /// Photogrammetry estimate: images and the wall's sample distance at the standoff (m/px).
  std::optional<double> gsd_wall_m;
  double footprint_width_m = 0.0, footprint_height_m = 0.0;  ///< a photo's extent on the wall at standoff
  /// The wall unrolled: `cols` columns along the perimeter, counter-clockwise from the footprint's first
  /// vertex (as its GeoJSON ring), `rows` rows from the ground up; views[row * cols + col] (all UAVs).
  int cols = 0, rows = 0;
  std::vector<int> wall_start_col;  ///< the first column of each wall (footprint edge)
  std::vector<std::uint16_t> views;
};

struct FacadeOptions {
  double sample_m = 0.5;
};

/// The facade evaluation of a structure plan (empty when the mission has no structure or no camera).
/// Photos are taken as photo.hpp's trigger rule says (each shot leg at its start, every trigger distance,
/// at its end; a shared corner once) with the part's Attitude: altitude (else the mission's), heading per
/// vertex interpolated along the leg (else along the track), gimbal pitch (else the camera's), trigger
/// distance (else the mission camera's).
std::optional<FacadeCoverage> evaluate_facade(const Plan& plan, const FacadeOptions& options = {});

/// plan.json's evaluation "facade" block (and evaluation.json's). `unrolled`: the views picture as rows
/// of digits (views capped at 9, top row first).
nlohmann::json to_json(const FacadeCoverage& facade, bool unrolled = true);

}  // namespace uavcover::evaluation
