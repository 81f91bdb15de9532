// Property tests of the DARP planner (issue 3) over generated scenarios, several seeds each.
#include <gtest/gtest.h>

#include "planners/darp/darp_props.hpp"

#include <algorithm>

#include "support/hard_shapes.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover::test {
namespace {

struct Scenario {
  std::string name;
  MultiPolygon area, nfz;
  std::vector<Point> starts;
  std::vector<double> shares;
  double ds = 25;
  bool expect_converged = true;
};

Scenario proportional_three() {
  return {"15/40/45", {rect(0, 0, 1200, 900)}, {}, {{50, 50}, {1150, 50}, {600, 850}}, {0.15, 0.40, 0.45}};
}
Scenario pair_60_40() {
  // L-shaped field
  return {"60/40 L",
          {poly({{0, 0}, {1000, 0}, {1000, 400}, {450, 400}, {450, 900}, {0, 900}})},
          {},
          {{100, 100}, {900, 300}},
          {0.6, 0.4}};
}
Scenario two_pylons() {
  return {"pylons",
          {rect(0, 0, 1000, 600)},
          {rect(290, 290, 320, 320), rect(690, 280, 720, 310)},
          {{20, 20}, {980, 580}, {500, 20}},
          {1.0 / 3, 1.0 / 3, 1.0 / 3}};
}
Scenario ten_uavs() {
  Scenario s{"10 UAVs, 2 NFZs",
             {rect(0, 0, 1500, 1000)},
             {rect(300, 300, 500, 420), rect(950, 600, 1100, 800)},
             {},
             {},
             25};
  for (int i = 0; i < 10; ++i) {
    s.starts.push_back({75.0 + 150.0 * i, i % 2 ? 950.0 : 50.0});
    s.shares.push_back(i < 5 ? 0.12 : 0.08);
  }
  return s;
}
Scenario concave() {
  // a comb-like concave field with a hole-free notch
  return {"concave",
          {poly({{0, 0}, {900, 0}, {900, 700}, {700, 700}, {700, 250}, {520, 250}, {520, 700}, {0, 700}})},
          {rect(150, 300, 260, 420)},
          {{50, 50}, {800, 650}, {100, 650}, {450, 100}},
          {0.25, 0.25, 0.25, 0.25}};
}

class DarpScenario : public ::testing::TestWithParam<std::tuple<int, int, int>> {};

TEST_P(DarpScenario, PropertiesHold) {
  const auto [which, seed, mode_i] = GetParam();
  const Scenario sc =
      std::vector<Scenario (*)()>{proportional_three, pair_60_40, two_pylons, ten_uavs, concave}[which]();
  const Mode mode = mode_i ? Mode::Coverage : Mode::Strict;
  const darp::Input in = make_input(sc.area, sc.nfz, sc.starts, sc.shares, sc.ds, mode, seed);
  const darp::Output out = darp::run(in, darp::Options{}, Context{});
  SCOPED_TRACE(sc.name);
  check_plan(in, out, sc.expect_converged);
  for (const auto& u : out.uavs) EXPECT_EQ(u.loops.size(), 1u) << sc.name;  // connected free space
}

INSTANTIATE_TEST_SUITE_P(Scenarios, DarpScenario,
                         ::testing::Combine(::testing::Range(0, 5), ::testing::Values(1, 7, 42),
                                            ::testing::Values(0, 1)));

TEST(Darp, SameSeedSameOutput) {
  const Scenario sc = ten_uavs();
  const darp::Input in = make_input(sc.area, sc.nfz, sc.starts, sc.shares, sc.ds, Mode::Strict, 5);
  const darp::Output a = darp::run(in, darp::Options{}, Context{});
  const darp::Output b = darp::run(in, darp::Options{}, Context{});
  EXPECT_TRUE(same_output(a, b));
}

TEST(Darp, DisconnectedAreaIsShared) {
  // two fields 200 m apart, all three UAVs start in the first one
  MultiPolygon area{rect(0, 0, 600, 600), rect(800, 0, 1200, 400)};
  for (int seed : {1, 2, 3}) {
    const darp::Input in = make_input(area, {}, {{50, 50}, {550, 50}, {300, 550}},
                                      {1.0 / 3, 1.0 / 3, 1.0 / 3}, 25, Mode::Strict, seed);
    const darp::Output out = darp::run(in, darp::Options{}, Context{});
    check_plan(in, out, false);
    int loops = 0;
    for (const auto& u : out.uavs) loops += static_cast<int>(u.loops.size());
    EXPECT_EQ(loops, 4);  // three regions in the first field, the second flown whole by one UAV
    // shares hold as well as the split allows: the second field (64 cells of 208) is close to a third
    for (const auto& u : out.uavs) EXPECT_NEAR(u.share_actual, 1.0 / 3, 0.05);
  }
}

TEST(Darp, NoFlyZoneCuttingTheArea) {
  // a no-fly band cuts the field in two; both parts are planned and no path crosses the band
  MultiPolygon area{rect(0, 0, 1000, 500)};
  MultiPolygon nfz{rect(480, -10, 530, 510)};
  const darp::Input in = make_input(area, nfz, {{50, 50}, {950, 450}}, {0.5, 0.5}, 25, Mode::Strict, 3);
  const darp::Output out = darp::run(in, darp::Options{}, Context{});
  // the parts differ by more than the tolerance: the UAV of the smaller part also takes a piece
  // of the larger one, so the shares hold
  check_plan(in, out, true);
  EXPECT_EQ(out.uavs[0].loops.size(), 1u);
  EXPECT_GE(out.uavs[1].loops.size(), 1u);
  EXPECT_LT(out.uavs[0].loops[0].front().x(), 480);
  EXPECT_GT(out.uavs[1].loops[0].front().x(), 530);  // its own part first
}

TEST(Darp, StartOutsideTheArea) {
  MultiPolygon area{rect(0, 0, 500, 500)};
  const darp::Input in = make_input(area, {}, {{-300, -300}, {800, 250}}, {0.5, 0.5}, 25, Mode::Strict, 1);
  const darp::Output out = darp::run(in, darp::Options{}, Context{});
  check_plan(in, out, true);
  EXPECT_TRUE(out.warnings.empty()) << "taking off beside the field is normal: " << out.warnings.front();
  // the loop starts near the corner closest to the outside start
  EXPECT_LT(out.uavs[0].loops[0].front().x(), 100);
  EXPECT_LT(out.uavs[0].loops[0].front().y(), 100);
}

// Issue 26's star (tests/support/hard_shapes.hpp), 3 UAVs taking off outside it: the bottom-left UAV's
// nearest cell is in the star's point, whose only link leads into the cell the bottom UAV's start took.
// It held that one cell (1 of 18 for a target of 6, 27.8 points off); the bottom UAV's start now moves to
// the nearest cell that walls nobody in (3 / 8 / 7 cells, 17.0 points), and the transfers after the
// division, free to hand over a start cell of a UAV from outside the area, reach 6 / 6 / 6.
TEST(Darp, AStartOutsideTheAreaDoesNotWallAnotherUavIn) {
  for (const auto& shape : uavcover::testing::hard_shapes()) {
    if (shape.name != "star") continue;
    nlohmann::json j = shape.mission;
    j["planner"] = "darp";
    const Plan p = plan(parse_mission(j.dump()));
    for (const auto& u : p.uavs) EXPECT_NEAR(u.share_actual, 1.0 / 3.0, 1e-9) << u.id << ": 6 of 18 cells";
    EXPECT_TRUE(p.warnings.empty()) << p.warnings.front();
    const std::vector<double> own = uavcover::testing::own_region_coverage(p);
    EXPECT_GE(*std::min_element(own.begin(), own.end()), 0.97);
    return;
  }
  FAIL() << "no star among the hard shapes";
}

TEST(Darp, StartInsideTheAreaButOnNoFreeCellIsWarned) {
  // a 20 m wide strip sticks out of the field: in strict mode no 50 m mega-cell fits in it
  MultiPolygon area;
  bg::union_(MultiPolygon{rect(0, 0, 500, 500)}, MultiPolygon{rect(500, 240, 700, 260)}, area);
  const darp::Input in = make_input(area, {}, {{650, 250}, {100, 100}}, {0.5, 0.5}, 25, Mode::Strict, 1);
  const darp::Output out = darp::run(in, darp::Options{}, Context{});
  check_plan(in, out, true);
  ASSERT_EQ(out.warnings.size(), 1u);
  EXPECT_NE(out.warnings[0].find("UAV 1"), std::string::npos) << out.warnings[0];
}

TEST(Darp, NoFreeCellIsAnInputError) {
  MultiPolygon area{rect(0, 0, 20, 20)};
  const darp::Input in = make_input(area, {}, {{10, 10}}, {1.0}, 25, Mode::Strict, 1);
  EXPECT_THROW(darp::run(in, darp::Options{}, Context{}), InputError);
}

TEST(Darp, ProgressIsReported) {
  const Scenario sc = proportional_three();
  const darp::Input in = make_input(sc.area, sc.nfz, sc.starts, sc.shares, sc.ds, Mode::Strict, 1);
  std::vector<std::string> stages;
  darp::run(in, darp::Options{}, Context([&](std::string_view s, double f) {
              EXPECT_GE(f, 0.0);
              EXPECT_LE(f, 1.0);
              if (stages.empty() || stages.back() != s) stages.emplace_back(s);
            }));
  EXPECT_EQ(stages, (std::vector<std::string>{"placement", "darp", "stc"}));
}

}  // namespace
}  // namespace uavcover::test
