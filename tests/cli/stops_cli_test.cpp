// `uavcover plan` stopped in every stage, and its time limit over the whole command. The command is
// held at a known stage with the test hook UAVCOVER_TEST_HOLD_STAGE (docs/stops.md), so that nothing
// here depends on how fast planning or writing is.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "cli/cli_support.hpp"

using namespace uavcover::testing;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

/// Starts `uavcover ARGS` with `env` ("NAME=value ..."), stdout and stderr into `log`.
pid_t start_cli(const std::string& env, const std::string& args, const fs::path& log) {
  const std::string cmd =
      "exec env " + env + " " + std::string(UAVCOVER_CLI) + " " + args + " > " + log.string() + " 2>&1";
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

/// Waits until `log` holds `text` or the process ended (no timing is asserted: the hold itself ends
/// after 60 s at the latest, so this cannot hang). True when the text appeared.
bool wait_for_line(pid_t pid, const fs::path& log, const std::string& text) {
  for (;;) {
    if (slurp(log).find(text) != std::string::npos) return true;
    int status = 0;
    if (::waitpid(pid, &status, WNOHANG) == pid)  // it ended (and is reaped) without reaching the hold
      return slurp(log).find(text) != std::string::npos;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

bool any_staging_left(const fs::path& dir) {
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.path().filename().string().find(".staging-") != std::string::npos) return true;
  return false;
}

class PlanInterrupt : public ::testing::TestWithParam<std::string> {};

}  // namespace

// Ctrl-C while the command is held in a stage: exit 130, "nothing was written", no output folder and
// no staging folder, in every stage up to the last moment of writing.
TEST_P(PlanInterrupt, InterruptStopsCleanlyWithNoOutputFolder) {
  const std::string stage = GetParam();
  const auto dir = temp_dir("sigint-" + stage);
  const auto out = dir / "out";
  const auto log = dir / "log";
  const pid_t pid = start_cli(
      "UAVCOVER_TEST_HOLD_STAGE=" + stage,
      "-q plan " + example("olive-grove.json").string() + " --out " + out.string() + " --export qgc,kml",
      log);
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(wait_for_line(pid, log, "uavcover: test hold: " + stage)) << slurp(log);
  ::kill(pid, SIGINT);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << slurp(log);
  EXPECT_EQ(WEXITSTATUS(status), 130) << slurp(log);
  EXPECT_NE(slurp(log).find("nothing was written"), std::string::npos) << slurp(log);
  EXPECT_FALSE(fs::exists(out)) << "a partial output folder was left";
  EXPECT_FALSE(any_staging_left(dir)) << "a staging folder was left";
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(EveryStage, PlanInterrupt,
                         ::testing::Values("planning", "evaluation", "pictures", "exports", "storing"),
                         [](const auto& info) { return info.param; });

// Into a folder that exists already: a stop while writing leaves it as it was.
TEST(PlanInterruptExisting, StopWhileWritingLeavesAnExistingFolderUntouched) {
  const auto dir = temp_dir("sigint-existing");
  const auto out = dir / "out";
  fs::create_directories(out);
  std::ofstream(out / "keep.txt") << "mine";
  const auto log = dir / "log";
  const pid_t pid =
      start_cli("UAVCOVER_TEST_HOLD_STAGE=storing",
                "-q plan " + example("olive-grove.json").string() + " --out " + out.string(), log);
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(wait_for_line(pid, log, "uavcover: test hold: storing")) << slurp(log);
  ::kill(pid, SIGINT);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130) << slurp(log);
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(out)) names.push_back(e.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"keep.txt"});
  fs::remove_all(dir);
}

// The time limit covers the stages after the planner: held in "pictures" until the deadline, the
// command still exits 0 with plan.json and paths.geojson, no pictures and no exports, and says so.
TEST(PlanTimeLimit, StagesThatDoNotFitAreLeftOutAndNamed) {
  const auto dir = temp_dir("timelimit-stages");
  auto mission = read_json(example("olive-grove.json"));
  mission["planner"] = "boustrophedon";  // a planner that finishes long before the limit
  const auto file = dir / "m.json";
  std::ofstream(file) << mission.dump();
  const auto out = dir / "out";
  const auto r =
      run_cli("plan " + file.string() + " --out " + out.string() + " --time-limit 2 --export qgc,kml",
              "UAVCOVER_TEST_HOLD_STAGE=pictures");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("uavcover: test hold: pictures"), std::string::npos) << r.output;
  const std::string left = "time limit reached after planning: left out ";
  ASSERT_NE(r.output.find(left), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("pictures plan.png, plan.svg"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("exports qgc, kml"), std::string::npos) << r.output;
  const auto pj = read_json(out / "plan.json");
  EXPECT_TRUE(pj.at("complete").get<bool>());
  bool said = false;
  for (const auto& w : pj.at("warnings")) said = said || w.get<std::string>().starts_with(left);
  EXPECT_TRUE(said) << pj.at("warnings").dump();
  EXPECT_TRUE(fs::exists(out / "paths.geojson"));
  for (const char* f : {"plan.png", "plan.svg", "heatmap.png", "histogram.png", "export"})
    EXPECT_FALSE(fs::exists(out / f)) << f;
  // without the hold the same command has time for everything
  const auto full = dir / "full";
  const auto r2 =
      run_cli("plan " + file.string() + " --out " + full.string() + " --time-limit 600 --export qgc");
  ASSERT_EQ(r2.exit_code, 0) << r2.output;
  EXPECT_EQ(r2.output.find(left), std::string::npos) << r2.output;
  EXPECT_TRUE(fs::exists(full / "plan.png"));
  EXPECT_TRUE(fs::exists(full / "export"));
  fs::remove_all(dir);
}

// Transition altitudes that cannot fit under the export's ceiling are refused before any planning:
// exit 2 with the export's message naming the field; the planner is never reached (its hold is not).
TEST(PlanAltitudes, CeilingThatCannotBeMetIsRefusedBeforePlanning) {
  const auto dir = temp_dir("ceiling");
  const auto file = dir / "m.json";
  std::ofstream(file) << R"({"name": "many",
    "area": {"type": "Polygon", "coordinates": [[[9.0, 45.0], [9.01, 45.0], [9.01, 45.01], [9.0, 45.01]]]},
    "spacing_m": 20, "uavs": 20, "seed": 2})";
  const auto out = dir / "out";
  const auto r = run_cli("plan " + file.string() + " --out " + out.string() + " --export qgc",
                         "UAVCOVER_TEST_HOLD_STAGE=planning");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("altitude.transition_ceiling_m: 20 UAVs need transition altitudes"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("test hold: planning"), std::string::npos) << "refused only after planning";
  EXPECT_FALSE(fs::exists(out));
  // without exports nothing flies them: the plan is made
  const auto r2 =
      run_cli("-q plan " + file.string() + " --out " + out.string() + " --no-evaluate --no-images");
  EXPECT_EQ(r2.exit_code, 0) << r2.output;
  fs::remove_all(dir);
}
