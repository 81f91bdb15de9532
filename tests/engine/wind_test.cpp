// Wind-aware planning and shares from capabilities (issue 32, docs/wind.md): the sweep direction with
// the least flight time in the mission's wind, battery sorties timed at each leg's ground speed, and
// shares from each UAV's area rate so that a heterogeneous fleet finishes together.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "codec/plan_codec.hpp"
#include "evaluation/evaluate.hpp"
#include "geometry/geometry.hpp"
#include "sorties/sorties.hpp"
#include "support/shapes.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"

using namespace uavcover;
using nlohmann::json;
using uavcover::testing::zone_lattice_point;

namespace {

json geo_rect(double x0, double y0, double x1, double y1) {
  auto p = [](double x, double y) {
    const LonLat q = zone_lattice_point(x, y);
    return json::array({q.lon, q.lat});
  };
  return {{"type", "Polygon"}, {"coordinates", {{p(x0, y0), p(x1, y0), p(x1, y1), p(x0, y1), p(x0, y0)}}}};
}

json pos(double x, double y) {
  const LonLat q = zone_lattice_point(x, y);
  return json::array({q.lon, q.lat});
}

/// 1200 m east-west x 400 m north-south, one UAV at 10 m/s starting at the south-west corner, lines 40 m
/// apart: in calm air the fewest turns are east-west legs.
json field() {
  return {{"area", geo_rect(0, 0, 1200, 400)},
          {"spacing_m", 40},
          {"uavs", {{{"id", "a"}, {"speed_mps", 10}, {"endurance_min", 300}, {"start", pos(-20, -20)}}}},
          {"planner", "boustrophedon"},
          {"seed", 1}};
}

/// Length-weighted share of the coverage legs running within 20 degrees of east-west.
double east_west_fraction(const Plan& p) {
  double ew = 0, all = 0;
  for (const auto& u : p.uavs)
    for (const auto& part : u.parts) {
      if (part.kind != PartKind::Coverage) continue;
      for (std::size_t i = 1; i < part.local.size(); ++i) {
        const double dx = part.local[i].x() - part.local[i - 1].x(),
                     dy = part.local[i].y() - part.local[i - 1].y();
        const double len = std::hypot(dx, dy);
        all += len;
        if (std::abs(dy) < std::tan(20 * M_PI / 180) * std::abs(dx)) ew += len;
      }
    }
  return all > 0 ? ew / all : 0;
}

/// The evaluator's flight time (eq. 17) of `p` in `wind`.
double flight_time_in(Plan p, std::optional<Wind> wind) {
  p.mission.wind = wind;
  evaluation::EvaluateOptions eo;
  eo.compute_coverage = false;
  return evaluation::evaluate_plan(p, eo).cost.flight_time_min;
}

}  // namespace

