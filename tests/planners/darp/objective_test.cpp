// DARP's placement objective (issue 33): planner_params objective and j_weight_a/b/c, the paper's own
// J (Apostolidis et al. 2022, eq. 7-10) beside ours.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "codec/plan_codec.hpp"
#include "engine/local_mission.hpp"
#include "evaluation/evaluate.hpp"
#include "planners/darp/darp_planner.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover::test {
namespace {

using nlohmann::json;

std::string roi_text(int r) {
  char name[32];
  std::snprintf(name, sizeof name, "/roi%02d.json", r);
  std::ifstream f(std::string(UAVCOVER_BENCH_DATA) + "/apostolidis2022" + name);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// ROI r as a one-UAV DARP input (strict mode, its own seed and start).
darp::Input roi_input(int r) {
  const Mission m = parse_mission(roi_text(r));
  const engine::LocalMission lm = engine::to_local(m);
  darp::Input in;
  in.free = lm.free;
  in.no_fly = lm.no_fly;
  in.ds = m.spacing_m;
  in.mode = Mode::Strict;
  in.seed = 1;
  in.shares = {1.0};
  in.starts = {lm.free.front().outer().front()};
  return in;
}

struct Evaluated {
  double sx, sy, th;
  grid::Score s;
};

/// Runs DARP with the paper's objective and weights (a, b, c), recording every placement evaluated.
darp::Output run_paper(const darp::Input& in, double a, double b, double c, std::vector<Evaluated>* seen) {
  darp::Options o;
  o.paper_objective = true;
  o.j_weight_a = a;
  o.j_weight_b = b;
  o.j_weight_c = c;
  if (seen)
    o.on_placement_evaluation = [seen](double sx, double sy, double th, const grid::Score& s) {
      seen->push_back({sx, sy, th, s});
    };
  return darp::run(in, o, Context{});
}

/// J is `terms`, or `terms` less the disconnected-grid penalty (0.5) of both objectives.
bool j_is(const grid::Score& s, double terms) {
  return std::fabs(s.J - terms) < 1e-12 || std::fabs(s.J - (terms - 0.5)) < 1e-12;
}

void expect_field(const json& params, const std::string& field, const std::string& says) {
  json j = json::parse(roi_text(1));
  j["planner_params"] = params;
  try {
    (void)parse_mission(j.dump());
    ADD_FAILURE() << "accepted " << params.dump();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
  }
}

TEST(DarpObjective, ParamsAreParsedWithTheirDefaultsAndBadValuesNameTheField) {
  const Mission d = parse_mission(roi_text(1));
  EXPECT_EQ(d.planner_params.at("objective"), "uavcover");
  EXPECT_DOUBLE_EQ(d.planner_params.at("j_weight_a").get<double>(), 0.68);
  EXPECT_DOUBLE_EQ(d.planner_params.at("j_weight_b").get<double>(), 0.32);
  EXPECT_DOUBLE_EQ(d.planner_params.at("j_weight_c").get<double>(), 0.25);

  json j = json::parse(roi_text(1));
  j["planner_params"] = {{"objective", "paper"}, {"j_weight_a", 1}, {"j_weight_b", 0}, {"j_weight_c", 0}};
  const Mission p = parse_mission(j.dump());
  EXPECT_EQ(p.planner_params.at("objective"), "paper");
  EXPECT_DOUBLE_EQ(p.planner_params.at("j_weight_a").get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(p.planner_params.at("j_weight_b").get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(p.planner_params.at("j_weight_c").get<double>(), 0.0);

  expect_field({{"objective", "papers"}}, "planner_params.objective", "must be one of uavcover, paper");
  expect_field({{"objective", 1}}, "planner_params.objective", "must be a string");
  expect_field({{"j_weight_a", -0.1}}, "planner_params.j_weight_a", "must be >= 0, got -0.1");
  expect_field({{"j_weight_b", 1.5}}, "planner_params.j_weight_b", "must be <= 1, got 1.5");
  expect_field({{"j_weight_c", "0.25"}}, "planner_params.j_weight_c", "must be a number");
  expect_field({{"j_weights", {{"a", 1}}}}, "planner_params.j_weights", "unknown parameter");
  EXPECT_EQ(d.planner_params.at("min_turn_orientation"), true);
  expect_field({{"min_turn_orientation", "no"}}, "planner_params.min_turn_orientation",
               "must be true or false");
}

TEST(DarpObjective, ThePapersJWithItsWeightsOrdersTheAblationAsThePaperOnItsRegions) {
  // Apostolidis et al. 2022, Table 3, on the 18 regions it averages: the paper's own J (objective
  // "paper", a 0.68, b 0.32, c 0.25) on the bare STC loops, each plan scored by the one evaluator (the
  // paper's square footprint w = 1.5 ds swept, here on a 2 m lattice). The paper orders the mean PoC No
  // Optimization (87.73) < J1+J2 (96.02) < J1 (96.18) < J1+J2+J3 (96.37); its last two differ by 0.19
  // points, which a grid search on other machines does not reproduce exactly (bench/results/papers.md:
  // ours 96.36 and 96.08), so that step is checked as "within half a point".
  const std::vector<std::pair<std::string, json>> variants = {
      {"none", {{"optimise_placement", false}}},
      {"j1", {{"objective", "paper"}, {"j_weight_a", 1}, {"j_weight_b", 0}, {"j_weight_c", 0}}},
      {"j12", {{"objective", "paper"}, {"j_weight_a", 0.68}, {"j_weight_b", 0.32}, {"j_weight_c", 0}}},
      {"j123", {{"objective", "paper"}, {"j_weight_a", 0.68}, {"j_weight_b", 0.32}, {"j_weight_c", 0.25}}}};
  std::map<std::string, double> mean;
  std::map<std::string, std::vector<double>> poc;
  for (int r = 1; r <= 20; ++r) {
    if (r == 6 || r == 18) continue;  // the paper's means leave them out
    for (const auto& [name, params] : variants) {
      json j = json::parse(roi_text(r));
      j["planner_params"] = params;
      j["planner_params"]["extend_legs"] = false;
      j["planner_params"]["shift_legs"] = false;
      const Plan p = plan(parse_mission(j.dump()));
      evaluation::EvaluateOptions eo;
      eo.coverage.lattice_m = 2.0;
      const double c = evaluation::evaluate_plan(p, eo).coverage.total.poc;
      poc[name].push_back(c);
      mean[name] += c / 18.0;
    }
  }
  SCOPED_TRACE(::testing::Message() << "none " << mean["none"] << ", j1 " << mean["j1"] << ", j12 "
                                    << mean["j12"] << ", j123 " << mean["j123"]);
  EXPECT_LT(mean["none"] + 0.05, mean["j12"]);  // the optimised grid gains points, as the paper's 8.3
  EXPECT_LT(mean["j12"], mean["j1"]);
  EXPECT_LT(mean["j12"], mean["j123"]);
  EXPECT_NEAR(mean["j123"], mean["j1"], 0.005);
  // and per region: every term ablation covers at least as much as the grid at shift 0, rotation 0
  for (const char* v : {"j1", "j12", "j123"})
    for (std::size_t k = 0; k < poc["none"].size(); ++k)
      EXPECT_GE(poc[v][k], poc["none"][k]) << v << " " << k;
}

TEST(DarpObjective, WithoutTheTurnMinimisingOrientationTheLoopsTurnMore) {
  // the paper's Fig. 9 on its own regions: the same grid and division, one tree orientation per region
  int with = 0, without = 0;
  for (int r : {2, 3, 8}) {
    json j = json::parse(roi_text(r));
    j["planner_params"] = {{"extend_legs", false}, {"shift_legs", false}};
    const Plan a = plan(parse_mission(j.dump()));
    j["planner_params"]["min_turn_orientation"] = false;
    const Plan b = plan(parse_mission(j.dump()));
    // the grid placement does not depend on the loops: the same grid, the same region
    EXPECT_EQ(a.diagnostics.at("grid").dump(), b.diagnostics.at("grid").dump());
    const int ta = a.uavs[0].turns, tb = b.uavs[0].turns;
    SCOPED_TRACE(r);
    EXPECT_GE(tb, ta);
    with += ta, without += tb;
  }
  EXPECT_GT(without, with);
}

TEST(DarpObjective, PaperJ1AloneChoosesTheMostNodesAmongTheEvaluatedPlacements) {
  for (int roi : {2, 5, 11}) {
    SCOPED_TRACE("roi " + std::to_string(roi));
    std::vector<Evaluated> seen;
    const darp::Output out = run_paper(roi_input(roi), 1, 0, 0, &seen);
    ASSERT_GT(seen.size(), 100u);
    double best_j = -std::numeric_limits<double>::infinity(), best_j1 = best_j;
    int best_cells = 0;
    for (const auto& e : seen) {
      best_j = std::max(best_j, e.s.J);
      EXPECT_DOUBLE_EQ(e.s.key, e.s.J) << "the paper's objective is J alone";
      EXPECT_TRUE(j_is(e.s, e.s.J1)) << e.s.J << " " << e.s.J1;
      if (e.s.J == e.s.J1)
        best_j1 = std::max(best_j1, e.s.J1), best_cells = std::max(best_cells, e.s.free_cells);
    }
    EXPECT_EQ(out.placement.J, best_j);
    EXPECT_EQ(out.placement.J, out.placement.J1) << "a connected grid is chosen";
    EXPECT_EQ(out.placement.J1, best_j1) << "the most nodes of the connected grids evaluated";
    int cells = 0;
    for (const auto& u : out.uavs) cells += u.cells;
    EXPECT_EQ(cells, best_cells);
  }
}

TEST(DarpObjective, PaperJWithoutCIgnoresJ3AndRaisingCDoesNotRaiseTheChosenJ3) {
  for (int roi : {2, 5, 11, 14}) {
    SCOPED_TRACE("roi " + std::to_string(roi));
    const darp::Input in = roi_input(roi);
    std::vector<Evaluated> seen0, seen1;
    const darp::Output c0 = run_paper(in, 0.68, 0.32, 0.0, &seen0);
    const darp::Output c1 = run_paper(in, 0.68, 0.32, 0.25, &seen1);
    // c = 0: J3 contributes nothing to any placement's J, and the chosen one has the largest J
    double best0 = -std::numeric_limits<double>::infinity(), best1 = best0;
    for (const auto& e : seen0) {
      EXPECT_TRUE(j_is(e.s, 0.68 * e.s.J1 + 0.32 * e.s.J2)) << e.s.J;
      best0 = std::max(best0, e.s.J);
    }
    for (const auto& e : seen1) {
      EXPECT_TRUE(j_is(e.s, 0.68 * e.s.J1 + 0.32 * e.s.J2 - 0.25 * e.s.J3)) << e.s.J;
      best1 = std::max(best1, e.s.J);
    }
    EXPECT_EQ(c0.placement.J, best0);
    EXPECT_EQ(c1.placement.J, best1);
    // the pre-scan lattice is the same for both weights: c = 0.25 charges J3 there
    ASSERT_GT(seen0.size(), 300u);
    for (std::size_t k = 0; k < 300; ++k) {
      ASSERT_EQ(seen0[k].sx, seen1[k].sx);
      ASSERT_EQ(seen0[k].th, seen1[k].th);
      EXPECT_NEAR(seen0[k].s.J - seen1[k].s.J, 0.25 * seen0[k].s.J3, 1e-12);
    }
    EXPECT_LE(c1.placement.J3, c0.placement.J3) << "c = 0 leaves the margins to chance; 0.25 evens them";
  }
}

TEST(DarpObjective, ExplicitDefaultsKeepThePlanAndThePaperObjectiveChangesIt) {
  const std::string text = roi_text(5);
  const Plan base = plan(parse_mission(text));
  json j = json::parse(text);
  j["planner_params"] = {
      {"objective", "uavcover"}, {"j_weight_a", 0.68}, {"j_weight_b", 0.32}, {"j_weight_c", 0.25}};
  const Plan same = plan(parse_mission(j.dump()));
  EXPECT_EQ(codec::paths_geojson(same).dump(), codec::paths_geojson(base).dump());

  j["planner_params"] = {
      {"objective", "paper"}, {"j_weight_a", 0.5}, {"j_weight_b", 0.5}, {"j_weight_c", 1.0}};
  const Plan paper = plan(parse_mission(j.dump()));
  EXPECT_NE(codec::paths_geojson(paper).dump(), codec::paths_geojson(base).dump());
  // the weights reach the placement: plan.json's J is a J1 + b J2 - c J3 with the mission's a, b, c
  const json& pl = paper.diagnostics.at("placement");
  const double J = pl.at("J"), J1 = pl.at("J1"), J2 = pl.at("J2"), J3 = pl.at("J3");
  EXPECT_TRUE(std::fabs(J - (0.5 * J1 + 0.5 * J2 - J3)) < 1e-9 ||
              std::fabs(J - (0.5 * J1 + 0.5 * J2 - J3 - 0.5)) < 1e-9)
      << pl.dump();
}

}  // namespace
}  // namespace uavcover::test
