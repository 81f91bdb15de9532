// The waypoint model reads PathPart::attitude (issue 30, docs/exports.md "Attitude"): a part's own height
// for every vertex, a heading per vertex (NAV_WAYPOINT param4; MAV_CMD_CONDITION_YAW for ArduPilot), a
// gimbal pitch set before the part and set back after it, a region of interest on and off around it, and
// the part's own trigger distance.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "export/attitude_fixture.hpp"
#include "geodesy/local_frame.hpp"
#include "waypoints/ardupilot.hpp"
#include "waypoints/waypoints.hpp"

using namespace uavcover;
using namespace uavcover::waypoints;

namespace {

/// Difference of two headings, in [0, 180].
double heading_error(double a, double b) { return std::abs(std::remainder(a - b, 360.0)); }

/// Index of the first item of part `part` (a positioned item), or items.size().
std::size_t first_of_part(const std::vector<MissionItem>& items, int part) {
  for (std::size_t k = 0; k < items.size(); ++k)
    if (items[k].part == part) return k;
  return items.size();
}
std::size_t last_of_part(const std::vector<MissionItem>& items, int part) {
  std::size_t last = items.size();
  for (std::size_t k = 0; k < items.size(); ++k)
    if (items[k].part == part) last = k;
  return last;
}

}  // namespace

TEST(WaypointAttitude, OrbitFliesAtItsOwnHeightFacingTheCentre) {
  const Plan plan = fixture::attitude_plan();
  const geodesy::LocalFrame frame(plan.origin);
  const auto items = mission_items(plan, 0);
  int seen = 0;
  for (const auto& it : items) {
    if (it.part != 1 || it.command != kNavWaypoint) continue;
    ++seen;
    const Point p = frame.to_local({it.lon, it.lat});
    // on the orbit, at its own altitude (not the mission's 40 m), looking at the centre
    EXPECT_NEAR(std::hypot(p.x() - fixture::kOrbitCentre.x(), p.y() - fixture::kOrbitCentre.y()),
                fixture::kOrbitRadius, 1e-3);
    EXPECT_FLOAT_EQ(it.alt, fixture::kOrbitAltitude);
    ASSERT_FALSE(std::isnan(it.param4));
    EXPECT_LT(heading_error(it.param4, fixture::bearing_deg(p, fixture::kOrbitCentre)), 0.01) << it.role;
  }
  EXPECT_GE(seen, 13);  // every vertex (and the capture points between, if any)
  // no CONDITION_YAW unless asked for (PX4 refuses it in a mission)
  for (const auto& it : items) EXPECT_NE(it.command, kConditionYaw);
}

TEST(WaypointAttitude, ConditionYawPrecedesEveryWaypointWithAHeadingForArduPilot) {
  const Plan plan = fixture::attitude_plan();
  const auto items = ardupilot_mission_items(plan, 0);
  int yaws = 0, headed = 0;
  for (std::size_t k = 0; k < items.size(); ++k) {
    const MissionItem& it = items[k];
    if (it.command == kConditionYaw) {
      ++yaws;
      // param1 the absolute heading of the waypoint right after it; param4 0 = absolute, param3 0 = short way
      ASSERT_LT(k + 1, items.size());
      EXPECT_EQ(items[k + 1].command, kNavWaypoint);
      EXPECT_FLOAT_EQ(it.param1, items[k + 1].param4);
      EXPECT_EQ(it.param3, 0.0f);
      EXPECT_EQ(it.param4, 0.0f);
      EXPECT_GE(it.param1, 0.0f);
      EXPECT_LT(it.param1, 360.0f);
    }
    if (it.command == kNavWaypoint && !std::isnan(it.param4)) ++headed;
  }
  EXPECT_EQ(yaws, headed);
  EXPECT_GE(yaws, 13 + 2);  // the orbit's vertices and the oblique pass's two
}

TEST(WaypointAttitude, GimbalIsSetForTheObliquePassAndSetBackAfter) {
  const Plan plan = fixture::attitude_plan();
  const auto items = mission_items(plan, 0);
  const std::size_t first = first_of_part(items, 3), last = last_of_part(items, 3);
  ASSERT_LT(first, items.size());
  // the pitch of the pass between the last positioned item before it and its first waypoint
  std::optional<float> before;
  for (std::size_t k = first; k-- > 0 && items[k].command != kNavWaypoint;)
    if (items[k].command == kDoGimbalManagerPitchyaw) before = items[k].param1;
  ASSERT_TRUE(before.has_value());
  EXPECT_FLOAT_EQ(*before, fixture::kObliquePitch);
  // the fixed heading on every waypoint of the pass
  for (std::size_t k = first; k <= last; ++k)
    if (items[k].command == kNavWaypoint) {
      EXPECT_FLOAT_EQ(items[k].param4, fixture::kObliqueHeading);
    }
  // the camera's own pitch (-90) again after its last waypoint, before the next positioned item
  std::optional<float> after;
  for (std::size_t k = last + 1; k < items.size() && items[k].command != kNavWaypoint; ++k)
    if (items[k].command == kDoGimbalManagerPitchyaw) after = items[k].param1;
  ASSERT_TRUE(after.has_value());
  EXPECT_FLOAT_EQ(*after, plan.mission.camera->gimbal_pitch_deg);
  // no gimbal item inside the pass
  for (std::size_t k = first; k <= last; ++k) EXPECT_NE(items[k].command, kDoGimbalManagerPitchyaw);
}

