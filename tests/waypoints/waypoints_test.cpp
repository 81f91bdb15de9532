#include <gtest/gtest.h>

#include <filesystem>

#include "export/export.hpp"
#include "export/fixture.hpp"
#include "export/separation.hpp"
#include "waypoints/waypoints.hpp"

using namespace uavcover;
using namespace uavcover::exporting;
using namespace uavcover::waypoints;

namespace {

std::vector<MissionItem> with_role(const std::vector<MissionItem>& items, const std::string& role) {
  std::vector<MissionItem> out;
  for (const auto& it : items)
    if (it.role == role) out.push_back(it);
  return out;
}

}  // namespace

TEST(MissionItems, TransitionAltitudePerUav) {
  AltitudeOptions opt;
  opt.transition_base_m = 50;
  opt.transition_step_m = 7;
  EXPECT_DOUBLE_EQ(transition_altitude(opt, 0, 40), 50);
  EXPECT_DOUBLE_EQ(transition_altitude(opt, 3, 40), 71);
  // automatic base: 60 m, or 20 m above a higher mission altitude
  const AltitudeOptions automatic;
  EXPECT_DOUBLE_EQ(transition_altitude(automatic, 0, 40), 60);
  EXPECT_DOUBLE_EQ(transition_altitude(automatic, 1, 40), 70);
  EXPECT_DOUBLE_EQ(transition_altitude(automatic, 0, 100), 120);
}

TEST(MissionItems, SequenceFollowsHongTransitionScheme) {
  const Plan plan = fixture::two_uav_plan();
  for (std::size_t u = 0; u < 2; ++u) {
    const AltitudeOptions opt;
    const double T = transition_altitude(opt, u, plan.mission.altitude_m);
    const auto items = mission_items(plan, u, opt);
    ASSERT_GE(items.size(), 5u);
    const LonLat home = plan.mission.uavs[u].start_resolved;
    // take-off above home straight to the transition altitude
    EXPECT_EQ(items[0].command, kNavTakeoff);
    EXPECT_EQ(items[0].frame, kFrameGlobalRelativeAlt);
    EXPECT_DOUBLE_EQ(items[0].lat, home.lat);
    EXPECT_DOUBLE_EQ(items[0].lon, home.lon);
    EXPECT_FLOAT_EQ(items[0].alt, static_cast<float>(T));
    EXPECT_EQ(items[1].command, kDoChangeSpeed);
    EXPECT_FLOAT_EQ(items[1].param2, static_cast<float>(plan.mission.uavs[u].speed_mps));
    // coverage waypoints: the loop, in order, at mission altitude
    const auto cov = with_role(items, "coverage");
    const auto& loop = plan.uavs[u].parts[1].wgs84;
    ASSERT_EQ(cov.size(), loop.size());
    for (std::size_t k = 0; k < loop.size(); ++k) {
      EXPECT_DOUBLE_EQ(cov[k].lat, loop[k].lat);
      EXPECT_DOUBLE_EQ(cov[k].lon, loop[k].lon);
      EXPECT_FLOAT_EQ(cov[k].alt, 40.0f);
      EXPECT_EQ(cov[k].command, kNavWaypoint);
      EXPECT_EQ(cov[k].part, 1);
    }
    // every non-coverage waypoint flies at the transition altitude
    for (const auto& it : items) {
      if (it.command == kNavWaypoint && it.role != "coverage") {
        EXPECT_FLOAT_EQ(it.alt, static_cast<float>(T));
      }
    }
    // the item right before the first coverage waypoint is above the entry (descent is vertical)
    std::size_t first_cov = 0;
    while (items[first_cov].role != "coverage") ++first_cov;
    EXPECT_DOUBLE_EQ(items[first_cov - 1].lat, loop.front().lat);
    EXPECT_DOUBLE_EQ(items[first_cov - 1].lon, loop.front().lon);
    // after the loop: climb on the spot, then back home at T, then RTL
    std::size_t last_cov = items.size() - 1;
    while (items[last_cov].role != "coverage") --last_cov;
    EXPECT_EQ(items[last_cov + 1].role, "transition");
    EXPECT_FLOAT_EQ(items[last_cov + 1].alt, static_cast<float>(T));
    EXPECT_DOUBLE_EQ(items[last_cov + 1].lat, loop.back().lat);
    EXPECT_EQ(items.back().command, kNavReturnToLaunch);
    const auto& before = items[items.size() - 2];
    EXPECT_DOUBLE_EQ(before.lat, home.lat);
    EXPECT_DOUBLE_EQ(before.lon, home.lon);
    // no camera -> no trigger items
    EXPECT_TRUE(with_role(items, "camera").empty());
  }
}

