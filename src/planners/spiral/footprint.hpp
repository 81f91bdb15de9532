// The camera's ground footprint and the side W_d of the mesh's triangles (Balampanis et al. 2017,
// §IV eq. 1-8): a rectangle looking straight down, an isosceles trapezoid when the gimbal pitches the
// camera forward; the largest circle inside it; the equilateral triangle inscribed in that circle.
#pragma once

namespace uavcover::planners::spiral {

struct Footprint {
  double near_width_m = 0.0;  ///< across-track width of the edge nearest the UAV (a)
  double far_width_m = 0.0;   ///< across-track width of the far edge (b; = a looking down)
  double length_m = 0.0;      ///< along-track extent
  double inradius_m = 0.0;    ///< radius of the largest inscribed circle
  double side_m = 0.0;        ///< W_d = sqrt(3) * inradius: side of the inscribed equilateral triangle
};

/// Radius of the largest circle inside an isosceles trapezoid with parallel sides a and b (either
/// order) at distance `height`; a rectangle when a == b.
double trapezoid_inradius(double a, double b, double height);

/// Footprint of a camera at `altitude_m` with fields of view `hfov_deg` (across track) and `vfov_deg`
/// (along track), pitched `pitch_deg` forward from nadir. Throws InputError on
/// "planner_params.gimbal_pitch_deg" when the far edge reaches the horizon.
Footprint camera_footprint(double altitude_m, double hfov_deg, double vfov_deg, double pitch_deg);

/// A square footprint of side `side_m` (no camera: the spacing ds).
Footprint square_footprint(double side_m);

}  // namespace uavcover::planners::spiral