// A wind along the long side: legs into and with it cost 2Lv/(v^2-w^2) a pair, across it 2L/sqrt(v^2-w^2),
// so the planner flies north-south legs across the wind although they need three times the turns.
TEST(WindPlanning, BoustrophedonSweepsAcrossAStrongWindWhenThatIsFaster) {
  const Plan calm = plan(parse_mission(field().dump()));
  EXPECT_GT(east_west_fraction(calm), 0.9) << "calm air: the fewest turns, legs along the long side";
  EXPECT_FALSE(calm.diagnostics.contains("wind_sweep"));

  json j = field();
  j["wind"] = {{"speed_mps", 8}, {"from_deg", 270}};  // from the west
  const Plan windy = plan(parse_mission(j.dump()));
  EXPECT_LT(east_west_fraction(windy), 0.2) << "in wind: legs across it";
  ASSERT_TRUE(windy.diagnostics.contains("wind_sweep"));
  EXPECT_EQ(windy.diagnostics["wind_sweep"]["angle_deg"], 0.0);  // north-south, across a west wind
  const Wind w{8, 270};
  const double chosen = flight_time_in(windy, w), calm_plan = flight_time_in(calm, w);
  std::printf("calm air's east-west legs in the wind: %.2f min; the chosen sweep (angle %s): %.2f min\n",
              calm_plan, windy.diagnostics["wind_sweep"]["angle_deg"].dump().c_str(), chosen);
  // the calm plan's legs along the wind: 10 pairs of 1200 m at 18 and 2 m/s, about 55 min
  EXPECT_GT(calm_plan, 50.0);
  EXPECT_LT(chosen, 0.9 * calm_plan) << chosen << " min against " << calm_plan << " min";
  EXPECT_NEAR(windy.diagnostics["wind_sweep"]["flight_time_min"].get<double>(), chosen, 1e-9);
  // the user's parameters are kept as given: the search is deterministic, the plan repeats
  EXPECT_TRUE(windy.mission.planner_params["angle_deg"].is_null());
  const Plan again = plan(windy.mission);
  ASSERT_EQ(again.uavs[0].parts.size(), windy.uavs[0].parts.size());
  EXPECT_DOUBLE_EQ(again.uavs[0].length_m, windy.uavs[0].length_m);

  // a given angle_deg is flown as given
  j["planner_params"] = {{"angle_deg", 90}};
  EXPECT_GT(east_west_fraction(plan(parse_mission(j.dump()))), 0.9);
}

// "planner": "auto" in wind: the planners with a free sweep direction search it inside auto too, so the
// winner is at least as fast as boustrophedon's own search (auto had planned each candidate once, in
// the calm-air direction, and boustrophedon's candidate flew the legs along the wind).
TEST(WindPlanning, AutoSearchesTheSweepDirectionOfItsCandidates) {
  json j = field();
  j["wind"] = {{"speed_mps", 8}, {"from_deg", 270}};
  const Plan boustro = plan(parse_mission(j.dump()));
  j["planner"] = "auto";
  const Plan chosen = plan(parse_mission(j.dump()));
  const Wind w{8, 270};
  const double t_auto = flight_time_in(chosen, w), t_boustro = flight_time_in(boustro, w);
  std::printf("auto in wind: %s, %.2f min; boustrophedon's own search: %.2f min\n", chosen.planner.c_str(),
              t_auto, t_boustro);
  EXPECT_LE(t_auto, t_boustro + 1e-6);
  const auto& rows = chosen.selection["candidates"];
  bool boustro_row = false;
  for (const auto& r : rows)
    if (r["planner"] == "boustrophedon" && r.contains("figures")) {
      boustro_row = true;
      EXPECT_NEAR(r["figures"]["time_min"].get<double>(),
                  boustro.diagnostics["wind_sweep"]["flight_time_min"].get<double>(), 1e-6)
          << "auto's boustrophedon candidate is the direction search's plan";
    }
  EXPECT_TRUE(boustro_row);
  if (chosen.planner == "boustrophedon" || chosen.planner == "milp") {
    EXPECT_TRUE(chosen.diagnostics.contains("wind_sweep"));
  }
  // deterministic: the same mission and seed give the same plan
  const Plan again = plan(parse_mission(j.dump()));
  EXPECT_EQ(again.planner, chosen.planner);
  EXPECT_DOUBLE_EQ(flight_time_in(again, w), t_auto);
}

// A wind of 0 m/s plans exactly as calm air.
TEST(WindPlanning, AZeroWindPlansAsCalmAir) {
  json j = field();
  const Plan calm = plan(parse_mission(j.dump()));
  j["wind"] = {{"speed_mps", 0}, {"from_deg", 90}};
  const Plan zero = plan(parse_mission(j.dump()));
  ASSERT_EQ(zero.uavs[0].parts.size(), calm.uavs[0].parts.size());
  EXPECT_DOUBLE_EQ(zero.uavs[0].length_m, calm.uavs[0].length_m);
  EXPECT_DOUBLE_EQ(zero.uavs[0].expected_finish_min, calm.uavs[0].expected_finish_min);
}

