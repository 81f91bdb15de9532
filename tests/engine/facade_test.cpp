// The facade plan(): progress reporting, transit legs, random starts, planner errors.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "engine/local_mission.hpp"
#include "geometry/geometry.hpp"
#include "support/shapes.hpp"
#include "uavcover/uavcover.hpp"

using namespace uavcover;
using nlohmann::json;

namespace {

json field_with_wall() {
  // 1.2 km x 0.8 km field, a long no-fly wall in the middle (x from 20 % to 100 % of the width)
  return json::parse(R"({
    "area": {"type": "Polygon", "coordinates": [[[22.90, 40.60], [22.914, 40.60], [22.914, 40.607], [22.90, 40.607]]]},
    "no_fly_zones": [{"type": "Polygon", "coordinates": [[[22.903, 40.6033], [22.915, 40.6033], [22.915, 40.6037], [22.903, 40.6037]]]}],
    "spacing_m": 30,
    "uavs": [{"id": "north", "start": [22.913, 40.6065]}, {"id": "south", "start": [22.913, 40.6005]}],
    "seed": 3
  })");
}

}  // namespace

TEST(Facade, ReportsProgressPerStageEndingAtDone) {
  const Mission m = parse_mission(field_with_wall().dump());
  std::vector<std::pair<std::string, double>> events;
  (void)plan(m, {},
             Context([&](std::string_view stage, double f) { events.emplace_back(std::string(stage), f); }));
  ASSERT_FALSE(events.empty());
  for (const auto& [stage, f] : events) {
    EXPECT_GE(f, 0.0) << stage;
    EXPECT_LE(f, 1.0) << stage;
  }
  EXPECT_EQ(events.back().first, "done");
  EXPECT_EQ(events.back().second, 1.0);
  // within a stage, fractions never go back
  for (std::size_t i = 1; i < events.size(); ++i)
    if (events[i].first == events[i - 1].first) {
      EXPECT_GE(events[i].second, events[i - 1].second) << events[i].first;
    }
}

TEST(Facade, TransitLegsGoAroundNoFlyZones) {
  auto j = field_with_wall();
  // both UAVs take off east of the field, level with the wall: flying straight in would cross it
  j["uavs"][0]["start"] = {22.9145, 40.6031};
  j["uavs"][1]["start"] = {22.9145, 40.6039};
  const Mission m = parse_mission(j.dump());
  const Plan p = plan(m);
  const auto lm = engine::to_local(m);
  int transits = 0;
  for (const auto& u : p.uavs) {
    ASSERT_FALSE(u.parts.empty());
    EXPECT_EQ(u.parts.front().kind, PartKind::Transit) << "starts outside the area fly in";
    for (const auto& part : u.parts) {
      transits += part.kind == PartKind::Transit;
      for (std::size_t i = 1; i < part.local.size(); ++i)
        EXPECT_FALSE(geometry::segment_enters(lm.no_fly, part.local[i - 1], part.local[i], 0.01))
            << u.id << " part kind " << static_cast<int>(part.kind);
      ASSERT_EQ(part.local.size(), part.wgs84.size());
    }
    // the flight ends where it started
    const auto& last = u.parts.back().local.back();
    const Point start = lm.frame.to_local(m.uavs[&u - &p.uavs[0]].start_resolved);
    EXPECT_LT(bg::distance(last, start), 1e-6);
  }
  EXPECT_GE(transits, 4);
}

TEST(Facade, RandomStartsAreInsideTheFreeAreaAndSeeded) {
  auto j = field_with_wall();
  j["uavs"] = 3;
  const Mission m = parse_mission(j.dump());
  const Plan a = plan(m), b = plan(m);
  PlanOptions other;
  other.seed = 99;
  const Plan c = plan(m, other);
  const auto lm = engine::to_local(m);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_TRUE(bg::within(lm.frame.to_local(a.mission.uavs[i].start_resolved), lm.free));
    EXPECT_EQ(a.mission.uavs[i].start_resolved, b.mission.uavs[i].start_resolved);
  }
  EXPECT_FALSE(a.mission.uavs[0].start_resolved == c.mission.uavs[0].start_resolved);
  EXPECT_EQ(c.mission.seed, 99u);
}

