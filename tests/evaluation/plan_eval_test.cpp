// Evaluating plans made through the facade, and the study command end to end.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "evaluation/evaluate.hpp"
#include "support/files.hpp"
#include "uavcover/uavcover.hpp"

using namespace uavcover;
namespace fs = std::filesystem;

TEST(EvaluatePlan, PlannedRegionIsCoveredAndCosted) {
  Mission m = parse_mission(uavcover::testing::roi_text("roi01.json"));
  m.mode = Mode::Coverage;
  const Plan p = plan(m);
  const auto ev = evaluation::evaluate_plan(p);
  EXPECT_DOUBLE_EQ(ev.footprint_m, 60.0);
  EXPECT_GT(ev.coverage.total.poc, 0.97);
  EXPECT_GT(ev.coverage.total.pooc, 0.3);
  int turns = 0;
  double length = 0.0;
  for (const auto& u : p.uavs) turns += u.turns, length += u.length_m;
  EXPECT_EQ(ev.coverage.total.turns, turns);
  EXPECT_NEAR(ev.coverage.total.length_m, length, 1e-6 * length);
  ASSERT_EQ(ev.cost.n_uavs, 1);
  EXPECT_NEAR(ev.cost.flight_time_min, evaluation::flight_duration_min(length, turns, p.mission.uavs[0]),
              1e-9);
  EXPECT_DOUBLE_EQ(ev.cost.deployment_time_min, 8.0);
  const auto j = evaluation::to_json(ev);
  ASSERT_TRUE(j.contains("coverage") && j.contains("cost"));
  EXPECT_EQ(j["coverage"]["uavs"].size(), 1u);
  EXPECT_DOUBLE_EQ(j["coverage"]["poc"].get<double>(), ev.coverage.total.poc);
  EXPECT_DOUBLE_EQ(j["cost"]["total_time_min"].get<double>(), ev.cost.total_time_min);
  EXPECT_NEAR(j["coverage"]["uavs"][0]["area_share"].get<double>(), 1.0, 1e-12);
}

TEST(StudyCommand, TableJsonAndPicture) {
  const fs::path dir = fs::temp_directory_path() / ("uavcover_study_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string mission = std::string(UAVCOVER_BENCH_DATA) + "/apostolidis2022/roi01.json";
  const std::string cmd = std::string(UAVCOVER_CLI) + " study " + mission + " --uavs 1..3 --out " +
                          dir.string() + " > " + (dir.string() + ".txt");
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream in(dir / "study.json");
  const auto j = nlohmann::json::parse(in);
  ASSERT_EQ(j["rows"].size(), 3u);
  double best = 1e300;
  int best_n = 0;
  for (const auto& r : j["rows"]) {
    ASSERT_TRUE(r.contains("total_time_min")) << r.dump();
    EXPECT_GT(r["poc"].get<double>(), 0.9);
    EXPECT_DOUBLE_EQ(r["deployment_time_min"].get<double>(), 5.0 + 3.0 * r["uavs"].get<int>());
    if (r["total_time_min"].get<double>() < best)
      best = r["total_time_min"].get<double>(), best_n = r["uavs"].get<int>();
  }
  EXPECT_EQ(j["recommended_uavs"].get<int>(), best_n);
  EXPECT_GT(fs::file_size(dir / "study.png"), 3000u);
  std::ifstream txt(dir.string() + ".txt");
  const std::string out((std::istreambuf_iterator<char>(txt)), std::istreambuf_iterator<char>());
  EXPECT_NE(out.find("recommended: " + std::to_string(best_n)), std::string::npos) << out;
  fs::remove_all(dir);
  fs::remove(dir.string() + ".txt");
}

TEST(StudyCommand, RefusesBadCounts) {
  const std::string mission = std::string(UAVCOVER_BENCH_DATA) + "/apostolidis2022/roi01.json";
  for (const char* bad : {"0..3", "3..1", "x", "1,,2"}) {
    const std::string cmd = std::string(UAVCOVER_CLI) + " -q study " + mission + " --uavs " + bad +
                            " --out /tmp/uavcover_never_written 2>/dev/null";
    const int rc = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(rc));
    EXPECT_EQ(WEXITSTATUS(rc), 2) << bad;
  }
  EXPECT_FALSE(fs::exists("/tmp/uavcover_never_written/study.json"));
}

TEST(Footprint, FromCameraElseOneAndAHalfSpacing) {
  Mission m;
  m.spacing_m = 40;
  EXPECT_DOUBLE_EQ(evaluation::footprint_for(m), 60.0);
  Camera c;
  c.altitude_m = 40;
  c.hfov_deg = 73.4;
  m.camera = c;
  EXPECT_NEAR(evaluation::footprint_for(m), 2 * 40 * std::tan(36.7 * M_PI / 180), 1e-9);  // paper eq. 12
  c.hfov_deg.reset();
  c.image_width_px = 4000;
  m.camera = c;
  m.gsd_m = 0.01;
  EXPECT_DOUBLE_EQ(evaluation::footprint_for(m), 40.0);  // imgW * GSD
  m.footprint_m = 55.0;
  EXPECT_DOUBLE_EQ(evaluation::footprint_for(m), 55.0);  // the parser's value wins
}