TEST(MissionItems, CameraTriggersAtStartAndEndOfEachLeg) {
  const Plan plan = fixture::two_uav_plan(true);
  const auto items = mission_items(plan, 0);
  const float d = static_cast<float>(*plan.mission.trigger_distance_m);
  // every coverage leg: WP(start) TRIGG(d) WP(end) TRIGG(0); the loop of alpha has 6 legs
  std::vector<std::size_t> cams;
  for (std::size_t k = 0; k < items.size(); ++k)
    if (items[k].command == kDoSetCamTriggDist) cams.push_back(k);
  ASSERT_EQ(cams.size(), 12u);
  for (std::size_t c = 0; c < cams.size(); c += 2) {
    EXPECT_FLOAT_EQ(items[cams[c]].param1, d);
    EXPECT_FLOAT_EQ(items[cams[c + 1]].param1, 0.0f);
    // after the leg's first waypoint (or the previous leg's stop at that waypoint)
    EXPECT_TRUE(items[cams[c] - 1].role == "coverage" ||
                (items[cams[c] - 1].command == kDoSetCamTriggDist && items[cams[c] - 1].param1 == 0.0f));
    EXPECT_EQ(items[cams[c] + 1].role, "coverage");
    EXPECT_EQ(items[cams[c + 1] - 1].role, "coverage");
  }
  EXPECT_EQ(items[cams.back() + 1].role, "transition");
}

TEST(MissionItems, AUavWithItsOwnCameraTriggersAtItsOwnDistance) {
  Plan plan = fixture::two_uav_plan(true);
  const float mission_d = static_cast<float>(*plan.mission.trigger_distance_m);
  Camera own = *plan.mission.camera;
  own.capture = "distance";
  own.gimbal_pitch_deg = -60.0;
  plan.mission.uavs[1].camera = own;
  CameraGeometry g;
  g.trigger_distance_m = 0.5 * *plan.mission.trigger_distance_m;
  g.footprint_m = 0.5 * *plan.mission.footprint_m;
  g.along_track_footprint_m = 0.5 * *plan.mission.along_track_footprint_m;
  plan.mission.uavs[1].camera_geometry = g;
  auto distances = [](const std::vector<MissionItem>& items) {
    std::vector<float> d;
    for (const auto& it : items)
      if (it.command == kDoSetCamTriggDist && it.param1 > 0.0f) d.push_back(it.param1);
    return d;
  };
  for (const float d : distances(mission_items(plan, 0))) EXPECT_FLOAT_EQ(d, mission_d);
  const auto items = mission_items(plan, 1);
  const auto own_d = distances(items);
  ASSERT_FALSE(own_d.empty());
  for (const float d : own_d) EXPECT_FLOAT_EQ(d, static_cast<float>(g.trigger_distance_m));
  const auto gimbal = with_role(items, "gimbal");
  ASSERT_EQ(gimbal.size(), 1u);
  EXPECT_FLOAT_EQ(gimbal[0].param1, -60.0f);
}

TEST(MissionItems, LandInsteadOfRtl) {
  const Plan plan = fixture::two_uav_plan();
  AltitudeOptions opt;
  opt.land_instead_of_rtl = true;
  const auto items = mission_items(plan, 1, opt);
  EXPECT_EQ(items.back().command, kNavLand);
  EXPECT_DOUBLE_EQ(items.back().lat, plan.mission.uavs[1].start_resolved.lat);
  EXPECT_FLOAT_EQ(items.back().alt, 0.0f);
  for (const auto& it : items) EXPECT_NE(it.command, kNavReturnToLaunch);
}

TEST(MissionItems, BadIndexThrows) {
  const Plan plan = fixture::two_uav_plan();
  EXPECT_THROW(mission_items(plan, 2), std::out_of_range);
}

TEST(Separation, FixtureIsSafeAndUsesTheRegions) {
  const Plan plan = fixture::two_uav_plan();
  const RegionMap regions(plan);
  EXPECT_EQ(regions.owner({-50, -20}), 0);
  EXPECT_EQ(regions.owner({50, -20}), 1);
  EXPECT_EQ(regions.owner({70, -20}), -1);  // no-fly cell
  EXPECT_EQ(regions.owner({500, 0}), -1);   // outside every region
  EXPECT_TRUE(check_separation(plan, AltitudeOptions{}).empty());
}

