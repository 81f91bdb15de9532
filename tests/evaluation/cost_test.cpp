// The time and cost model reproduces Tables 7 and 8 of Apostolidis et al. 2022 from their inputs.
#include <gtest/gtest.h>

#include "evaluation/cost.hpp"
#include "uavcover/error.hpp"

using namespace uavcover;
using namespace uavcover::evaluation;

namespace {

std::vector<Uav> fleet(int n) {
  Uav u;
  u.speed_mps = 3.0;
  u.endurance_min = 25.0;
  return std::vector<Uav>(static_cast<std::size_t>(n), u);
}

struct Row {
  int n;
  int batteries;
  double ft, dt, cbd, total, cost;
};

void check(const Row& row, double area) {
  SCOPED_TRACE("n = " + std::to_string(row.n));
  const auto c = evaluate_cost_from_durations(std::vector<double>(static_cast<std::size_t>(row.n), row.ft),
                                              fleet(row.n), area);
  EXPECT_EQ(c.batteries_per_uav, row.batteries);
  EXPECT_DOUBLE_EQ(c.flight_time_min, row.ft);
  EXPECT_NEAR(c.deployment_time_min, row.dt, 1e-9);
  EXPECT_NEAR(c.change_battery_delay_min, row.cbd, 0.011);
  EXPECT_NEAR(c.total_time_min, row.total, 0.011);
  EXPECT_NEAR(c.flight_cost_eur, row.cost, 0.0051);
  EXPECT_EQ(c.single_battery, row.batteries == 1);
}

}  // namespace

TEST(Cost, ReproducesTable7) {  // testbed #3, 222 720 m^2
  for (const Row& r : {Row{1, 1, 23.25, 8, 0, 31.25, 0.40}, Row{2, 1, 12.70, 11, 0, 23.70, 0.44},
                       Row{3, 1, 8.48, 14, 0, 22.48, 0.44}, Row{5, 1, 5.32, 20, 0, 25.32, 0.46},
                       Row{7, 1, 4.28, 26, 0, 30.28, 0.52}, Row{9, 1, 3.21, 32, 0, 35.21, 0.50},
                       Row{12, 1, 2.15, 41, 0, 43.15, 0.44}, Row{15, 1, 2.15, 50, 0, 52.15, 0.56}})
    check(r, 222720.0);
}

TEST(Cost, ReproducesTable8) {  // testbed #4, 1 814 063 m^2: several batteries
  for (const Row& r : {Row{1, 8, 193.13, 8, 55.92, 257.05, 3.93}, Row{2, 4, 96.50, 11, 32.97, 140.47, 4.15},
                       Row{3, 3, 65.07, 14, 27.98, 107.05, 4.50}, Row{5, 2, 39.98, 20, 19.99, 79.97, 4.91},
                       Row{7, 2, 28.46, 26, 25.99, 80.45, 6.20}, Row{9, 1, 22.28, 32, 0, 54.28, 3.45},
                       Row{12, 1, 16.97, 41, 0, 57.97, 3.51}, Row{15, 1, 13.78, 50, 0, 63.78, 3.56}})
    check(r, 1814063.0);
}

TEST(Cost, FlightDurationIsEquation15) {
  Uav u;
  u.speed_mps = 3.0;
  u.turn_c1 = 4.0;
  u.turn_c2 = 1.0;
  // 1800 m / 3 m/s = 600 s; 10 turns * 4 * 3 / 4 = 30 s -> 630 s
  EXPECT_DOUBLE_EQ(flight_duration_min(1800.0, 10, u), 10.5);
  const auto c = evaluate_cost({1800.0, 900.0}, {10, 0}, {u, u}, 1e4);
  ASSERT_EQ(c.uavs.size(), 2u);
  EXPECT_DOUBLE_EQ(c.uavs[1].flight_duration_min, 5.0);
  EXPECT_DOUBLE_EQ(c.flight_time_min, 10.5);
  EXPECT_DOUBLE_EQ(c.deployment_time_min, 11.0);
}

