// A field crossed by 1 m hedges at 45 degrees (bench/web/pan-zoom.mjs's field at 300 m, hedges every
// 27 m, ds 4 m, strict, placement searched): the UAV's region (its cells clipped by the free area) was
// written as polygons plan.json's reader refused as self-intersecting, so the plan could not be
// exported. With the clipping on doubles, seeds 3, 4, 6, 8 of 1..10 failed at first; with pinched rings
// split and slivers dropped, seeds 2 and 8 (one UAV) and 2, 3, 8, 9 (three UAVs) still did, a hole
// crossing itself as Boost clipped it. The clipping is now on integer millimetres
// (geometry::intersection_mm; bench/results/darp-quality.md).
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>

#include "evaluation/evaluate.hpp"
#include "geodesy/local_frame.hpp"
#include "geometry/millimetres.hpp"
#include "io/plan_io.hpp"
#include "support/plan_folder.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/plan_outputs.hpp"

namespace uavcover::test {
namespace {

std::string hedged_field(int seed, int uavs = 1) {
  const double W = 300, gap = 27, m = 6, half = std::sqrt(0.5), lat0 = 40.6, lon0 = 22.9;
  auto pos = [&](double x, double y) {
    const double lon = lon0 + x / (111320 * std::cos(lat0 * std::numbers::pi / 180)), lat = lat0 + y / 110540;
    return nlohmann::json::array({std::round(lon * 1e7) / 1e7, std::round(lat * 1e7) / 1e7});
  };
  nlohmann::json zones = nlohmann::json::array();
  for (double c = -W + gap; c < W - gap; c += gap) {
    const double y0 = std::max(m, m - c), y1 = std::min(W - m, W - m - c);
    if (y1 - y0 <= 20) continue;
    zones.push_back({{"type", "Polygon"},
                     {"coordinates",
                      {{pos(y0 + c - half, y0), pos(y0 + c + half, y0), pos(y1 + c + half, y1),
                        pos(y1 + c - half, y1), pos(y0 + c - half, y0)}}}});
  }
  return nlohmann::json{
      {"name", "hedged field"},
      {"area",
       {{"type", "Polygon"}, {"coordinates", {{pos(0, 0), pos(W, 0), pos(W, W), pos(0, W), pos(0, 0)}}}}},
      {"no_fly_zones", zones},
      {"spacing_m", 4},
      {"mode", "strict"},
      {"seed", seed},
      {"uavs", uavs == 1 ? nlohmann::json{{{"id", "a"}, {"start", pos(-20, -20)}}}
                         : nlohmann::json{{{"id", "a"}, {"start", pos(-20, -20)}},
                                          {{"id", "b"}, {"start", pos(320, -20)}},
                                          {{"id", "c"}, {"start", pos(320, 320)}}}},
      {"planner", "darp"}}
      .dump();
}

/// Plans the hedged field, writes the plan folder and reads it back; checks the regions read back are
/// the planned ones, valid, in the free area and (several UAVs) exclusive.
void plan_write_read(int seed, int uavs) {
  const Plan plan = uavcover::plan(parse_mission(hedged_field(seed, uavs)));
  Plan loaded;
  EXPECT_NO_THROW(loaded = uavcover::testing::write_and_read_plan_folder(
                      plan, "uavcover_hedged_" + std::to_string(seed) + "_" + std::to_string(uavs)));
  ASSERT_EQ(loaded.uavs.size(), static_cast<std::size_t>(uavs));
  const MultiPolygon free = evaluation::free_area(plan.mission, geodesy::LocalFrame(plan.origin));
  for (int i = 0; i < uavs; ++i) {
    SCOPED_TRACE(::testing::Message() << "uav " << i);
    const MultiPolygon& region = loaded.uavs[static_cast<std::size_t>(i)].region_local;
    // the region read back is the planned one
    EXPECT_NEAR(bg::area(region), bg::area(plan.uavs[static_cast<std::size_t>(i)].region_local), 1.0);
    EXPECT_GT(bg::area(region), 0.0);
    for (const Polygon& piece : plan.uavs[static_cast<std::size_t>(i)].region_local) {
      std::string why;
      EXPECT_TRUE(bg::is_valid(piece, why)) << why;
    }
    // out of the hedges but for the millimetre rounding (on millimetres: Boost's overlay on doubles of
    // these pieces cannot be trusted)
    geometry::MmMultiPolygon outside;
    bg::difference(geometry::to_mm(region), geometry::to_mm(free), outside);
    EXPECT_LT(static_cast<double>(bg::area(outside)) / 1e6, 0.001 * bg::perimeter(region));
    for (int k = i + 1; k < uavs; ++k) {
      // exclusive: where a hedge crosses the cell edge two regions share, each clip rounds the crossing
      // to millimetres on its own, so they may overlap by slivers under a millimetre wide
      const MultiPolygon both =
          geometry::intersection_mm(region, loaded.uavs[static_cast<std::size_t>(k)].region_local);
      EXPECT_LT(bg::area(both), 0.001 * bg::perimeter(region)) << "uav " << k;
    }
  }
}

class HedgedRegion : public ::testing::TestWithParam<int> {};

TEST_P(HedgedRegion, ThePlanFolderReadsBack) { plan_write_read(GetParam(), 1); }

INSTANTIATE_TEST_SUITE_P(Seeds, HedgedRegion, ::testing::Range(1, 11));

class HedgedRegions : public ::testing::TestWithParam<int> {};

TEST_P(HedgedRegions, ThreeUavsReadBackExclusive) { plan_write_read(GetParam(), 3); }

// the seeds whose three regions failed with the clipping on doubles (one UAV passed)
INSTANTIATE_TEST_SUITE_P(Seeds, HedgedRegions, ::testing::Values(3, 9));

}  // namespace
}  // namespace uavcover::test
