// `uavcover evaluate` as a use case (src/usecases/evaluate_paths.cpp): GeoJSON paths matched to the
// mission's UAVs and swept with each UAV's own footprint.
#include "usecases/evaluate_paths.hpp"
#include "codec/plan_codec.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "evaluation/evaluate.hpp"
#include "geodesy/local_frame.hpp"
#include "io/plan_io.hpp"
#include "support/examples.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"

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

nlohmann::json at(double east_m, double north_m) {
  static const geodesy::LocalFrame f(LonLat{10.0, 45.0});
  const LonLat p = f.to_wgs84(Point(east_m, north_m));
  return {p.lon, p.lat};
}

nlohmann::json ring(const std::vector<std::pair<double, double>>& pts) {
  nlohmann::json r = nlohmann::json::array();
  for (auto [e, n] : pts) r.push_back(at(e, n));
  r.push_back(r.front());
  return {{"type", "Polygon"}, {"coordinates", {r}}};
}

TEST(EvaluatePaths, APlansOwnPathsKeepTheirObliquesAndFacadeFigures) {
  // issue 30: a plan folder's paths.geojson carries each part's attitude; evaluated as paths it must
  // give the plan's own oblique and facade figures (it had swept every line as a nadir pass at the
  // mission's altitude)
  const nlohmann::json oblique = {
      {"name", "oblique"},
      {"area", ring({{0, 0}, {300, 0}, {300, 300}, {0, 300}})},
      {"camera", {{"altitude_m", 100}, {"hfov_deg", 60}, {"vfov_deg", 45}, {"overlap", 1.4}}},
      {"pattern", {{"oblique", {{"gimbal_pitch_deg", -45}, {"directions", 4}, {"nadir", true}}}}},
      {"uavs", {{{"id", "u1"}, {"start", at(0, -50)}}}},
      {"planner", "boustrophedon"},
      {"planner_params", {{"angle_deg", 0}}},
      {"seed", 3}};
  const Plan p = plan(parse_mission(oblique.dump()));
  const auto planned = evaluation::evaluate_plan(p);
  const auto paths = usecases::evaluate_paths(p.mission, codec::paths_geojson(p).dump(), {});
  const auto& got = paths.evaluation.coverage;
  ASSERT_EQ(planned.coverage.oblique.size(), 4u);
  ASSERT_EQ(got.oblique.size(), 4u);
  ASSERT_TRUE(got.nadir_poc.has_value());
  EXPECT_NEAR(*got.nadir_poc, *planned.coverage.nadir_poc, 0.005);
  for (std::size_t d = 0; d < 4; ++d) {
    EXPECT_NEAR(got.oblique[d].heading_deg, planned.coverage.oblique[d].heading_deg, 1e-6);
    EXPECT_NEAR(got.oblique[d].poc, planned.coverage.oblique[d].poc, 0.005) << "direction " << d;
    EXPECT_GT(got.oblique[d].poc, 0.95) << "direction " << d;
  }
  EXPECT_NEAR(got.total.pooc, planned.coverage.total.pooc, 0.005);

  // a structure scan: the wall's coverage from the paths as from the plan (orbits at their own heights,
  // facing the wall)
  const nlohmann::json structure = {{"name", "square building"},
                                    {"structure",
                                     {{"footprint", ring({{-15, -15}, {15, -15}, {15, 15}, {-15, 15}})},
                                      {"height_m", 40},
                                      {"standoff_m", 15}}},
                                    {"camera", {{"altitude_m", 20}, {"hfov_deg", 73.4}, {"overlap", 0.5}}},
                                    {"uavs", {{{"id", "u1"}, {"start", at(0, -60)}}}},
                                    {"planner", "boustrophedon"},
                                    {"seed", 3}};
  const Plan s = plan(parse_mission(structure.dump()));
  const auto s_planned = evaluation::evaluate_plan(s);
  const auto s_paths = usecases::evaluate_paths(s.mission, codec::paths_geojson(s).dump(), {});
  ASSERT_TRUE(s_planned.facade.has_value());
  ASSERT_TRUE(s_paths.evaluation.facade.has_value());
  EXPECT_GT(s_planned.facade->total.covered_share, 0.9);
  EXPECT_NEAR(s_paths.evaluation.facade->total.covered_share, s_planned.facade->total.covered_share, 0.005);
  EXPECT_EQ(s_paths.evaluation.facade->total.images, s_planned.facade->total.images);
}

TEST(EvaluatePaths, ABadAttitudeIsRefusedNamingTheField) {
  const Plan& p = testing::olive_grove_plan();
  nlohmann::json g = codec::paths_geojson(p);
  std::size_t k = 0;
  while (g["features"][k]["geometry"]["type"] != "LineString") ++k;
  const auto expect_field = [&](const nlohmann::json& attitude, const std::string& field) {
    nlohmann::json bad = g;
    bad["features"][k]["properties"]["attitude"] = attitude;
    try {
      usecases::evaluate_paths(p.mission, bad.dump(), {});
      ADD_FAILURE() << "accepted " << attitude.dump();
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "features[" + std::to_string(k) + "].properties.attitude" + field) << e.what();
    }
  };
  const std::size_t vertices = g["features"][k]["geometry"]["coordinates"].size();
  expect_field({{"heading_deg", std::vector<double>(vertices + 1, 0.0)}}, ".heading_deg");
  expect_field({{"gimbal_pitch_deg", -120}}, ".gimbal_pitch_deg");
  expect_field({{"yaw", 3}}, ".yaw");
  expect_field("level", "");
}

}  // namespace
}  // namespace uavcover
