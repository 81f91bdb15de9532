// The tilted camera's ground footprint (Balampanis et al. 2017, eq. 6-8; docs/patterns.md "Obliques"):
// a camera at height h whose optical axis is tilted `tilt` from nadir (tilt = 90 + gimbal pitch) sees a
// trapezoid on flat ground, its near and far edges across the direction the camera faces.
#pragma once

#include <array>

#include "uavcover/geometry.hpp"

namespace uavcover::photo {

struct ObliqueFootprint {
  double near_m = 0.0;        ///< ground distance ahead of the UAV to the near edge: h tan(tilt - vfov/2)
  double far_m = 0.0;         ///< to the far edge: h tan(tilt + vfov/2)
  double near_width_m = 0.0;  ///< the near edge's length (eq. 6's a)
  double far_width_m = 0.0;   ///< the far edge's length (eq. 7's b)
  double centre_m = 0.0;      ///< where the optical axis meets the ground: h tan(tilt)
  [[nodiscard]] double depth_m() const { return far_m - near_m; }
};

/// The trapezoid of a pinhole camera at `height_m` with gimbal pitch `pitch_deg` (-90 nadir, 0
/// horizontal) and fields of view `hfov_deg` (across the image's width, i.e. across the direction the
/// camera faces) and `vfov_deg` (along it). An edge at angle e from nadir lies h tan(e) ahead, at slant
/// range h / cos(e), and is 2 h tan(hfov/2) cos(vfov/2) / cos(e) long: the slant range times the image
/// width's angle at that image row (the paper's eq. 6-7 take 2 tan(hfov/2) at every row, which is
/// 1 / cos(vfov/2) larger). At pitch -90 it is the nadir rectangle 2 h tan(hfov/2) x 2 h tan(vfov/2).
/// Requires tilt + vfov/2 < 90 (the far edge below the horizon).
ObliqueFootprint oblique_footprint(double height_m, double pitch_deg, double hfov_deg, double vfov_deg);

/// The trapezoid's corners on the ground (local metres) for a UAV at `at` whose camera faces bearing
/// `heading_deg` (clockwise from north): near-left, near-right, far-right, far-left.
std::array<Point, 4> footprint_corners(const ObliqueFootprint& f, Point at, double heading_deg);

/// Distance between shots along a track at `track_deg` (bearing) with the camera facing `heading_deg`,
/// for `front_overlap`: (1 - front_overlap) times the chord of the near rectangle (near width x depth)
/// along the track, min(depth / |cos d|, near width / |sin d|), d the angle between track and heading.
double oblique_trigger_distance(const ObliqueFootprint& f, double track_deg, double heading_deg,
                                double front_overlap);

/// The camera's fields of view from its nadir footprint at height h: 2 atan(width / 2h) (degrees).
double fov_deg(double footprint_m, double height_m);

}  // namespace uavcover::photo
