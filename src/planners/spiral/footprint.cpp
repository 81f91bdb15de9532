#include "planners/spiral/footprint.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "uavcover/error.hpp"

namespace uavcover::planners::spiral {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
const double kSqrt3 = std::sqrt(3.0);
}  // namespace

double trapezoid_inradius(double a, double b, double height) {
  const double lo = std::min(a, b), hi = std::max(a, b);
  // centre on the axis at distance y from the short side: distance to the short side y, to the long
  // side height - y, to each leg g(y) = c (lo/2 + k y), with c the cosine of the leg's slope
  const double k = (hi - lo) / (2.0 * height);
  const double c = height / std::hypot(height, (hi - lo) / 2.0);
  auto g = [&](double y) { return c * (lo / 2.0 + k * y); };
  if (g(height / 2.0) >= height / 2.0) return height / 2.0;  // the two parallel sides bind
  // the legs bind: the largest circle touches both legs and the long side (g increases with y)
  const double y = (height - c * lo / 2.0) / (1.0 + c * k);
  return std::min(height - y, g(y));
}

Footprint camera_footprint(double altitude_m, double hfov_deg, double vfov_deg, double pitch_deg) {
  const double h = altitude_m, th = hfov_deg * kDeg, tv = vfov_deg * kDeg, beta = pitch_deg * kDeg;
  const double near_angle = beta - tv / 2.0, far_angle = beta + tv / 2.0;
  if (far_angle >= 85.0 * kDeg)
    throw InputError(
        "planner_params.gimbal_pitch_deg",
        "pitch plus half the vertical field of view must stay below 85 degrees (the far edge of the "
        "footprint reaches the horizon)");
  Footprint f;
  // ground distance of the near and far edges ahead of the UAV (negative: behind it)
  const double d_near = h * std::tan(near_angle), d_far = h * std::tan(far_angle);
  f.length_m = d_far - d_near;
  // across-track width grows with the slant range to each edge (eq. 6-7 for a pinhole camera): a
  // corner ray (tan(th/2), tan(tv/2), 1) leaves the edge's central ray at tan(th/2) cos(tv/2) per metre
  const double lateral = std::tan(th / 2.0) * std::cos(tv / 2.0);
  f.near_width_m = 2.0 * h / std::cos(near_angle) * lateral;
  f.far_width_m = 2.0 * h / std::cos(far_angle) * lateral;
  f.inradius_m = trapezoid_inradius(f.near_width_m, f.far_width_m, f.length_m);
  f.side_m = kSqrt3 * f.inradius_m;
  return f;
}

Footprint square_footprint(double side_m) {
  Footprint f;
  f.near_width_m = f.far_width_m = f.length_m = side_m;
  f.inradius_m = side_m / 2.0;
  f.side_m = kSqrt3 * f.inradius_m;  // eq. 3
  return f;
}

}  // namespace uavcover::planners::spiral
