// Refly the gaps (issue 32): a flight whose UAV failed half way leaves a gap; the refly plans exactly
// what is left, and the flight plus the refly cover the field.
#include "usecases/refly.hpp"

#include <gtest/gtest.h>

#include <boost/geometry.hpp>
#include <filesystem>

#include "support/files.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/rectangle_plan.hpp"

namespace uavcover {
namespace {

namespace bg = boost::geometry;
using flight::Track;

using testing::rectangle_plan;

/// A UAV's flight as its log would record it: its path's vertices, coverage at the mission's altitude,
/// transit at its transition altitude; cut after `fraction` of its coverage waypoints (a failure).
Track track_of(const Plan& p, const UavPlan& u, double fraction = 1.0) {
  Track t{u.id, {}};
  std::size_t total = 0;
  for (const auto& part : u.parts)
    if (part.kind == PartKind::Coverage) total += part.wgs84.size();
  const auto keep = static_cast<std::size_t>(fraction * static_cast<double>(total));
  std::size_t seen = 0;
  for (const auto& part : u.parts) {
    const bool coverage = part.kind == PartKind::Coverage;
    const double alt = coverage ? p.mission.altitude_m : u.transition_altitude_m;
    for (const auto& v : part.wgs84) {
      if (coverage && seen++ >= keep) return t;
      t.second.push_back({v.lon, v.lat, alt});
    }
  }
  return t;
}

TEST(Refly, AFailedUavsGapIsPlannedAndTheFlightWithTheReflyCoversTheField) {
  const Plan p = rectangle_plan();
  ASSERT_EQ(p.uavs.size(), 3u);
  ASSERT_GT(p.mission.uavs[1].start_resolved.lon, -180.0);
  std::vector<Track> flown = {track_of(p, p.uavs[0]), track_of(p, p.uavs[1], 0.4), track_of(p, p.uavs[2])};
  const auto gaps = usecases::coverage_gaps(p, flown);
  // green flew 40 % of its coverage: about 60 % of its third of the field is left
  EXPECT_LT(gaps.flown_poc, 0.85);
  EXPECT_GT(gaps.planned_poc, 0.99);
  ASSERT_FALSE(gaps.local.empty());
  const double green_region = bg::area(p.uavs[1].region_local);
  EXPECT_GT(gaps.area_m2, 0.4 * green_region);
  EXPECT_LT(gaps.area_m2, 0.9 * green_region + 0.5 * p.mission.spacing_m * 200.0);
  // the gaps lie in the failed UAV's region (grown by half the spacing), not in the others'
  MultiPolygon outside;
  bg::difference(gaps.local, p.uavs[1].region_local, outside);
  EXPECT_LT(bg::area(outside), p.mission.spacing_m * 200.0) << "gap outside green's region";

  // the refly, flown by red and yellow only
  const Mission refly = usecases::refly_mission(p, gaps, {"red", "yellow"});
  ASSERT_EQ(refly.uavs.size(), 2u);
  EXPECT_EQ(refly.uavs[0].id, "red");
  EXPECT_EQ(refly.uavs[0].start_resolved, p.mission.uavs[0].start_resolved) << "from the start it used";
  EXPECT_NEAR(refly.uavs[0].share + refly.uavs[1].share, 1.0, 1e-9);
  EXPECT_NE(refly.name.find("(refly)"), std::string::npos);
  const Plan second = plan(refly);
  // the flight plus the refly's paths, flown as planned, cover the field
  std::vector<Track> both = flown;
  for (const auto& u : second.uavs) both.push_back(track_of(second, u));
  const auto after = usecases::coverage_gaps(p, both);
  EXPECT_GE(after.flown_poc, 0.99) << "flown + refly";
  EXPECT_THROW(usecases::refly_mission(p, after, {}), InputError) << "nothing left: refused";
}

TEST(Refly, ACompleteFlightLeavesNothingToFly) {
  const Plan p = rectangle_plan();
  std::vector<Track> flown;
  for (const auto& u : p.uavs) flown.push_back(track_of(p, u));
  const auto gaps = usecases::coverage_gaps(p, flown);
  EXPECT_TRUE(gaps.local.empty()) << gaps.area_m2 << " m^2 left after a whole flight";
  try {
    (void)usecases::refly_mission(p, gaps, {});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "area");
  }
}

TEST(Refly, UnknownOrRepeatedUavsAreRefused) {
  const Plan p = rectangle_plan();
  const auto gaps = usecases::coverage_gaps(p, {track_of(p, p.uavs[0], 0.5)});
  for (const std::vector<std::string>& ids :
       {std::vector<std::string>{"blue"}, std::vector<std::string>{"red", "red"}}) {
    try {
      (void)usecases::refly_mission(p, gaps, ids);
      FAIL() << "expected InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "uavs");
    }
  }
}

TEST(Refly, FlightLogsParseFromTheServersGeoJsonAndCsv) {
  const std::string geojson = R"({"type":"FeatureCollection","features":[
    {"type":"Feature","geometry":{"type":"LineString","coordinates":[[8.5,47.3,30],[8.501,47.3,30.5]]},
     "properties":{"uav":"red","kind":"track","positions":2}},
    {"type":"Feature","geometry":null,"properties":{"uav":"red","kind":"event"}}]})";
  const auto g = usecases::parse_flight_log(geojson, "--flown");
  ASSERT_EQ(g.size(), 1u);
  EXPECT_EQ(g[0].first, "red");
  ASSERT_EQ(g[0].second.size(), 2u);
  EXPECT_DOUBLE_EQ(g[0].second[1][2], 30.5);
  const std::string csv =
      "seq,time,uav,kind,lon,lat,alt_m,speed_mps,battery_pct,data\n"
      "1,2026-12-02T10:00:00.000Z,red,telemetry,8.5,47.3,30,3,99,\"{\"\"lon\"\":8.5}\"\n"
      "2,2026-12-02T10:00:01.000Z,red,mission,,,,,,\"{}\"\n"
      "3,2026-12-02T10:00:02.000Z,green,telemetry,8.6,47.4,31,3,98,\"{}\"\n";
  const auto c = usecases::parse_flight_log(csv, "--flown");
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[1].first, "green");
  EXPECT_DOUBLE_EQ(c[1].second[0][1], 47.4);
  for (const std::string& bad :
       {std::string("{\"type\":\"Feature\"}"), std::string("uav,lon\nred,1\n"),
        std::string("seq,uav,kind,lon,lat,alt_m\n1,red,telemetry,east,47,30\n"), std::string("")}) {
    try {
      (void)usecases::parse_flight_log(bad, "--flown");
      FAIL() << "accepted: " << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.field()).rfind("--flown", 0), 0u) << e.field();
    }
  }
}

}  // namespace
}  // namespace uavcover
