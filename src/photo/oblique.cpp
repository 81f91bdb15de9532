#include "photo/oblique.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace uavcover::photo {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}

ObliqueFootprint oblique_footprint(double h, double pitch_deg, double hfov_deg, double vfov_deg) {
  const double tilt = (90.0 + pitch_deg) * kDeg;
  const double v = 0.5 * vfov_deg * kDeg;
  const double half_w = std::tan(0.5 * hfov_deg * kDeg) * std::cos(v);  // per metre of slant along the axis
  ObliqueFootprint f;
  f.near_m = h * std::tan(tilt - v);
  f.far_m = h * std::tan(tilt + v);
  f.centre_m = h * std::tan(tilt);
  f.near_width_m = 2.0 * h * half_w / std::cos(tilt - v);
  f.far_width_m = 2.0 * h * half_w / std::cos(tilt + v);
  return f;
}

std::array<Point, 4> footprint_corners(const ObliqueFootprint& f, Point at, double heading_deg) {
  const double b = heading_deg * kDeg;
  const double fx = std::sin(b), fy = std::cos(b);  // forward (east, north)
  const double rx = fy, ry = -fx;                   // right of forward
  auto p = [&](double ahead, double right) {
    return Point{at.x() + fx * ahead + rx * right, at.y() + fy * ahead + ry * right};
  };
  return {p(f.near_m, -0.5 * f.near_width_m), p(f.near_m, 0.5 * f.near_width_m),
          p(f.far_m, 0.5 * f.far_width_m), p(f.far_m, -0.5 * f.far_width_m)};
}

double oblique_trigger_distance(const ObliqueFootprint& f, double track_deg, double heading_deg,
                                double front_overlap) {
  const double d = (track_deg - heading_deg) * kDeg;
  const double c = std::abs(std::cos(d)), s = std::abs(std::sin(d));
  double chord = std::min(c > 1e-9 ? f.depth_m() / c : 1e300, s > 1e-9 ? f.near_width_m / s : 1e300);
  return (1.0 - front_overlap) * chord;
}

double fov_deg(double footprint_m, double height_m) {
  return 2.0 * std::atan(footprint_m / (2.0 * height_m)) / kDeg;
}

}  // namespace uavcover::photo