// Sorties in wind: every sortie is timed at its legs' ground speeds (checked here leg by leg with the
// wind triangle) and fits one battery; the headwind legs make it need more sorties than in calm air.
TEST(WindPlanning, SortiesAreTimedAtGroundSpeedAndFitOneBattery) {
  json j = field();
  j["uavs"][0]["endurance_min"] = 11;         // a leg with its transits, climbs and descents in one battery
  j["planner_params"] = {{"angle_deg", 90}};  // legs along the wind
  const Plan calm = plan(parse_mission(j.dump()));
  j["wind"] = {{"speed_mps", 6}, {"from_deg", 270}};
  const Plan windy = plan(parse_mission(j.dump()));
  const Uav& u = windy.mission.uavs[0];
  const double budget = sorties::budget_min(windy, 0);
  ASSERT_FALSE(windy.uavs[0].sorties.empty());
  for (const auto& s : windy.uavs[0].sorties) {
    double seconds = 0;
    for (const auto& part : s.parts)
      for (std::size_t i = 1; i < part.local.size(); ++i) {
        const double dx = part.local[i].x() - part.local[i - 1].x(),
                     dy = part.local[i].y() - part.local[i - 1].y();
        const double len = std::hypot(dx, dy);
        if (len == 0) continue;
        // wind from the west blows east: ground speed w cos(phi) + sqrt(v^2 - w^2 sin^2(phi))
        const double c = dx / len, sn = dy / len;
        seconds += len / (6 * c + std::sqrt(100 - 36 * sn * sn));
      }
    const double expected = (seconds + s.turns * u.turn_c1 * u.speed_mps / (u.turn_c2 + u.speed_mps)) / 60;
    EXPECT_NEAR(s.duration_min, expected, 1e-9 * expected) << "sortie " << s.index;
    EXPECT_LE(s.duration_min + sorties::vertical_min(windy, 0, s), budget * (1 + 1e-9))
        << "sortie " << s.index;
  }
  std::printf("sorties along a 6 m/s wind: %zu (calm air: %zu)\n", windy.uavs[0].sorties.size(),
              calm.uavs[0].sorties.size());
  EXPECT_GT(windy.uavs[0].sorties.size(), calm.uavs[0].sorties.size());
}

