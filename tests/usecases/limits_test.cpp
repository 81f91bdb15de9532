// Stops and time limits after the planner (issues 26 §3, 27; docs/stops.md): plan_outputs() with a
// deadline that has passed leaves out what did not fit, names it, and still gives a complete, readable
// plan (plan.json + paths.geojson, written whole); a stop in any stage after the planner ends the work
// with Cancelled (the CLI's exit 130, a job's `cancelled`), never a result. No test here depends on how
// fast anything runs: the deadline has passed before the outputs begin, or a progress callback waits
// for it (or requests the stop) at a known point inside a stage.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <set>
#include <stop_token>
#include <thread>

#include "codec/plan_codec.hpp"
#include "io/write_artifacts.hpp"
#include "support/files.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/jobs.hpp"
#include "usecases/plan_outputs.hpp"

using namespace uavcover;
using nlohmann::json;
using usecases::JobType;

namespace {

Mission rectangle() {
  Mission m = parse_mission(uavcover::testing::slurp(std::filesystem::path(UAVCOVER_BENCH_DATA) /
                                                     "mondinelli2025" / "rectangle_3uav.json"));
  m.planner = "boustrophedon";  // planned in milliseconds; the outputs are what these tests are about
  m.planner_params = json::object();
  return m;
}

std::set<std::string> names(const Artifacts& artifacts) {
  std::set<std::string> out;
  for (const auto& a : artifacts) out.insert(a.name);
  return out;
}

const Artifact& artifact(const Artifacts& artifacts, const std::string& name) {
  for (const auto& a : artifacts)
    if (a.name == name) return a;
  throw std::runtime_error("no artifact " + name);
}

usecases::OutputOptions everything() {
  usecases::OutputOptions oo;
  oo.exports = {"qgc", "kml", "wpl"};
  return oo;
}

constexpr const char* kLeftOut = "time limit reached after planning: left out ";

/// plan.json and paths.geojson read back into the same plan, and plan.json's warnings say `warning`.
void expect_complete_plan(const Plan& p, const Artifacts& artifacts, const std::string& warning) {
  const json pj = json::parse(artifact(artifacts, "plan.json").bytes);
  const json pg = json::parse(artifact(artifacts, "paths.geojson").bytes);
  const Plan back = codec::load_plan(pj, pg);
  ASSERT_EQ(back.uavs.size(), p.uavs.size());
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    EXPECT_EQ(back.uavs[i].id, p.uavs[i].id);
    EXPECT_EQ(back.uavs[i].parts.size(), p.uavs[i].parts.size());
    EXPECT_NEAR(back.uavs[i].length_m, p.uavs[i].length_m, 1e-6 * (1 + p.uavs[i].length_m));
  }
  bool said = false;
  for (const auto& w : pj.at("warnings")) said = said || w.get<std::string>() == warning;
  EXPECT_TRUE(said) << pj.at("warnings").dump();
}

}  // namespace