TEST(Cost, ConstantsAreConfigurable) {
  CostOptions o;
  o.deployment_base_min = 0.0;
  o.deployment_per_uav_min = 1.0;
  o.fcm_eur_per_min = 1.0;
  const auto c = evaluate_cost_from_durations({10.0, 20.0}, fleet(2), 1e4, o);
  EXPECT_DOUBLE_EQ(c.deployment_time_min, 2.0);
  EXPECT_DOUBLE_EQ(c.total_time_min, 22.0);
  EXPECT_DOUBLE_EQ(c.flight_cost_eur, 40.0);
}

TEST(Cost, PerUavEnduranceDecidesBatteries) {
  auto f = fleet(2);
  f[1].endurance_min = 10.0;
  const auto c = evaluate_cost_from_durations({20.0, 20.0}, f, 1e4);
  EXPECT_EQ(c.uavs[0].batteries, 1);
  EXPECT_EQ(c.uavs[1].batteries, 2);
  EXPECT_EQ(c.batteries_per_uav, 2);
  EXPECT_FALSE(c.single_battery);
}

TEST(Cost, RejectsBadInput) {
  EXPECT_THROW(evaluate_cost_from_durations({1.0}, fleet(2), 1e4), InputError);
  auto f = fleet(1);
  f[0].speed_mps = 0.0;
  EXPECT_THROW(evaluate_cost_from_durations({1.0}, f, 1e4), InputError);
}

TEST(GroundSpeed, HeadTailAndCrosswindFollowTheCrabbingModel) {
  const std::optional<Wind> west{Wind{8.0, 270.0}};  // from the west: travels east
  EXPECT_DOUBLE_EQ(ground_speed_mps(12.0, std::nullopt, 1.0, 0.0), 12.0);
  EXPECT_NEAR(ground_speed_mps(12.0, west, 100.0, 0.0), 20.0, 1e-9);                    // east: tailwind
  EXPECT_NEAR(ground_speed_mps(12.0, west, -100.0, 0.0), 4.0, 1e-9);                    // west: headwind
  EXPECT_NEAR(ground_speed_mps(12.0, west, 0.0, 50.0), std::sqrt(144.0 - 64.0), 1e-9);  // crosswind
  // an out-and-back leg pair takes longer in any wind than in calm air
  const double calm = 2 * 100.0 / 12.0;
  EXPECT_GT(
      100.0 / ground_speed_mps(12.0, west, 100.0, 0.0) + 100.0 / ground_speed_mps(12.0, west, -100.0, 0.0),
      calm);
  EXPECT_GT(2 * 100.0 / ground_speed_mps(12.0, west, 0.0, 100.0), calm);
  EXPECT_THROW(ground_speed_mps(8.0, west, 1.0, 0.0), InputError);
}

TEST(GroundSpeed, AirDistanceTimesEachLegAtItsGroundSpeed) {
  const std::vector<Point> line{{0, 0}, {300, 0}, {300, 400}, {0, 400}};
  EXPECT_EQ(air_length_m(line, 10.0, std::nullopt), 1000.0);  // calm air: the length itself
  EXPECT_EQ(air_length_m(line, 10.0, Wind{0.0, 90.0}), 1000.0);
  const std::optional<Wind> west{Wind{6.0, 270.0}};  // blows east
  // east 300 m at 16 m/s, north 400 m at 8 m/s, west 300 m at 4 m/s: (18.75 + 50 + 75) s at 10 m/s
  EXPECT_NEAR(air_length_m(line, 10.0, west), 10.0 * (300.0 / 16 + 400.0 / 8 + 300.0 / 4), 1e-9);
  EXPECT_NEAR(air_distance_m({0, 0}, {300, 0}, 10.0, west), 187.5, 1e-9);
}