TEST(WaypointAttitude, RoiIsSetBeforeThePartAndClearedAfter) {
  const Plan plan = fixture::attitude_plan();
  const geodesy::LocalFrame frame(plan.origin);
  const auto items = mission_items(plan, 0);
  const std::size_t first = first_of_part(items, 5), last = last_of_part(items, 5);
  ASSERT_LT(first, items.size());
  std::optional<MissionItem> on, off;
  for (std::size_t k = first; k-- > 0 && items[k].command != kNavWaypoint;)
    if (items[k].command == kDoSetRoi) on = items[k];
  for (std::size_t k = last + 1; k < items.size() && items[k].command != kNavWaypoint; ++k)
    if (items[k].command == kDoSetRoi) off = items[k];
  ASSERT_TRUE(on && off);
  EXPECT_EQ(on->param1, 3.0f);  // MAV_ROI_LOCATION
  EXPECT_EQ(on->frame, kFrameGlobalRelativeAlt);
  const Point r = frame.to_local({on->lon, on->lat});
  EXPECT_NEAR(r.x(), fixture::kRoi.x(), 1e-3);
  EXPECT_NEAR(r.y(), fixture::kRoi.y(), 1e-3);
  EXPECT_FLOAT_EQ(on->alt, plan.mission.altitude_m);  // level with the part
  EXPECT_EQ(on->param4, 0.0f);                        // never NaN outside a NAV command's param4
  EXPECT_EQ(off->param1, 0.0f);                       // MAV_ROI_NONE at no location
  EXPECT_EQ(off->lat, 0.0);
  EXPECT_EQ(off->lon, 0.0);
  // exactly one on and one off in the whole mission
  int rois = 0;
  for (const auto& it : items) rois += it.command == kDoSetRoi ? 1 : 0;
  EXPECT_EQ(rois, 2);
}

TEST(WaypointAttitude, PartWithItsOwnAltitudeAndTriggerDistance) {
  const Plan plan = fixture::attitude_plan();
  const auto items = mission_items(plan, 0);
  const std::size_t first = first_of_part(items, 7), last = last_of_part(items, 7);
  ASSERT_LT(first, items.size());
  int wps = 0, triggers = 0;
  for (std::size_t k = first; k <= last + 1 && k < items.size(); ++k) {
    if (items[k].command == kNavWaypoint && items[k].part == 7) {
      ++wps;
      EXPECT_FLOAT_EQ(items[k].alt, fixture::kHighAltitude);
      EXPECT_TRUE(std::isnan(items[k].param4));  // no heading of its own: the vehicle's heading mode
    }
    if (items[k].command == kDoSetCamTriggDist && items[k].param1 > 0) {
      ++triggers;
      EXPECT_FLOAT_EQ(items[k].param1, fixture::kHighTrigger);
    }
  }
  EXPECT_EQ(wps, 2);
  EXPECT_EQ(triggers, 1);
  // the other parts shoot at the mission camera's distance
  for (std::size_t k = 0; k < first; ++k)
    if (items[k].command == kDoSetCamTriggDist && items[k].param1 > 0) {
      EXPECT_FLOAT_EQ(items[k].param1, static_cast<float>(*plan.mission.trigger_distance_m));
    }
}

TEST(WaypointAttitude, EmptyAttitudeChangesNothing) {
  // bravo's parts carry no attitude: its items are those of the plan without any attitude
  const Plan with = fixture::attitude_plan();
  const Plan without = fixture::two_uav_plan(true);
  const auto a = mission_items(with, 1), b = mission_items(without, 1);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].command, b[k].command) << k;
    EXPECT_EQ(a[k].alt, b[k].alt) << k;
    EXPECT_TRUE(std::isnan(a[k].param4) == std::isnan(b[k].param4)) << k;
    EXPECT_EQ(a[k].role, b[k].role) << k;
  }
  // alpha with its attitude cleared flies the defaults: mission altitude, no heading, no ROI or yaw items
  Plan cleared = with;
  for (auto& part : cleared.uavs[0].parts) part.attitude = {};
  for (const auto& it : mission_items(cleared, 0)) {
    EXPECT_NE(it.command, kDoSetRoi);
    EXPECT_NE(it.command, kConditionYaw);
    if (it.role == "coverage") {
      EXPECT_FLOAT_EQ(it.alt, cleared.mission.altitude_m);
      EXPECT_TRUE(std::isnan(it.param4));
    }
  }
}