// Shares from capabilities (Mondinelli's heterogeneous swarms): a fast UAV with a wide camera, a medium
// one and a slow one with a narrow camera, every share "auto": the evaluator's finish times (eq. 15 in
// wind plus eq. 19's battery changes) agree within 5 %, and plan.json's expected_finish_min matches the
// evaluation of the plan read back.
TEST(CapabilityShares, AFastAMediumAndASlowUavFinishTogether) {
  const json cam = {{"altitude_m", 40}, {"hfov_deg", 60}, {"overlap", 0.2}};
  json wide = cam, narrow = cam;
  wide["hfov_deg"] = 80;
  narrow["hfov_deg"] = 55;
  json j = {{"area", geo_rect(0, 0, 1500, 1000)},
            {"camera", cam},
            {"uavs",
             {{{"id", "fast"},
               {"speed_mps", 15},
               {"endurance_min", 60},
               {"camera", wide},
               {"start", pos(0, -30)},
               {"share", "auto"}},
              {{"id", "medium"},
               {"speed_mps", 9},
               {"endurance_min", 60},
               {"start", pos(750, -30)},
               {"share", "auto"}},
              {{"id", "slow"},
               {"speed_mps", 4},
               {"endurance_min", 60},
               {"camera", narrow},
               {"start", pos(1500, -30)},
               {"share", "auto"}}}},
            {"wind", {{"speed_mps", 2}, {"from_deg", 200}}},
            {"planner", "boustrophedon"},
            {"seed", 4}};
  const Mission m = parse_mission(j.dump());
  for (const auto& u : m.uavs) EXPECT_TRUE(u.share_auto);
  const Plan p = plan(m);
  ASSERT_EQ(p.uavs.size(), 3u);
  // the shares follow the area rates: fast > medium > slow
  EXPECT_GT(p.uavs[0].share_requested, p.uavs[1].share_requested);
  EXPECT_GT(p.uavs[1].share_requested, p.uavs[2].share_requested);
  EXPECT_NEAR(p.uavs[0].share_requested + p.uavs[1].share_requested + p.uavs[2].share_requested, 1.0, 1e-9);

  // read back from plan.json and evaluated there
  const Plan back = codec::load_plan(codec::plan_json(p), codec::paths_geojson(p));
  const auto ev = evaluation::evaluate_plan(back);
  double lo = 1e300, hi = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    // the whole flight: eq. 15, the battery changes, and the missions' climbs and descents
    EXPECT_GT(back.uavs[i].vertical_time_s, 0.0) << p.uavs[i].id;
    const double t = ev.cost.uavs[i].flight_duration_min + ev.cost.uavs[i].change_battery_delay_min +
                     back.uavs[i].vertical_time_s / 60.0;
    lo = std::min(lo, t);
    hi = std::max(hi, t);
    EXPECT_NEAR(back.uavs[i].expected_finish_min, t, 0.05 * t) << p.uavs[i].id;
    EXPECT_GT(t, 5.0) << p.uavs[i].id;
  }
  std::printf("auto shares %.3f %.3f %.3f: evaluated finish %.2f to %.2f min (spread %.1f %%)\n",
              p.uavs[0].share_requested, p.uavs[1].share_requested, p.uavs[2].share_requested, lo, hi,
              100 * (hi - lo) / hi);
  EXPECT_LT((hi - lo) / hi, 0.05) << "finish times from " << lo << " to " << hi << " min; "
                                  << p.diagnostics["capability_shares"].dump();
  EXPECT_GT(ev.coverage.total.poc, 0.95);

  // equal shares leave the slow UAV far behind
  for (auto& u : j["uavs"]) u.erase("share");
  const Plan equal = plan(parse_mission(j.dump()));
  const auto eq = evaluation::evaluate_plan(equal);
  std::printf("equal shares: flight durations %.2f %.2f %.2f min\n", eq.cost.uavs[0].flight_duration_min,
              eq.cost.uavs[1].flight_duration_min, eq.cost.uavs[2].flight_duration_min);
  EXPECT_GT(eq.cost.uavs[2].flight_duration_min, 2.0 * eq.cost.uavs[0].flight_duration_min);
}

// "shares": "capability" sets every UAV's share to "auto"; the refusals name the field.
TEST(CapabilityShares, MissionLevelCapabilityAndRefusals) {
  json j = field();
  j["uavs"] = {{{"id", "a"}, {"speed_mps", 10}}, {{"id", "b"}, {"speed_mps", 5}}};
  j["shares"] = "capability";
  const Mission m = parse_mission(j.dump());
  EXPECT_TRUE(m.uavs[0].share_auto && m.uavs[1].share_auto);
  const Plan p = plan(m);
  EXPECT_GT(p.uavs[0].share_requested, 1.5 * p.uavs[1].share_requested);
  EXPECT_TRUE(p.diagnostics.contains("capability_shares"));
  // round trip: mission_to_json writes "share": "auto"
  const Mission again = parse_mission(mission_to_json(m));
  EXPECT_TRUE(again.uavs[0].share_auto && again.uavs[1].share_auto);

  auto refused = [](const json& bad, const std::string& field) {
    try {
      parse_mission(bad.dump());
      ADD_FAILURE() << "accepted: " << bad.dump();
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  json bad = j;
  bad["shares"] = "equal";
  refused(bad, "shares");
  bad = j;
  bad["uavs"][1]["share"] = 0.3;
  refused(bad, "uavs[1].share");
  bad = field();
  bad["uavs"][0]["share"] = "fast";
  refused(bad, "uavs[0].share");
}
