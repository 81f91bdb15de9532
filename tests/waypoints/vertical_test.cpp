#include "waypoints/vertical.hpp"

#include <gtest/gtest.h>

#include "export/fixture.hpp"
#include "geodesy/local_frame.hpp"

using namespace uavcover;
using namespace uavcover::waypoints;

namespace {

MissionItem at(const geodesy::LocalFrame& frame, Point p, float alt, std::uint16_t command = kNavWaypoint) {
  MissionItem it;
  it.command = command;
  const LonLat g = frame.to_wgs84(p);
  it.lon = g.lon;
  it.lat = g.lat;
  it.alt = alt;
  return it;
}

}  // namespace

// The fixture's Hong scheme on flat ground, no wind: take-off straight up to T, descend on the spot above
// the entry to 40 m, climb back on the spot after the loop, fly home at T and descend there. Every height
// change is vertical, so each costs its full climb or descent time.
TEST(VerticalTime, TheTransitionSchemeClimbsAndDescendsOnTheSpot) {
  const Plan plan = fixture::two_uav_plan();
  for (std::size_t u = 0; u < 2; ++u) {
    const double T = transition_altitude({}, u, plan.mission.altitude_m);
    const double d = T - plan.mission.altitude_m;
    const double expected = T / 3.0 + d / 1.5 + d / 3.0 + T / 1.5;  // defaults: 3 m/s up, 1.5 m/s down
    const auto items = mission_items(plan, u);
    EXPECT_NEAR(vertical_time_s(plan, u, items), expected, 1e-3) << "uav " << u;
    EXPECT_NEAR(uav_vertical_time_s(plan, u), expected, 1e-3) << "uav " << u;
    // the take-off and the final descent are where they belong
    const auto e = vertical_extra_s(plan, u, items);
    ASSERT_EQ(e.size(), items.size());
    EXPECT_NEAR(e.front(), T / 3.0, 1e-3);
    EXPECT_NEAR(e.back(), T / 1.5, 1e-3);
  }
  EXPECT_NEAR(uav_vertical_time_s(plan, 0), 80.0, 1e-3);   // T = 60 m
  EXPECT_NEAR(uav_vertical_time_s(plan, 1), 100.0, 1e-3);  // T = 70 m
}

TEST(VerticalTime, FollowsTheUavsOwnVerticalSpeeds) {
  Plan plan = fixture::two_uav_plan();
  plan.mission.uavs[0].climb_mps = 6.0;
  plan.mission.uavs[0].descent_mps = 3.0;
  EXPECT_NEAR(uav_vertical_time_s(plan, 0), 40.0, 1e-3);  // half of 80 s
  EXPECT_NEAR(uav_vertical_time_s(plan, 1), 100.0, 1e-3);
}

// A slanted leg costs only what its height change takes beyond its horizontal flight.
TEST(VerticalTime, ASlantedLegCountsOnlyTheClimbBeyondItsFlight) {
  Plan plan = fixture::two_uav_plan();
  const geodesy::LocalFrame frame(plan.origin);
  const Point home = frame.to_local(plan.mission.uavs[0].start_resolved);  // speed 5 m/s
  std::vector<MissionItem> items{at(frame, home, 10, kNavTakeoff),
                                 at(frame, {home.x() + 100, home.y()}, 50),   // 20 s flight, 13.3 s climb
                                 at(frame, {home.x() + 110, home.y()}, 110),  // 2 s flight, 20 s climb
                                 at(frame, {home.x() + 110, home.y()}, 80)};  // 20 s descent on the spot
  const auto e = vertical_extra_s(plan, 0, items);
  ASSERT_EQ(e.size(), 4u);
  EXPECT_NEAR(e[0], 10.0 / 3.0, 1e-3);
  EXPECT_NEAR(e[1], 0.0, 1e-9);
  EXPECT_NEAR(e[2], 20.0 - 2.0, 1e-2);
  EXPECT_NEAR(e[3], 20.0, 1e-3);
  // commands without a position cost nothing; RTL flies home at its height and descends there
  MissionItem speed;
  speed.command = kDoChangeSpeed;
  MissionItem rtl;
  rtl.command = kNavReturnToLaunch;
  items.push_back(speed);
  items.push_back(rtl);
  const auto f = vertical_extra_s(plan, 0, items);
  EXPECT_EQ(f[4], 0.0);
  EXPECT_NEAR(f[5], 80.0 / 1.5, 1e-3);
}
