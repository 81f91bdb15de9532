// A field crossed by 1 m hedges at 45 degrees (bench/web/pan-zoom.mjs's field at 300 m, hedges every
// 27 m, ds 4 m, strict, placement searched): the UAV's region (its cells clipped by the free area) was
// written as polygons plan.json's reader refused as self-intersecting, so the plan could not be
// exported. Seeds 3, 4, 6, 8 of 1..10 failed before (regions.cpp split no pinched ring, darp.cpp kept the
// clipping's slivers); seeds 2 and 8 fail now (a hole of the large piece, as Boost clips it, crosses
// itself; bench/results/darp-quality.md).
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>

#include "io/plan_io.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/plan_outputs.hpp"

namespace uavcover::test {
namespace {

std::string hedged_field(int seed) {
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
      {"uavs", {{{"id", "a"}, {"start", pos(-20, -20)}}}},
      {"planner", "darp"}}
      .dump();
}

class HedgedRegion : public ::testing::TestWithParam<int> {};

TEST_P(HedgedRegion, ThePlanFolderReadsBack) {
  const Plan plan = uavcover::plan(parse_mission(hedged_field(GetParam())));
  const auto dir = std::filesystem::temp_directory_path() /
                   ("uavcover_hedged_" + std::to_string(GetParam()) + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  usecases::OutputOptions oo;
  oo.evaluate = false;
  oo.images = false;
  io::write_artifacts(dir, usecases::plan_outputs(plan, oo).artifacts);
  Plan loaded;
  EXPECT_NO_THROW(loaded = io::load_plan_dir(dir));
  std::filesystem::remove_all(dir);
  ASSERT_EQ(loaded.uavs.size(), 1u);
  // the region read back is the planned one (slivers under 1 m^2 aside)
  EXPECT_NEAR(bg::area(loaded.uavs[0].region_local), bg::area(plan.uavs[0].region_local), 1.0);
  EXPECT_GT(bg::area(loaded.uavs[0].region_local), 0.0);
}

INSTANTIATE_TEST_SUITE_P(Seeds, HedgedRegion, ::testing::Values(3, 4));

}  // namespace
}  // namespace uavcover::test
