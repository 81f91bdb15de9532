// Altitude layers (issue 32, "transition_altitudes": "layers"): the conflict graph's colouring puts
// UAVs whose transits cross others' work on different transition altitudes, the others on one.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "geometry/geometry.hpp"
#include "uavcover/uavcover.hpp"
#include "waypoints/waypoints.hpp"

using namespace uavcover;
using nlohmann::json;

namespace {

// 2.5 km x 1.1 km; boustrophedon divides it into full-width strips from north to south, so a UAV
// starting at the west end of its own strip never flies over another's strip
json fleet(int n, const std::string& rule) {
  json uavs = json::array();
  for (int i = 0; i < n; ++i)
    uavs.push_back({{"id", "u" + std::to_string(i)}, {"start", {22.9001, 40.61 - 0.01 * (i + 0.5) / n}}});
  return {
      {"area",
       {{"type", "Polygon"},
        {"coordinates", {{{22.90, 40.60}, {22.93, 40.60}, {22.93, 40.61}, {22.90, 40.61}, {22.90, 40.60}}}}}},
      {"spacing_m", 30},
      {"uavs", uavs},
      {"planner", "boustrophedon"},
      {"transition_altitudes", rule},
      {"seed", 1}};
}

bool transit_crosses(const UavPlan& a, const UavPlan& b) {
  for (const auto& part : a.parts)
    if (part.kind == PartKind::Transit &&
        bg::intersects(bg::model::linestring<Point>(part.local.begin(), part.local.end()), b.region_local))
      return true;
  return false;
}

}  // namespace

TEST(AltitudeLayers, FiftyUavsWithDisjointWorkFitUnder120m) {
  const Plan p = plan(parse_mission(fleet(50, "layers").dump()));
  ASSERT_EQ(p.uavs.size(), 50u);
  const json& s = p.separation;
  ASSERT_TRUE(s.is_object());
  EXPECT_EQ(s.at("pairs").size(), 50u * 49u / 2u);
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    EXPECT_LE(p.uavs[i].transition_altitude_m, 120.0) << p.uavs[i].id;
    for (std::size_t j = 0; j < p.uavs.size(); ++j)
      if (i != j) {
        EXPECT_FALSE(transit_crosses(p.uavs[i], p.uavs[j])) << "the fleet's work is disjoint";
      }
  }
  // the export's rule (resolve_altitudes under the 120 m ceiling) accepts the fleet: every item <= 120 m
  for (std::size_t i = 0; i < p.uavs.size(); ++i)
    for (const auto& item : waypoints::mission_items(p, i)) EXPECT_LE(item.alt, 120.0 + 1e-9);
  // Hong's rule (one altitude per UAV) cannot: 50 UAVs 5 m apart from 60 m need 305 m
  const Plan hong = plan(parse_mission(fleet(50, "hong").dump()));
  EXPECT_THROW((void)waypoints::mission_items(hong, 0), InputError);
}

TEST(AltitudeLayers, CrossingPairGetsLayersAtLeast5mApart) {
  json j = fleet(2, "layers");
  // both take off south of the field: the one with the north strip flies over the other's
  j["uavs"][0]["start"] = {22.915, 40.5995};
  j["uavs"][1]["start"] = {22.9152, 40.5995};
  const Plan p = plan(parse_mission(j.dump()));
  ASSERT_TRUE(transit_crosses(p.uavs[0], p.uavs[1]) || transit_crosses(p.uavs[1], p.uavs[0]))
      << "the setup: one UAV's transit crosses the other's strip";
  const json& s = p.separation;
  EXPECT_EQ(s.at("layers"), 2);
  EXPECT_NE(s.at("layer")[0], s.at("layer")[1]);
  EXPECT_GE(std::fabs(p.uavs[0].transition_altitude_m - p.uavs[1].transition_altitude_m), 5.0);
  ASSERT_EQ(s.at("pairs").size(), 1u);
  EXPECT_GE(s.at("pairs")[0][2].get<double>(), 5.0);
  ASSERT_EQ(s.at("conflicts").size(), 1u);
  // the export flies them at those altitudes
  double top0 = 0, top1 = 0;
  for (const auto& it : waypoints::mission_items(p, 0)) top0 = std::max(top0, static_cast<double>(it.alt));
  for (const auto& it : waypoints::mission_items(p, 1)) top1 = std::max(top1, static_cast<double>(it.alt));
  EXPECT_GE(std::fabs(top0 - top1), 5.0);
}

TEST(AltitudeLayers, HongStillGivesOneAltitudePerUav) {
  const Plan p = plan(parse_mission(fleet(3, "hong").dump()));
  EXPECT_TRUE(p.separation.is_null());
  // Hong et al. 2021 §2.3 as the export applies it: base max(60, altitude + 20), 10 m per UAV
  const double base = std::max(60.0, p.mission.altitude_m + 20.0);
  for (std::size_t i = 0; i < p.uavs.size(); ++i)
    EXPECT_DOUBLE_EQ(p.uavs[i].transition_altitude_m, base + 10.0 * static_cast<double>(i));
  try {
    (void)parse_mission(fleet(2, "stacked").dump());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "transition_altitudes");
  }
}
