// `uavcover evaluate` as a use case (src/usecases/evaluate_paths.cpp): GeoJSON paths matched to the
// mission's UAVs and swept with each UAV's own footprint.
#include "usecases/evaluate_paths.hpp"
#include "codec/plan_codec.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "evaluation/evaluate.hpp"
#include "io/plan_io.hpp"
#include "support/examples.hpp"

namespace uavcover {
namespace {

TEST(EvaluatePaths, EachFlightIsSweptWithItsUavsOwnCamera) {
  // the olive grove's own paths as GeoJSON, evaluated against the mission, then against the same
  // mission where bravo's own camera sees 25 m across (the mission's: 74.5 m)
  const Plan& p = testing::olive_grove_plan();
  const Plan own = testing::olive_grove_with_own_camera(1, 25.0);
  const std::string geojson = codec::paths_geojson(p).dump();
  const auto before = usecases::evaluate_paths(p.mission, geojson, {});
  const auto after = usecases::evaluate_paths(own.mission, geojson, {});
  ASSERT_EQ(after.evaluation.coverage.uavs.size(), 3u);
  ASSERT_EQ(after.evaluation.uav_ids[1], "bravo");
  const auto& b = after.evaluation.coverage.uavs;
  const auto& a = before.evaluation.coverage.uavs;
  EXPECT_NEAR(b[1].footprint_m, 25.0, 1e-9);
  EXPECT_NEAR(b[0].footprint_m, evaluation::footprint_for(p.mission), 1e-9);
  EXPECT_EQ(b[0].stats.poc, a[0].stats.poc) << "alpha is unchanged";
  EXPECT_LT(b[1].stats.poc, 0.8 * a[1].stats.poc);
  EXPECT_LT(after.evaluation.coverage.total.poc, before.evaluation.coverage.total.poc);
  // the same figures as the evaluator gives the plan itself with bravo's camera
  const auto planned = evaluation::evaluate_plan(own);
  EXPECT_NEAR(b[1].stats.poc, planned.coverage.uavs[1].stats.poc, 0.01);
  EXPECT_EQ(evaluation::to_json(after.evaluation)["coverage"]["uavs"][1]["footprint_m"].get<double>(),
            b[1].footprint_m);
  // --footprint sweeps one width for every flight
  evaluation::EvaluateOptions one;
  one.coverage.footprint_m = evaluation::footprint_for(p.mission);
  const auto overridden = usecases::evaluate_paths(own.mission, geojson, one);
  EXPECT_EQ(overridden.evaluation.coverage.uavs[1].footprint_m, one.coverage.footprint_m);
  EXPECT_EQ(overridden.evaluation.coverage.total.poc, before.evaluation.coverage.total.poc);
}

TEST(EvaluatePaths, FlightsTakeTheCameraOfTheUavTheyAreMatchedTo) {
  // the paths name their UAVs: listed in another order, bravo's flight still gets bravo's camera
  const Plan own = testing::olive_grove_with_own_camera(1, 25.0);
  nlohmann::json g = codec::paths_geojson(own);
  std::reverse(g["features"].begin(), g["features"].end());
  const auto r = usecases::evaluate_paths(own.mission, g.dump(), {});
  bool seen = false;
  for (std::size_t i = 0; i < r.evaluation.uav_ids.size(); ++i) {
    const bool bravo = r.evaluation.uav_ids[i] == "bravo";
    seen = seen || bravo;
    EXPECT_NEAR(r.evaluation.coverage.uavs[i].footprint_m,
                bravo ? 25.0 : evaluation::footprint_for(own.mission), 1e-9)
        << r.evaluation.uav_ids[i];
  }
  EXPECT_TRUE(seen);
}

}  // namespace
}  // namespace uavcover
