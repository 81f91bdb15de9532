// "planner": "auto" (issue 32, docs/planners.md): the best plan by the objective among the planners that
// support the mission, with PoC at most 0.5 points below the best planner's.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <stop_token>

#include "uavcover/uavcover.hpp"

using namespace uavcover;
using nlohmann::json;

namespace {

json field(const std::string& objective) {
  // 600 m x 400 m field, two UAVs
  return json::parse(R"({
    "area": {"type": "Polygon", "coordinates": [[[22.90, 40.60], [22.907, 40.60], [22.907, 40.6036], [22.90, 40.6036]]]},
    "spacing_m": 30,
    "uavs": [{"id": "a", "start": [22.9005, 40.6005]}, {"id": "b", "start": [22.9065, 40.6030]}],
    "planner": "auto",
    "objective": ")" +
                     objective + R"(",
    "seed": 5
  })");
}

double figure(const json& row, const std::string& objective) {
  const auto& f = row.at("figures");
  if (objective == "poc") return -f.at("poc").get<double>();
  if (objective == "turns") return f.at("turns").get<double>();
  if (objective == "length") return f.at("length_m").get<double>();
  return f.at("time_min").get<double>();
}

}  // namespace

TEST(AutoPlanner, WinnerIsBestByEachObjectiveAmongPlansWithinHalfAPocPoint) {
  for (const std::string objective : {"time", "poc", "turns", "length"}) {
    const Plan p = plan(parse_mission(field(objective).dump()));
    const json& s = p.selection;
    ASSERT_TRUE(s.is_object()) << objective;
    EXPECT_EQ(s.at("by"), "auto");
    EXPECT_EQ(s.at("objective"), objective);
    EXPECT_EQ(p.planner, s.at("winner").get<std::string>()) << "plan.json's planner is the winner's";
    EXPECT_EQ(p.mission.planner, "auto");
    const json* win = nullptr;
    double best_poc = 0;
    int ok = 0;
    for (const auto& r : s.at("candidates"))
      if (r.contains("figures")) {
        best_poc = std::max(best_poc, r["figures"]["poc"].get<double>());
        ++ok;
        if (r["status"] == "won") win = &r;
      }
    ASSERT_NE(win, nullptr) << objective;
    EXPECT_GE(ok, 2) << "darp and boustrophedon at least plan a plain field";
    EXPECT_GE((*win)["figures"]["poc"].get<double>(), best_poc - 0.005 - 1e-12);
    for (const auto& r : s.at("candidates"))
      if (r.contains("figures") && r["figures"]["poc"].get<double>() >= best_poc - 0.005 - 1e-12) {
        EXPECT_LE(figure(*win, objective), figure(r, objective))
            << objective << ": " << r["planner"] << " is better than the winner";
      }
  }
}

TEST(AutoPlanner, WinnerPlanIsThePlanOfThatPlannerAndIsDeterministic) {
  const Mission m = parse_mission(field("length").dump());
  const Plan a = plan(m), b = plan(m);
  EXPECT_EQ(a.planner, b.planner);
  ASSERT_EQ(a.uavs.size(), b.uavs.size());
  Mission direct = m;
  direct.planner = a.planner;
  const Plan d = plan(direct);
  for (std::size_t i = 0; i < a.uavs.size(); ++i) {
    EXPECT_DOUBLE_EQ(a.uavs[i].length_m, b.uavs[i].length_m);
    EXPECT_DOUBLE_EQ(a.uavs[i].length_m, d.uavs[i].length_m);
  }
  EXPECT_TRUE(d.selection.is_null()) << "a named planner has no selection";
}

TEST(AutoPlanner, PlannersThatCannotPlanTheMissionAreSkippedWithTheReason) {
  auto j = field("time");
  j["no_fly_zones"] = json::parse(
      R"([{"type": "Polygon", "coordinates": [[[22.903, 40.601], [22.904, 40.601], [22.904, 40.602], [22.903, 40.602]]]}])");
  const Plan p = plan(parse_mission(j.dump()));
  int skipped = 0;
  for (const auto& r : p.selection.at("candidates"))
    if (r["status"] == "skipped") {
      ++skipped;
      EXPECT_NE(r.at("reason").get<std::string>().find("no_fly_zones"), std::string::npos) << r.dump();
    }
  for (const auto& info : available_planners())
    if (!info.schema.at("supports").value("no_fly_zones", true)) {
      EXPECT_GE(skipped, 1) << info.name;
    }
}

TEST(AutoPlanner, RefusesUnknownObjectiveAndParameters) {
  try {
    (void)parse_mission(field("fastest").dump());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "objective");
  }
  auto j = field("time");
  j["planner_params"] = {{"max_iterations", 10}};
  try {
    (void)parse_mission(j.dump());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "planner_params");
  }
}

TEST(AutoPlanner, TheWholeTimeLimitAndCancelHoldAcrossTheRuns) {
  const Mission m = parse_mission(field("time").dump());
  EXPECT_THROW((void)plan(m, {}, Context({}, {}, std::chrono::nanoseconds(0))), TimeLimitReached);
  std::stop_source stop;
  stop.request_stop();
  EXPECT_THROW((void)plan(m, {}, Context({}, stop.get_token())), Cancelled);
  // progress: every report in [0, 1], ending at done
  std::vector<std::pair<std::string, double>> events;
  (void)plan(m, {}, Context([&](std::string_view st, double f) { events.emplace_back(std::string(st), f); }));
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().first, "done");
  for (std::size_t i = 1; i < events.size(); ++i)
    if (events[i].first == events[i - 1].first && events[i].first != "done") {
      EXPECT_GE(events[i].second, events[i - 1].second) << events[i].first;
    }
}
