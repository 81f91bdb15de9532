// End-to-end tests of `uavcover plan`: exit codes, messages, and the files it writes.
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "cli/cli_support.hpp"

using namespace uavcover::testing;
using nlohmann::json;
namespace fs = std::filesystem;

TEST(PlanCli, HelpDocumentsTheCommands) {
  auto r = run_cli("--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("plan"), std::string::npos);
  r = run_cli("plan --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("--out"), std::string::npos);
  EXPECT_NE(r.output.find("--seed"), std::string::npos);
  EXPECT_NE(r.output.find("paths.geojson"), std::string::npos);
}

TEST(PlanCli, UsageErrorsExitTwo) {
  EXPECT_EQ(run_cli("").exit_code, 2);
  EXPECT_EQ(run_cli("plan").exit_code, 2);
  EXPECT_EQ(run_cli("frobnicate").exit_code, 2);
}

TEST(PlanCli, WritesPathsAndPlan) {
  const auto dir = temp_dir("plan");
  const auto r =
      run_cli("plan " + example("olive-grove.json").string() + " --out " + dir.string() + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.output.empty()) << "--quiet prints nothing: " << r.output;
  const json gj = read_json(dir / "paths.geojson");
  ASSERT_EQ(gj["type"], "FeatureCollection");
  std::map<std::string, int> coverage_lines;
  int areas = 0, nfz = 0;
  for (const auto& f : gj["features"]) {
    const auto& props = f["properties"];
    if (props.contains("role")) {
      EXPECT_EQ(f["geometry"]["type"], "Polygon");
      areas += props["role"] == "area";
      nfz += props["role"] == "no_fly_zone";
      continue;
    }
    ASSERT_EQ(f["geometry"]["type"], "LineString");
    for (const char* k : {"uav", "kind", "share_requested", "share_actual", "length_m", "turns"})
      EXPECT_TRUE(props.contains(k)) << k;
    const auto& c = f["geometry"]["coordinates"];
    ASSERT_GE(c.size(), 2u);
    for (const auto& p : c) {
      EXPECT_GT(p[0].get<double>(), 22.8);  // [lon, lat] order
      EXPECT_LT(p[1].get<double>(), 40.7);
    }
    if (props["kind"] == "coverage") {
      ++coverage_lines[props["uav"]];
      EXPECT_EQ(c.front(), c.back()) << "coverage loops are closed";
    } else {
      EXPECT_EQ(props["kind"], "transit");
    }
  }
  EXPECT_EQ(areas, 1);
  EXPECT_EQ(nfz, 2);
  EXPECT_EQ(coverage_lines.size(), 3u);
  const json pj = read_json(dir / "plan.json");
  EXPECT_NEAR(pj["spacing_m"].get<double>(), 55.9, 0.1);
  EXPECT_NEAR(pj["footprint_m"].get<double>(), 74.5, 0.1);
  EXPECT_EQ(pj["uavs"].size(), 3u);
  for (const char* k : {"J", "J1", "J2", "J3", "rotation_deg", "shift_x_m", "shift_y_m"})
    EXPECT_TRUE(pj["planner_diagnostics"]["placement"].contains(k)) << k;
  EXPECT_EQ(pj["planner"], "darp");
  for (const auto& u : pj["uavs"]) EXPECT_EQ(u["region"]["type"], "MultiPolygon");
  double share_sum = 0;
  for (const auto& u : pj["uavs"]) share_sum += u["share_actual"].get<double>();
  EXPECT_NEAR(share_sum, 1.0, 1e-9);
  EXPECT_GT(pj["totals"]["length_m"].get<double>(), 1000);
  // coverage and cost are in plan.json at planning time
  ASSERT_TRUE(pj.contains("coverage")) << pj.dump().substr(0, 500);
  ASSERT_TRUE(pj.contains("cost"));
  // the trajectory-based alternative to eq. 15: slower than constant speed, same order of magnitude
  ASSERT_TRUE(pj.contains("cost_trajectory"));
  const double ft_eq15 = pj["cost"]["flight_time_min"].get<double>();
  const double ft_traj = pj["cost_trajectory"]["flight_time_min"].get<double>();
  EXPECT_GT(ft_traj, 0.5 * ft_eq15);
  EXPECT_LT(ft_traj, 2.0 * ft_eq15);
  const double poc = pj["coverage"]["poc"].get<double>();
  EXPECT_GT(poc, 0.85);
  EXPECT_LE(poc, 1.0);
  // pictures
  for (const char* img : {"plan.png", "heatmap.png", "histogram.png"}) {
    const std::string png = slurp(dir / img);
    ASSERT_GT(png.size(), 1000u) << img;
    EXPECT_EQ(png.substr(1, 3), "PNG") << img;
  }
  EXPECT_NE(slurp(dir / "plan.svg").find("<svg"), std::string::npos);
  fs::remove_all(dir);
}

TEST(PlanCli, SameSeedSamePlan) {
  const auto d1 = temp_dir("seed1"), d2 = temp_dir("seed2"), d3 = temp_dir("seed3");
  const std::string m = example("mcpp-darp-input.json").string();
  ASSERT_EQ(run_cli("plan " + m + " --out " + d1.string() + " -q --seed 5").exit_code, 0);
  ASSERT_EQ(run_cli("plan " + m + " --out " + d2.string() + " -q --seed 5").exit_code, 0);
  EXPECT_EQ(slurp(d1 / "paths.geojson"), slurp(d2 / "paths.geojson"));
  // random starts (UAV count only) depend on the seed
  const auto dir = temp_dir("seedm");
  json mission = read_json(example("olive-grove.json"));
  mission["uavs"] = 2;
  std::ofstream(dir / "m.json") << mission.dump();
  ASSERT_EQ(run_cli("plan " + (dir / "m.json").string() + " --out " + d1.string() + " -q --seed 1").exit_code,
            0);
  ASSERT_EQ(run_cli("plan " + (dir / "m.json").string() + " --out " + d3.string() + " -q --seed 2").exit_code,
            0);
  EXPECT_NE(read_json(d1 / "plan.json")["uavs"][0]["start"], read_json(d3 / "plan.json")["uavs"][0]["start"]);
  for (const auto& d : {d1, d2, d3, dir}) fs::remove_all(d);
}

TEST(PlanCli, BadInputExitsTwoWithOneLineAndNoFiles) {
  const auto dir = temp_dir("bad");
  json mission = read_json(example("olive-grove.json"));
  mission["uavs"][1]["share"] = -1;
  std::ofstream(dir / "bad.json") << mission.dump();
  std::ofstream(dir / "broken.json") << "{\"area\": [";
  struct Case {
    std::string file, needle;
  };
  for (const Case& c : {Case{(dir / "bad.json").string(), "uavs[1].share"},
                        Case{(dir / "broken.json").string(), "malformed JSON"},
                        Case{(dir / "missing.json").string(), "cannot read"}}) {
    const auto out = dir / "out";
    const auto r = run_cli("plan " + c.file + " --out " + out.string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(c.needle), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << "one line: " << r.output;
    EXPECT_FALSE(fs::exists(out)) << "no output on bad input";
  }
  fs::remove_all(dir);
}

TEST(PlanCli, ExportsInOneGoAndRefusesUnknownFormats) {
  const auto dir = temp_dir("export");
  auto r = run_cli("plan " + example("mcpp-darp-input.json").string() + " --out " + dir.string() +
                   " -q --no-images --export qgc,wpl");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "export" / "uav1.plan"));
  EXPECT_TRUE(fs::exists(dir / "export" / "uav2.waypoints"));
  EXPECT_FALSE(fs::exists(dir / "plan.png"));
  const auto bad = dir / "bad";
  r = run_cli("plan " + example("mcpp-darp-input.json").string() + " --out " + bad.string() +
              " --export qgc,gpx");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--export"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(bad));
  fs::remove_all(dir);
}

TEST(PlanCli, ImportsMcppFormatAndRefusesHugeGrids) {
  const auto dir = temp_dir("mcpp");
  auto r = run_cli("plan " + example("mcpp-darp-input.json").string() + " --out " + dir.string() + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_json(dir / "plan.json")["mission"]["uavs"][0]["share"].get<double>(), 0.6);
  r = run_cli("plan " + example("olive-grove.json").string() + " --out " + (dir / "x").string() +
              " --max-cells 50");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("use a spacing of at least"), std::string::npos) << r.output;
  fs::remove_all(dir);
}