TEST(Separation, SharedOrLowTransitionAltitudesAreReported) {
  const Plan plan = fixture::two_uav_plan();
  AltitudeOptions same;
  same.transition_step_m = 0;
  const auto p1 = check_separation(plan, same);
  ASSERT_EQ(p1.size(), 1u);
  EXPECT_NE(p1[0].find("share the transition altitude"), std::string::npos);
  AltitudeOptions low;
  low.transition_base_m = 30;  // below the 40 m mission altitude for UAV 0
  const auto p2 = check_separation(plan, low);
  ASSERT_FALSE(p2.empty());
  EXPECT_NE(p2[0].find("not above the mission altitude"), std::string::npos);
}

TEST(Separation, LowLegThroughAnotherRegionIsReported) {
  Plan plan = fixture::two_uav_plan();
  const geodesy::LocalFrame frame(plan.origin);
  // alpha also owns one cell inside bravo's half (col 7, row 3: x 40..60, y 10..30) and flies a second
  // loop there right after its first one, with no transit: the connecting leg stays at mission
  // altitude and crosses bravo's region
  MultiPolygon cell, rest;
  bg::read_wkt("MULTIPOLYGON(((40 10,40 30,60 30,60 10,40 10)))", cell);
  bg::correct(cell);
  bg::difference(plan.uavs[1].region_local, cell, rest);
  plan.uavs[1].region_local = rest;
  MultiPolygon alpha;
  bg::union_(plan.uavs[0].region_local, cell, alpha);
  plan.uavs[0].region_local = alpha;
  auto& parts = plan.uavs[0].parts;
  parts.insert(parts.begin() + 2, fixture::make_part(frame, PartKind::Coverage,
                                                     {{45, 15}, {55, 15}, {55, 25}, {45, 25}, {45, 15}}));
  ASSERT_EQ(RegionMap(plan).owner({50, 20}), 0);
  const auto problems = check_separation(plan, AltitudeOptions{});
  ASSERT_FALSE(problems.empty());
  EXPECT_NE(problems[0].find("enters the region of uav 'bravo'"), std::string::npos);
  // with a transit part between the loops the leg flies at the transition altitude: no problem
  parts.insert(parts.begin() + 2, fixture::make_part(frame, PartKind::Transit, {{-90, -40}, {45, 15}}));
  EXPECT_TRUE(check_separation(plan, AltitudeOptions{}).empty());
}

TEST(Separation, FallsBackToLoopsWithoutRegions) {
  Plan plan = fixture::two_uav_plan();
  for (auto& u : plan.uavs) u.region_local.clear();
  const RegionMap regions(plan);
  EXPECT_EQ(regions.owner({-30, -20}), 0);
  EXPECT_EQ(regions.owner({70, 20}), 1);
  EXPECT_EQ(regions.owner({0, 45}), -1);
}

TEST(Separation, HomeInsideAnotherRegionIsReported) {
  Plan plan = fixture::two_uav_plan();
  const geodesy::LocalFrame frame(plan.origin);
  // bravo takes off inside alpha's half
  plan.mission.uavs[1].start_resolved = frame.to_wgs84({-30, 20});
  // (around the no-fly zone at x 60..80, y -30..-10)
  plan.uavs[1].parts.front() = fixture::make_part(frame, PartKind::Transit, {{-30, 20}, {90, 20}, {90, -40}});
  plan.uavs[1].parts.back() = fixture::make_part(frame, PartKind::Transit, {{90, -40}, {90, 20}, {-30, 20}});
  EXPECT_TRUE(check_separation(plan, AltitudeOptions{}).empty());  // a warning, not a blocking problem
  EXPECT_TRUE(separation_warnings(fixture::two_uav_plan()).empty());
  const auto problems = separation_warnings(plan);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(
      problems[0].find("take-off and landing at home cross the mission altitude inside the region of uav "
                       "'alpha'"),
      std::string::npos);
  // export_plan still writes the files and hands the warning back
  std::vector<std::string> warnings;
  ExportOptions eo;
  eo.warnings = &warnings;
  const auto dir =
      std::filesystem::temp_directory_path() / ("uavcover_sep_warn_" + std::to_string(::getpid()));
  EXPECT_EQ(fixture::export_to(plan, {"csv"}, dir, eo).size(), 2u);
  EXPECT_EQ(warnings, problems);
  std::filesystem::remove_all(dir);
}

TEST(MissionItems, UavWithoutCellsTakesOffAndReturns) {
  Plan plan = fixture::two_uav_plan();
  plan.uavs[1].parts.clear();
  const auto items = mission_items(plan, 1);
  ASSERT_EQ(items.size(), 3u);
  EXPECT_EQ(items[0].command, kNavTakeoff);
  EXPECT_EQ(items[1].command, kDoChangeSpeed);
  EXPECT_EQ(items[2].command, kNavReturnToLaunch);
  EXPECT_TRUE(check_separation(plan, AltitudeOptions{}).empty());
}