TEST(Facade, SpacingTooCoarseForAnyCellIsAnInputError) {
  // a 100 m square: in strict mode the 2x2 sub-cell centres of a 240 m mega-cell span 120 m and
  // cannot fit at any shift or rotation
  const json j = json::parse(R"({
    "area": {"type": "Polygon", "coordinates": [[[22.90, 40.60], [22.90118, 40.60], [22.90118, 40.6009], [22.90, 40.6009]]]},
    "spacing_m": 120, "uavs": 1, "mode": "strict"})");
  const Mission m = parse_mission(j.dump());
  try {
    plan(m);
    FAIL() << "planned a cell that cannot fit";
  } catch (const InputError& e) {
    EXPECT_FALSE(e.field().empty()) << e.what();
  }
}

namespace {

// Near 80 degrees a strict path follows the area as GeoJSON readers draw it (edges straight in lon/lat):
// every vertex and every edge's lon/lat midpoint lies inside the lon/lat area within 1 m.
TEST(PolarPaths, StrictPathsStayInsideTheLonLatArea) {
  Mission m;
  m.name = "polar";
  m.spacing_m = 100.0;
  const double lat0 = 80.0, lon0 = 10.0, dlat = 0.05, dlon = 0.3;  // about 5.5 x 5.8 km
  m.area.push_back(GeoPolygon{GeoRing{
      {lon0, lat0}, {lon0 + dlon, lat0}, {lon0 + dlon, lat0 + dlat}, {lon0, lat0 + dlat}, {lon0, lat0}}});
  for (int i = 0; i < 2; ++i) {
    Uav u;
    u.id = "u" + std::to_string(i);
    u.share = 0.5;
    m.uavs.push_back(u);
  }
  m.seed = 3;
  const Plan p = plan(m);
  // lon/lat as a plane, in metres at the area's latitude
  const double kx = 111320.0 * std::cos(lat0 * M_PI / 180), ky = 111320.0;
  auto flat = [&](const LonLat& ll) { return Point{(ll.lon - lon0) * kx, (ll.lat - lat0) * ky}; };
  Polygon area;
  for (const auto& ll : m.area[0][0]) area.outer().push_back(flat(ll));
  bg::correct(area);
  double worst = 0;
  for (const auto& u : p.uavs)
    for (const auto& part : u.parts) {
      if (part.kind != PartKind::Coverage) continue;
      for (std::size_t i = 0; i < part.wgs84.size(); ++i) {
        worst = std::max(worst, geometry::distance(MultiPolygon{area}, flat(part.wgs84[i])));
        if (i == 0) continue;
        const LonLat mid{(part.wgs84[i - 1].lon + part.wgs84[i].lon) / 2,
                         (part.wgs84[i - 1].lat + part.wgs84[i].lat) / 2};
        worst = std::max(worst, geometry::distance(MultiPolygon{area}, flat(mid)));
      }
    }
  EXPECT_LE(worst, 1.0);
}

}  // namespace

namespace {

// 10 000 small zones (a 100 x 100 lattice of 2 m squares in a 2 km field): DARP plans, and no path
// segment enters a zone.
TEST(ManyZones, TenThousandZonesPlanAndPathsAvoidThem) {
  Mission m = uavcover::testing::zone_lattice_mission(2000, 100, 20, 2, 40.0);
  for (int i = 0; i < 3; ++i) {
    Uav u;
    u.id = "u" + std::to_string(i);
    u.share = 1.0 / 3;
    // one battery each: this test is about planning and transits over 10 000 zones; battery sorties
    // (each sortie's return routed through the lattice) are tested in tests/sorties on 400 zones
    u.endurance_min = 10000.0;
    u.start = uavcover::testing::zone_lattice_point(0.5 + 20 * i, 0.5);
    m.uavs.push_back(u);
  }
  const Plan p = plan(m);
  const engine::LocalMission lm = engine::to_local(p.mission);
  ASSERT_EQ(lm.no_fly.size(), 10000u);
  const geometry::Router router(lm.no_fly);
  std::size_t segments = 0;
  for (const auto& u : p.uavs)
    for (const auto& part : u.parts)
      for (std::size_t i = 1; i < part.local.size(); ++i, ++segments)
        EXPECT_TRUE(router.clear(part.local[i - 1], part.local[i])) << u.id;
  EXPECT_GT(segments, 100u);
}

}  // namespace
