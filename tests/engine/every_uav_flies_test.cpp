// Issue 26 (hard shapes): every UAV with a region flies it. A heterogeneous fleet of three on a 1.5 km x 1 km
// field, boustrophedon at a fixed 20 degrees: the overlay that keeps the UAVs' paths apart along their shared
// borders (the region less the others grown by a few centimetres) lost the fast UAV's whole region, and it
// got a region of 55 % of the field and no path, with no warning (PoC 45 %). Found by the wind session.
#include <gtest/gtest.h>

#include "evaluation/evaluate.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover {
namespace {

constexpr const char* kMission = R"({
  "area": {"type": "Polygon", "coordinates": [[[9.0, 45.0], [9.019056057703555, 45.0],
    [9.019056057703555, 45.00898311174991], [9.0, 45.00898311174991], [9.0, 45.0]]]},
  "camera": {"altitude_m": 40, "hfov_deg": 60, "overlap": 0.2},
  "uavs": [
    {"id": "fast", "speed_mps": 15, "endurance_min": 60, "camera": {"altitude_m": 40, "hfov_deg": 80, "overlap": 0.2},
     "start": [9.0, 44.9997305066475], "share": 0.5492786253981331},
    {"id": "medium", "speed_mps": 9, "endurance_min": 60, "start": [9.009528028851777, 44.9997305066475],
     "share": 0.33804377235590544},
    {"id": "slow", "speed_mps": 4, "endurance_min": 60, "camera": {"altitude_m": 40, "hfov_deg": 55, "overlap": 0.2},
     "start": [9.019056057703555, 44.9997305066475], "share": 0.11267760224596148}],
  "planner": "boustrophedon", "seed": 4, "planner_params": {"angle_deg": 20}})";

TEST(EveryUavFlies, AHeterogeneousFleetAtAFixedAngleSweepsEveryRegion) {
  for (const double angle : {20.0, 0.0, 45.0, 90.0}) {
    auto j = nlohmann::json::parse(kMission);
    j["planner_params"]["angle_deg"] = angle;
    const Plan p = plan(parse_mission(j.dump()));
    ASSERT_EQ(p.uavs.size(), 3u);
    for (const auto& u : p.uavs) {
      EXPECT_GT(u.share_actual, 0.05) << u.id << " at " << angle;
      EXPECT_GT(u.turns, 0) << u.id << " has a region and no path at " << angle << " deg";
      EXPECT_GT(u.coverage_length_m, 0.0) << u.id << " at " << angle;
    }
    const auto e = evaluation::evaluate_plan(p);
    EXPECT_GE(e.coverage.total.poc, 0.98) << "at " << angle << " deg";
  }
}

}  // namespace
}  // namespace uavcover