TEST(EvaluateCommand, OwnPlanDirectoryGivesTheSameNumbersAsEvaluatePlan) {
  const fs::path dir = fs::temp_directory_path() / ("uavcover_eval_own_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string mission = std::string(UAVCOVER_BENCH_DATA) + "/apostolidis2022/roi09.json";
  const std::string cli = UAVCOVER_CLI;
  ASSERT_EQ(std::system((cli + " -q plan " + mission + " --out " + dir.string()).c_str()), 0);
  ASSERT_EQ(std::system((cli + " -q evaluate " + mission + " " + (dir / "paths.geojson").string() +
                         " --out " + dir.string() + " --no-images")
                            .c_str()),
            0);
  std::ifstream in(dir / "evaluation.json");
  const auto j = nlohmann::json::parse(in);
  // paths read from GeoJSON carry no battery sorties: their batteries follow eq. 16, as a plan's
  // without sorties does (docs/sorties.md)
  Plan own = plan(parse_mission(uavcover::testing::roi_text("roi09.json")));
  for (auto& u : own.uavs) u.sorties.clear();
  const auto ev = evaluation::evaluate_plan(own);
  EXPECT_NEAR(j["poc"].get<double>(), ev.coverage.total.poc, 0.002);
  EXPECT_NEAR(j["pooc"].get<double>(), ev.coverage.total.pooc, 0.002);
  EXPECT_EQ(j["turns"].get<int>(), ev.coverage.total.turns);
  EXPECT_NEAR(j["length_m"].get<double>(), ev.coverage.total.length_m, 0.5);
  EXPECT_NEAR(j["total_time_min"].get<double>(), ev.cost.total_time_min, 0.01);
  fs::remove_all(dir);
}

TEST(EvaluatePlan, LatticeSharesFollowTheDivision) {
  const Mission m =
      uavcover::testing::with_equal_uavs(parse_mission(uavcover::testing::roi_text("roi09.json")), 3);
  const Plan p = plan(m);
  const auto ev = evaluation::evaluate_plan(p);
  ASSERT_EQ(ev.coverage.uavs.size(), 3u);
  double sum = 0.0;
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(ev.coverage.uavs[i].area_share, p.uavs[i].share_actual, 0.05) << i;
    sum += ev.coverage.uavs[i].area_share;
  }
  EXPECT_NEAR(sum, 1.0, 1e-9);
  ASSERT_EQ(ev.cost.n_uavs, 3);
  EXPECT_DOUBLE_EQ(ev.cost.deployment_time_min, 14.0);
  double longest = 0.0;
  for (const auto& u : ev.cost.uavs) longest = std::max(longest, u.flight_duration_min);
  EXPECT_DOUBLE_EQ(ev.cost.flight_time_min, longest);
}

TEST(EvaluatePlan, AUavWithASmallerCameraSeesLessOfTheSamePath) {
  // a 1 km x 0.8 km field, the mission's camera 40 m across (hfov 90 deg at 20 m), two UAVs
  nlohmann::json j = nlohmann::json::parse(R"({
    "area": {"type": "Polygon", "coordinates": [[[22.90, 40.60], [22.912, 40.60], [22.912, 40.607], [22.90, 40.607], [22.90, 40.60]]]},
    "camera": {"altitude_m": 20, "hfov_deg": 90, "overlap": 0.5},
    "uavs": [{"id": "a", "start": [22.901, 40.601]}, {"id": "b", "start": [22.911, 40.606]}],
    "mode": "coverage", "seed": 3})");
  const Plan same_cameras = plan(parse_mission(j.dump()));
  // the same paths, flown by a b whose own camera sees 20 m across (hfov 53.13 deg at 20 m)
  j["uavs"][1]["camera"] = {
      {"altitude_m", 20}, {"hfov_deg", 2 * std::atan(0.5) * 180 / M_PI}, {"overlap", 0.5}};
  Plan smaller_b = same_cameras;
  smaller_b.mission = parse_mission(j.dump());
  ASSERT_NEAR(evaluation::footprint_for(smaller_b.mission, 1), 20.0, 1e-9);
  ASSERT_NEAR(evaluation::footprint_for(smaller_b.mission, 0), 40.0, 1e-9);

  const auto before = evaluation::evaluate_plan(same_cameras);
  const auto after = evaluation::evaluate_plan(smaller_b);
  ASSERT_EQ(after.coverage.uavs.size(), 2u);
  EXPECT_DOUBLE_EQ(after.coverage.uavs[0].footprint_m, 40.0);
  EXPECT_DOUBLE_EQ(after.coverage.uavs[1].footprint_m, 20.0);
  EXPECT_DOUBLE_EQ(after.coverage.uavs[0].stats.poc, before.coverage.uavs[0].stats.poc) << "a is unchanged";
  // b's lines are 30 m apart (the mission's spacing): a 20 m footprint leaves gaps between them
  EXPECT_LT(after.coverage.uavs[1].stats.poc, 0.9 * before.coverage.uavs[1].stats.poc);
  EXPECT_LT(after.coverage.total.poc, before.coverage.total.poc);
  EXPECT_EQ(evaluation::to_json(after)["coverage"]["uavs"][1]["footprint_m"].get<double>(), 20.0);
  // a --footprint override sweeps one w for every UAV
  evaluation::EvaluateOptions one;
  one.coverage.footprint_m = 40.0;
  EXPECT_DOUBLE_EQ(evaluation::evaluate_plan(smaller_b, one).coverage.uavs[1].stats.poc,
                   before.coverage.uavs[1].stats.poc);
  // photo estimate: b shoots at its own camera's trigger distance, so more images on the same legs
  ASSERT_TRUE(after.images && before.images);
  EXPECT_DOUBLE_EQ(after.images->uavs[1].trigger_distance_m,
                   smaller_b.mission.uavs[1].camera_geometry->trigger_distance_m);
  EXPECT_EQ(after.images->uavs[0].images, before.images->uavs[0].images);
  EXPECT_GT(after.images->uavs[1].images, before.images->uavs[1].images);
}
