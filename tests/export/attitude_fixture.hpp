// A plan whose coverage parts carry PathPart::attitude, for the tests of the waypoint model and the exports
// (issue 30, docs/exports.md "Attitude"): the two-UAV fixture with UAV "alpha" flying, in the west half,
//  0 an orbit of radius 30 m around (-50, 0) at its own altitude of 30 m, heading at every vertex toward the
//    centre;
//  1 a pass with the gimbal at -45 deg and a fixed heading of 90 deg (east);
//  2 a pass looking at a region of interest (-50, 0);
//  3 a pass at its own altitude of 55 m with its own trigger distance of 7 m.
#pragma once

#include <cmath>
#include <numbers>
#include <vector>

#include "export/fixture.hpp"

namespace uavcover::fixture {

inline constexpr double kOrbitRadius = 30.0;
inline const Point kOrbitCentre{-50.0, 0.0};
inline constexpr double kOrbitAltitude = 30.0;
inline constexpr double kObliquePitch = -45.0;
inline constexpr double kObliqueHeading = 90.0;
inline const Point kRoi{-50.0, 0.0};
inline constexpr double kHighAltitude = 55.0;
inline constexpr double kHighTrigger = 7.0;

/// Heading (deg clockwise from north) from `from` toward `to`, in the local ENU frame.
inline double bearing_deg(Point from, Point to) {
  const double h = std::atan2(to.x() - from.x(), to.y() - from.y()) * 180.0 / std::numbers::pi;
  return h < 0 ? h + 360.0 : h;
}

inline Plan attitude_plan() {
  Plan plan = two_uav_plan(true);
  const geodesy::LocalFrame frame(plan.origin);
  UavPlan& a = plan.uavs[0];
  a.parts.clear();
  // the orbit: 12 vertices, closed (the first repeated), counter-clockwise from the south
  std::vector<Point> orbit;
  for (int k = 0; k <= 12; ++k) {
    const double t = -std::numbers::pi / 2 + 2 * std::numbers::pi * (k % 12) / 12.0;
    orbit.emplace_back(kOrbitCentre.x() + kOrbitRadius * std::cos(t),
                       kOrbitCentre.y() + kOrbitRadius * std::sin(t));
  }
  PathPart o = make_part(frame, PartKind::Coverage, orbit);
  o.attitude.altitude_m = kOrbitAltitude;
  for (const Point& p : orbit) o.attitude.heading_deg.push_back(bearing_deg(p, kOrbitCentre));
  PathPart oblique = make_part(frame, PartKind::Coverage, {{-90, -40}, {-10, -40}});
  oblique.attitude.gimbal_pitch_deg = kObliquePitch;
  oblique.attitude.heading_deg = {kObliqueHeading, kObliqueHeading};
  PathPart roi = make_part(frame, PartKind::Coverage, {{-10, 40}, {-90, 40}});
  roi.attitude.roi = kRoi;
  PathPart high = make_part(frame, PartKind::Coverage, {{-90, 45}, {-10, 45}});
  high.attitude.altitude_m = kHighAltitude;
  high.attitude.trigger_distance_m = kHighTrigger;
  a.parts.push_back(make_part(frame, PartKind::Transit, {{-120, -60}, orbit.front()}));
  a.parts.push_back(o);
  a.parts.push_back(make_part(frame, PartKind::Transit, {orbit.back(), {-90, -40}}));
  a.parts.push_back(oblique);
  a.parts.push_back(make_part(frame, PartKind::Transit, {{-10, -40}, {-10, 40}}));
  a.parts.push_back(roi);
  a.parts.push_back(make_part(frame, PartKind::Transit, {{-90, 40}, {-90, 45}}));
  a.parts.push_back(high);
  a.parts.push_back(make_part(frame, PartKind::Transit, {{-10, 45}, {-120, -60}}));
  return plan;
}

}  // namespace uavcover::fixture