// The deadline passed before the outputs began (a zero time limit): every stage after the planner is
// left out and named, in one warning (the pictures drawn from the evaluation too), and what remains is
// a complete plan that reads back and is written whole.
TEST(PlanOutputsLimits, APassedDeadlineLeavesOutEveryStageAndNamesIt) {
  const Plan p = plan(rectangle());
  const Context expired = Context().with_time_limit(Context::Clock::duration::zero());
  ASSERT_TRUE(expired.time_up());
  const auto out = usecases::plan_outputs(p, everything(), expired);
  EXPECT_EQ(out.left_out,
            (std::vector<std::string>{"evaluation", "pictures plan.png, plan.svg, heatmap.png, histogram.png",
                                      "exports qgc, kml, wpl"}));
  const std::string warning = std::string(kLeftOut) +
                              "evaluation, pictures plan.png, plan.svg, heatmap.png, histogram.png, exports "
                              "qgc, kml, wpl (plan.json and paths.geojson are complete; raise the time "
                              "limit for the rest)";
  ASSERT_EQ(std::count(out.warnings.begin(), out.warnings.end(), warning), 1)
      << ::testing::PrintToString(out.warnings);
  EXPECT_EQ(names(out.artifacts), (std::set<std::string>{"plan.json", "paths.geojson"}));
  EXPECT_LT(out.poc, 0) << "no evaluation, no PoC";
  const json pj = json::parse(artifact(out.artifacts, "plan.json").bytes);
  EXPECT_FALSE(pj.contains("coverage"));
  EXPECT_FALSE(pj.contains("cost"));
  expect_complete_plan(p, out.artifacts, warning);

  // the folder the CLI writes from them: exactly the two files, complete, no staging left beside it
  const auto dir = std::filesystem::temp_directory_path() / ("uavcover-limits-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto folder = dir / "out";
  (void)io::write_artifacts(folder, out.artifacts, Context());
  std::set<std::string> on_disk, beside;
  for (const auto& e : std::filesystem::directory_iterator(folder))
    on_disk.insert(e.path().filename().string());
  for (const auto& e : std::filesystem::directory_iterator(dir)) beside.insert(e.path().filename().string());
  EXPECT_EQ(on_disk, (std::set<std::string>{"plan.json", "paths.geojson"}));
  EXPECT_EQ(beside, (std::set<std::string>{"out"}));
  EXPECT_EQ(uavcover::testing::slurp(folder / "plan.json"), artifact(out.artifacts, "plan.json").bytes);
  std::filesystem::remove_all(dir);
}

// The deadline passes inside the evaluation (the progress callback waits for it once the first UAV's
// coverage is counted): the evaluation's own check leaves it out, with everything after it; the
// planner's plan is still whole.
TEST(PlanOutputsLimits, ADeadlineInsideTheEvaluationLeavesItOutWithWhatFollows) {
  const Plan p = plan(rectangle());
  ASSERT_GT(p.uavs.size(), 1u);
  std::optional<Context::Clock::time_point> deadline;
  bool waited = false;
  const Context base([&](std::string_view stage, double f) {
    if (stage == "evaluation" && f > 0 && !waited) {
      waited = true;
      std::this_thread::sleep_until(*deadline + std::chrono::milliseconds(1));
    }
  });
  const Context ctx = base.with_time_limit(std::chrono::milliseconds(300));
  deadline = ctx.deadline();
  const auto out = usecases::plan_outputs(p, everything(), ctx);
  EXPECT_TRUE(waited);
  ASSERT_FALSE(out.left_out.empty());
  EXPECT_EQ(out.left_out.front(), "evaluation");
  EXPECT_EQ(out.left_out.back(), "exports qgc, kml, wpl");
  EXPECT_LT(out.poc, 0);
  EXPECT_FALSE(names(out.artifacts).contains("heatmap.png"));
  EXPECT_TRUE(names(out.artifacts).contains("plan.json"));
  EXPECT_TRUE(names(out.artifacts).contains("paths.geojson"));
}

// With time for everything, nothing is left out and nothing is said about it.
TEST(PlanOutputsLimits, WithTimeForEverythingNothingIsLeftOut) {
  const Plan p = plan(rectangle());
  const auto out = usecases::plan_outputs(p, everything(), Context().with_time_limit(std::chrono::hours(1)));
  EXPECT_TRUE(out.left_out.empty());
  for (const auto& w : out.warnings) EXPECT_FALSE(w.starts_with(kLeftOut)) << w;
  for (const char* f : {"plan.json", "paths.geojson", "plan.png", "plan.svg", "heatmap.png", "histogram.png"})
    EXPECT_TRUE(names(out.artifacts).contains(f)) << f;
  EXPECT_GE(out.poc, 0);
}

// A stop (Ctrl-C, DELETE of a job) inside each stage after the planner ends the work with Cancelled,
// never with outputs: at the stage's start, after the evaluation's first UAV, after the first picture,
// after the first export format.
TEST(PlanOutputsLimits, AStopInsideEveryStageEndsCancelled) {
  const Plan p = plan(rectangle());
  struct Point {
    const char* stage;
    bool inside;  ///< after the stage's first step, not at its start
  };
  for (const Point at : {Point{"evaluation", false}, Point{"evaluation", true}, Point{"pictures", false},
                         Point{"pictures", true}, Point{"exports", false}, Point{"exports", true}}) {
    std::stop_source stop;
    std::vector<std::string> seen;
    const Context ctx(
        [&](std::string_view stage, double f) {
          if (seen.empty() || seen.back() != stage) seen.emplace_back(stage);
          if (stage == at.stage && (at.inside ? f > 0 : true)) stop.request_stop();
        },
        stop.get_token());
    EXPECT_THROW((void)usecases::plan_outputs(p, everything(), ctx), Cancelled) << at.stage << at.inside;
    ASSERT_TRUE(stop.stop_requested()) << at.stage << " never reached";
    EXPECT_EQ(seen.back(), at.stage) << "went on past the stop: " << ::testing::PrintToString(seen);
  }
}

// The server's plan job runs the same use case: a stop during its evaluation or its pictures cancels
// the job (the worker records `cancelled`, never `done`, with no artifacts).
TEST(PlanOutputsLimits, APlanJobStoppedInItsEvaluationOrPicturesIsCancelled) {
  const Mission m = rectangle();
  const json params = usecases::validate_job_params(JobType::Plan, m, nullptr);
  for (const char* at : {"evaluation", "pictures"}) {
    std::stop_source stop;
    const Context ctx(
        [&](std::string_view stage, double) {
          if (stage == at) stop.request_stop();
        },
        stop.get_token());
    EXPECT_THROW((void)usecases::run_job(JobType::Plan, m, params, ctx), Cancelled) << at;
    EXPECT_TRUE(stop.stop_requested()) << at;
  }
}

// Transition altitudes that cannot fit under the export's 120 m ceiling (50 UAVs) are refused when a
// plan job is validated, before anything is planned (the server answers 422 naming the field).
TEST(PlanOutputsLimits, AnUnmeetableCeilingIsRefusedBeforePlanning) {
  Mission m = rectangle();
  const Uav first = m.uavs.front();
  m.uavs.clear();
  for (int i = 0; i < 50; ++i) {
    Uav u = first;
    u.id = "u" + std::to_string(i);
    u.share = 1.0 / 50;
    m.uavs.push_back(u);
  }
  try {
    (void)usecases::validate_job_params(JobType::Plan, m, nullptr);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "altitude.transition_ceiling_m");
    EXPECT_NE(std::string(e.what()).find("50 UAVs"), std::string::npos) << e.what();
  }
  // the CLI's check before planning, with an export
  usecases::OutputOptions oo;
  oo.exports = {"qgc"};
  EXPECT_THROW(usecases::check_outputs(m, oo), InputError);
}