namespace {

/// A mission large enough that planning takes seconds: a 6 km square at ds 10 m, 8 UAVs.
std::filesystem::path big_mission(const std::filesystem::path& dir) {
  const auto p = dir / "big.json";
  std::ofstream(p) << R"({"name": "big",
    "area": {"type": "Polygon", "coordinates": [[[9.0, 45.0], [9.08, 45.0], [9.08, 45.055], [9.0, 45.055]]]},
    "spacing_m": 10, "uavs": 8, "seed": 2})";
  return p;
}

}  // namespace

// Ctrl-C in every stage: tests/cli/stops_cli_test.cpp (held there by the test hook, not by a big mission)

TEST(PlanCommand, TimeLimitGivesTheBestPlanSoFarWithAWarning) {
  using namespace uavcover::testing;
  const auto dir = temp_dir("timelimit");
  const auto r = run_cli("plan " + big_mission(dir).string() + " --out " + (dir / "out").string() +
                         " --time-limit 0.2 --no-evaluate --no-images");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("best plan found so far"), std::string::npos) << r.output;
  const auto pj = read_json(dir / "out" / "plan.json");
  EXPECT_FALSE(pj.at("complete").get<bool>());
  for (const auto& u : pj.at("uavs")) EXPECT_GT(u.at("turns").get<int>(), 0) << "every UAV has a path";
  EXPECT_EQ(run_cli("plan " + big_mission(dir).string() + " --out x --time-limit -1").exit_code, 2);
  std::filesystem::remove_all(dir);
}

TEST(PlannersCommand, ListsEveryPlannerWithItsParameters) {
  using namespace uavcover::testing;
  const auto r = run_cli("planners --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  ASSERT_TRUE(j.is_array());
  bool darp = false;
  for (const auto& p : j) darp = darp || p.at("name") == "darp";
  EXPECT_TRUE(darp);
}
