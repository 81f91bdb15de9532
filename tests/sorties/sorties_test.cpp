// Battery sorties and resume (docs/sorties.md) on planned missions: the olive grove example, a
// rectangle of the thesis and a region of the paper's evaluation.
#include "sorties/sorties.hpp"
#include "codec/plan_codec.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include "evaluation/cost.hpp"
#include "evaluation/evaluate.hpp"
#include "export/checks.hpp"
#include "export/export.hpp"
#include "geometry/geometry.hpp"
#include "io/plan_io.hpp"
#include "json/strict.hpp"
#include "support/files.hpp"
#include "support/shapes.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"
#include "uavcover/vehicle.hpp"
#include "usecases/study.hpp"
#include "waypoints/vertical.hpp"

namespace uavcover {
namespace {

using nlohmann::json;

/// The olive grove example, its UAVs climbing and descending at 30 m/s: the tests of the cut's rules
/// (boundaries, transits, resume, exports) keep figures that eq. 15 gives, a few seconds of climbs and
/// descents apart; EverySortieFitsWithItsClimbsAndDescents sets real vertical speeds.
const Plan& olive_grove() {
  static const Plan p = [] {
    Mission m = parse_mission(
        testing::slurp(std::filesystem::path(UAVCOVER_SOURCE_DIR) / "examples" / "olive-grove.json"));
    for (auto& u : m.uavs) u.climb_mps = u.descent_mps = 30.0;
    return plan(m);
  }();
  return p;
}

/// The olive grove with every UAV's endurance set to `minutes` and the sorties cut again.
Plan with_endurance(const Plan& base, double minutes, double reserve = kDefaultBatteryReserve) {
  Plan p = base;
  for (auto& u : p.mission.uavs) u.endurance_min = minutes;
  p.mission.battery_reserve = reserve;
  sorties::fill_sorties(p);
  return p;
}

/// Coverage legs (consecutive waypoints of one coverage part) of a list of parts, as coordinates.
std::multiset<std::pair<std::pair<double, double>, std::pair<double, double>>> legs_of(
    const std::vector<PathPart>& parts) {
  std::multiset<std::pair<std::pair<double, double>, std::pair<double, double>>> out;
  // a sortie's lead-in (issue 31: the stretch before its first waypoint, flown again) is not its own work
  for (const auto& part : parts)
    if (part.kind == PartKind::Coverage)
      for (std::size_t k = part.lead_in + 1; k < part.local.size(); ++k)
        out.insert({{part.local[k - 1].x(), part.local[k - 1].y()}, {part.local[k].x(), part.local[k].y()}});
  return out;
}

std::vector<Point> coverage_points(const std::vector<PathPart>& parts) {
  std::vector<Point> out;
  for (const auto& part : parts)
    if (part.kind == PartKind::Coverage)
      out.insert(out.end(), part.local.begin() + static_cast<long>(part.lead_in), part.local.end());
  return out;
}

bool same(Point a, Point b) { return a.x() == b.x() && a.y() == b.y(); }

/// Every property a UAV's sorties must have (docs/sorties.md).
void expect_valid_sorties(const Plan& p, std::size_t i) {
  SCOPED_TRACE("uav " + p.uavs[i].id);
  const UavPlan& up = p.uavs[i];
  const Uav& u = p.mission.uavs[i];
  const auto wps = sorties::coverage_waypoints(up);
  const std::vector<Point> all = coverage_points(up.parts);
  ASSERT_EQ(all.size(), wps.size());
  ASSERT_FALSE(up.sorties.empty());
  const double budget = u.endurance_min * (1.0 - p.mission.battery_reserve);
  const geodesy::LocalFrame frame(p.origin);
  const Point start = frame.to_local(u.start_resolved);
  std::vector<Point> joined;
  std::multiset<std::pair<std::pair<double, double>, std::pair<double, double>>> legs;
  for (std::size_t k = 0; k < up.sorties.size(); ++k) {
    const Sortie& s = up.sorties[k];
    EXPECT_EQ(s.index, static_cast<int>(k));
    // fits one battery, with the evaluator's time model and the sortie's climbs and descents
    EXPECT_LE(s.duration_min + sorties::vertical_min(p, i, s), budget * (1 + 1e-9));
    double len = 0;
    for (const auto& part : s.parts) len += geometry::length(part.local);
    EXPECT_NEAR(s.length_m, len, 1e-6);
    EXPECT_EQ(s.turns, s.last_waypoint - s.first_waypoint + 1);
    EXPECT_DOUBLE_EQ(s.duration_min, evaluation::flight_duration_min(s.length_m, s.turns, u));
    // from take-off and back to it
    ASSERT_FALSE(s.parts.empty());
    EXPECT_LT(bg::distance(s.parts.front().local.front(), start), 0.01);
    EXPECT_LT(bg::distance(s.parts.back().local.back(), start), 0.01);
    // its coverage waypoints are the plan's first..last
    const std::vector<Point> cov = coverage_points(s.parts);
    ASSERT_EQ(cov.size(), static_cast<std::size_t>(s.turns));
    for (int g = s.first_waypoint; g <= s.last_waypoint; ++g)
      EXPECT_TRUE(
          same(cov[static_cast<std::size_t>(g - s.first_waypoint)], all[static_cast<std::size_t>(g)]));
    // boundaries at turning waypoints: shared inside a coverage part, else the next part's first
    if (k == 0) {
      EXPECT_EQ(s.first_waypoint, 0);
    } else {
      const Sortie& prev = up.sorties[k - 1];
      const auto end = static_cast<std::size_t>(prev.last_waypoint);
      const bool part_end = end + 1 == wps.size() || wps[end + 1].part != wps[end].part;
      EXPECT_EQ(s.first_waypoint, part_end ? prev.last_waypoint + 1 : prev.last_waypoint);
    }
    for (std::size_t q = k == 0 ? 0 : (up.sorties[k - 1].last_waypoint == s.first_waypoint ? 1 : 0);
         q < cov.size(); ++q)
      joined.push_back(cov[q]);
    const auto l = legs_of(s.parts);
    legs.insert(l.begin(), l.end());
  }
  EXPECT_EQ(up.sorties.back().last_waypoint, static_cast<int>(wps.size()) - 1);
  // together: exactly the UAV's coverage waypoints in order, and every coverage leg once
  ASSERT_EQ(joined.size(), all.size());
  for (std::size_t g = 0; g < all.size(); ++g) EXPECT_TRUE(same(joined[g], all[g])) << g;
  EXPECT_EQ(legs, legs_of(up.parts));
}

TEST(Sorties, OneBatteryGivesOneSortieWhosePathIsThePlans) {
  const Plan& p = olive_grove();
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    const UavPlan& up = p.uavs[i];
    SCOPED_TRACE(up.id);
    ASSERT_EQ(up.sorties.size(), 1u);
    const Sortie& s = up.sorties.front();
    ASSERT_EQ(s.parts.size(), up.parts.size());
    for (std::size_t k = 0; k < s.parts.size(); ++k) {
      EXPECT_EQ(s.parts[k].kind, up.parts[k].kind);
      ASSERT_EQ(s.parts[k].local.size(), up.parts[k].local.size());
      for (std::size_t v = 0; v < s.parts[k].local.size(); ++v) {
        EXPECT_TRUE(same(s.parts[k].local[v], up.parts[k].local[v]));
        EXPECT_EQ(s.parts[k].wgs84[v].lon, up.parts[k].wgs84[v].lon);
        EXPECT_EQ(s.parts[k].wgs84[v].lat, up.parts[k].wgs84[v].lat);
      }
    }
    EXPECT_NEAR(s.length_m, up.length_m, 1e-6);
    EXPECT_EQ(s.turns, up.turns);
    expect_valid_sorties(p, i);
  }
  // the evaluator: one battery per sortie, as eq. 16 gives for one battery
  const auto ev = evaluation::evaluate_plan(p, {.coverage = {}, .cost = {}, .compute_coverage = false});
  for (std::size_t i = 0; i < p.uavs.size(); ++i) EXPECT_EQ(ev.cost.uavs[i].batteries, 1);
}

TEST(Sorties, ShortEnduranceCutsAtTurningWaypointsWithinTheBattery) {
  const Plan p = with_endurance(olive_grove(), 12.0);
  const auto ev = evaluation::evaluate_plan(p, {.coverage = {}, .cost = {}, .compute_coverage = false});
  std::ostringstream counts;
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    expect_valid_sorties(p, i);
    // alpha's 9 min fit one battery; bravo and charlie need several
    EXPECT_EQ(p.uavs[i].sorties.size() > 1, p.uavs[i].id != "alpha");
    // the time/cost model counts one battery per sortie
    EXPECT_EQ(ev.cost.uavs[i].batteries, static_cast<int>(p.uavs[i].sorties.size()));
    // at least what eq. 16 asks for the continuous flight with the reserve
    EXPECT_GE(static_cast<double>(p.uavs[i].sorties.size()),
              std::ceil(ev.cost.uavs[i].flight_duration_min / (12.0 * 0.8) - 1e-9));
    counts << p.uavs[i].id << " " << p.uavs[i].sorties.size() << " sorties ("
           << ev.cost.uavs[i].flight_duration_min << " min continuous); ";
  }
  std::cout << "olive grove at endurance 12 min, reserve 20 %: " << counts.str() << "\n";
}

TEST(Sorties, NoReserveAndSeveralReservesStayValid) {
  // budgets of 9.6 to 10.35 min: above the longest leg with its transits
  for (const auto& [reserve, minutes] : std::vector<std::pair<double, double>>{
           {0.0, 10.0}, {0.1, 11.5}, {0.35, 15.5}, {0.6, 25.0}, {0.0, 40.0}}) {
    SCOPED_TRACE(std::to_string(reserve) + " " + std::to_string(minutes));
    const Plan p = with_endurance(olive_grove(), minutes, reserve);
    for (std::size_t i = 0; i < p.uavs.size(); ++i) expect_valid_sorties(p, i);
  }
}

TEST(Sorties, PlanKeepsWorkingWhenALegDoesNotFit) {
  // ROI 5 of the paper at 25 min: one leg with its transits needs more than 20 min; the plan is still
  // made, without sorties for that UAV and with a warning, and the cost model keeps eq. 16
  const Plan p = plan(parse_mission(testing::roi_text("roi05.json")));
  ASSERT_EQ(p.uavs.size(), 1u);
  EXPECT_TRUE(p.uavs[0].sorties.empty());
  bool warned = false;
  for (const auto& w : p.warnings) warned = warned || w.find("no battery sorties") != std::string::npos;
  EXPECT_TRUE(warned);
  const auto ev = evaluation::evaluate_plan(p, {.coverage = {}, .cost = {}, .compute_coverage = false});
  EXPECT_EQ(ev.cost.uavs[0].batteries,
            static_cast<int>(
                std::ceil(ev.cost.uavs[0].flight_duration_min / p.mission.uavs[0].endurance_min - 1e-9)));
  // per-sortie exports refuse it, naming the UAV
  exporting::ExportOptions opt;
  opt.per_sortie = true;
  EXPECT_THROW((void)exporting::export_artifacts(p, {"qgc"}, opt), InputError);
}

TEST(Sorties, ALegTooLongForOneBatteryNamesTheUav) {
  Plan p = olive_grove();
  p.mission.uavs[1].endurance_min = 0.2;
  try {
    sorties::fill_sorties(p);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "uavs[1].endurance_min");
    EXPECT_NE(std::string(e.what()).find("\"bravo\""), std::string::npos) << e.what();
  }
}

/// `base` with UAV i's coverage part split before the given vertices into coverage parts, each joined
/// to the next by the straight transit between the neighbouring vertices (the same path).
Plan split_coverage(const Plan& base, std::size_t i, std::vector<std::size_t> cuts) {
  Plan p = base;
  auto& parts = p.uavs.at(i).parts;
  const auto it = std::find_if(parts.begin(), parts.end(),
                               [](const PathPart& q) { return q.kind == PartKind::Coverage; });
  if (it == parts.end()) throw std::runtime_error("no coverage part");
  const PathPart cov = *it;
  cuts.push_back(cov.local.size());
  std::vector<PathPart> pieces;
  std::size_t from = 0;
  for (const std::size_t to : cuts) {
    pieces.push_back(
        {PartKind::Coverage,
         {cov.local.begin() + static_cast<long>(from), cov.local.begin() + static_cast<long>(to)},
         {cov.wgs84.begin() + static_cast<long>(from), cov.wgs84.begin() + static_cast<long>(to)}});
    if (to < cov.local.size())
      pieces.push_back(
          {PartKind::Transit, {cov.local[to - 1], cov.local[to]}, {cov.wgs84[to - 1], cov.wgs84[to]}});
    from = to;
  }
  parts.erase(it);
  parts.insert(parts.begin() + (it - parts.begin()), pieces.begin(), pieces.end());
  return p;
}

TEST(Sorties, PlannerGivenBoundariesAreHonouredAndChecked) {
  // bravo (18.4 min continuous) in three coverage parts of about a third of its waypoints each
  const std::size_t bravo = 1;
  const std::size_t n = olive_grove().uavs[bravo].turns;
  ASSERT_GE(n, 9u);
  Plan p = split_coverage(olive_grove(), bravo, {n / 3, 2 * n / 3});
  // an endurance at which one part per sortie fits and parts 0 and 1 together do not
  sorties::Options given;
  given.sortie_starts = {{}, {0, 1, 2}};  // alpha: none given; charlie: missing
  sorties::Options too_long;
  too_long.sortie_starts = {{}, {0, 2}};
  Plan roomy = p;
  for (auto& u : roomy.mission.uavs) u.endurance_min = 100.0;
  double longest = 0.0;  // with its climbs and descents
  for (const auto& s : sorties::cut_sorties(roomy, bravo, given))
    longest = std::max(longest, s.duration_min + sorties::vertical_min(roomy, bravo, s));
  const double budget = longest * 1.02;
  ASSERT_GT(sorties::cut_sorties(roomy, bravo, too_long)[0].duration_min, budget)
      << "the test needs parts 0 and 1 together to exceed one battery";
  for (auto& u : p.mission.uavs) u.endurance_min = budget / (1.0 - p.mission.battery_reserve);
  const auto wps = sorties::coverage_waypoints(p.uavs[bravo]);
  ASSERT_EQ(wps.size(), n);

  // by endurance alone, bravo (18.4 min) needs several sorties too
  sorties::Options cut_opt;
  const auto cut = sorties::cut_sorties(p, bravo, cut_opt);
  ASSERT_GE(cut.size(), 2u);

  // given: one sortie per part, from take-off and back, covering exactly that part
  Plan q = p;
  sorties::fill_sorties(q, given);
  ASSERT_EQ(q.uavs[bravo].sorties.size(), 3u);
  const std::vector<int> first{0, static_cast<int>(n / 3), static_cast<int>(2 * n / 3)};
  for (std::size_t k = 0; k < 3; ++k) {
    const Sortie& s = q.uavs[bravo].sorties[k];
    EXPECT_EQ(s.first_waypoint, first[k]);
    EXPECT_EQ(s.last_waypoint, k + 1 < 3 ? first[k + 1] - 1 : static_cast<int>(n) - 1);
    int coverage_parts = 0;
    for (const auto& part : s.parts) coverage_parts += part.kind == PartKind::Coverage ? 1 : 0;
    EXPECT_EQ(coverage_parts, 1);
  }
  for (std::size_t i = 0; i < q.uavs.size(); ++i) expect_valid_sorties(q, i);
  // the other UAVs are cut from their endurance as without boundaries
  for (const std::size_t i : {std::size_t{0}, std::size_t{2}})
    EXPECT_EQ(q.uavs[i].sorties.size(), sorties::cut_sorties(p, i).size());
  // cut_sorties honours them too
  EXPECT_EQ(sorties::cut_sorties(p, bravo, given).size(), 3u);

  // a boundary that makes a sortie longer than one battery: parts 0 and 1 together
  Plan r = p;
  try {
    (void)sorties::cut_sorties(p, bravo, too_long);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "uavs[1].endurance_min");
    EXPECT_NE(std::string(e.what()).find("\"bravo\""), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("given by the planner"), std::string::npos) << e.what();
  }
  // as the engine calls it: that UAV keeps no sorties and the plan a warning, the others theirs
  std::vector<std::string> warnings;
  sorties::fill_sorties(r, too_long, &warnings);
  EXPECT_TRUE(r.uavs[bravo].sorties.empty());
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("no battery sorties"), std::string::npos) << warnings[0];
  expect_valid_sorties(r, 0);
  expect_valid_sorties(r, 2);

  // boundaries that are not increasing coverage-part indices from 0 are refused by name
  for (const auto& bad : std::vector<std::vector<std::size_t>>{{1, 2}, {0, 0}, {0, 2, 1}, {0, 3}}) {
    sorties::Options o;
    o.sortie_starts = {{}, bad};
    try {
      (void)sorties::cut_sorties(p, bravo, o);
      ADD_FAILURE() << "expected InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.field()).rfind("sortie_starts[1]", 0), 0u) << e.field();
    }
  }
}

TEST(Sorties, EverySortieFitsWithItsClimbsAndDescents) {
  // issue 32: a sortie's battery pays for the take-off climb, the descents and climbs between the
  // transition and the survey altitude, and the landing, not only eq. 15's horizontal flight
  auto at_speeds = [](double climb, double descent) {
    Plan p = olive_grove();
    for (auto& u : p.mission.uavs) {
      u.climb_mps = climb;
      u.descent_mps = descent;
    }
    return with_endurance(p, 15.0);
  };
  const Plan fast = at_speeds(30.0, 30.0);
  const Plan slow = at_speeds(2.0, 1.0);
  const double budget = 15.0 * (1.0 - kDefaultBatteryReserve);
  std::ostringstream said;
  for (std::size_t i = 0; i < slow.uavs.size(); ++i) {
    expect_valid_sorties(fast, i);
    expect_valid_sorties(slow, i);
    // the vertical minutes are those of the sortie's own mission, as the whole-flight time counts them
    double slow_vertical = 0.0;
    for (const Sortie& s : slow.uavs[i].sorties) {
      const double v = sorties::vertical_min(slow, i, s);
      EXPECT_NEAR(v * 60.0,
                  waypoints::uav_vertical_time_s(sorties::sortie_plan(slow, i, s), i,
                                                 waypoints::whole_flight_altitudes(slow)),
                  1e-6);
      EXPECT_GT(v, 1.0) << "a climb at 2 m/s and a descent at 1 m/s of tens of metres";
      slow_vertical = std::max(slow_vertical, v);
    }
    // slow climbs leave less of each battery to the coverage: at least as many sorties, more for the
    // UAVs that need several
    EXPECT_GE(slow.uavs[i].sorties.size(), fast.uavs[i].sorties.size());
    if (fast.uavs[i].sorties.size() > 1) {
      EXPECT_GT(slow.uavs[i].sorties.size(), fast.uavs[i].sorties.size());
    }
    // and the horizontal flight alone would have fitted more: the check is not eq. 15's
    for (const Sortie& s : slow.uavs[i].sorties) EXPECT_LE(s.duration_min, budget - 1.0);
    said << slow.uavs[i].id << " " << fast.uavs[i].sorties.size() << " -> " << slow.uavs[i].sorties.size()
         << " sorties (vertical up to " << slow_vertical << " min); ";
  }
  std::cout << "olive grove, endurance 15 min, climb/descent 30/30 -> 2/1 m/s: " << said.str() << "\n";
}

TEST(Sorties, APlannersSortieThatFitsOnlyInThePlaneIsCutFurther) {
  // bravo in three coverage parts, the planner's boundaries one part per sortie, and a battery that fits
  // each part's horizontal flight (eq. 15) but not with its climbs and descents
  const std::size_t bravo = 1;
  const std::size_t n = olive_grove().uavs[bravo].turns;
  Plan p = split_coverage(olive_grove(), bravo, {n / 3, 2 * n / 3});
  for (auto& u : p.mission.uavs) u.climb_mps = 3.0, u.descent_mps = 1.5;  // the defaults
  sorties::Options given;
  given.sortie_starts = {{}, {0, 1, 2}};
  Plan roomy = p;
  for (auto& u : roomy.mission.uavs) u.endurance_min = 100.0;
  double longest = 0.0, vertical = 0.0;
  for (const auto& s : sorties::cut_sorties(roomy, bravo, given)) {
    longest = std::max(longest, s.duration_min);
    vertical = std::max(vertical, sorties::vertical_min(roomy, bravo, s));
  }
  ASSERT_GT(vertical, 0.5);
  for (auto& u : p.mission.uavs) u.endurance_min = longest * 1.01 / (1.0 - p.mission.battery_reserve);
  sorties::fill_sorties(p, given);
  const auto& ss = p.uavs[bravo].sorties;
  EXPECT_GT(ss.size(), 3u);
  expect_valid_sorties(p, bravo);
  // the planner's boundaries stay boundaries: its parts' first waypoints begin sorties
  for (const int w : {static_cast<int>(n / 3), static_cast<int>(2 * n / 3)})
    EXPECT_TRUE(std::any_of(ss.begin(), ss.end(), [&](const Sortie& s) { return s.first_waypoint == w; }))
        << w;
}

TEST(Sorties, MissionBatteryReserveIsValidatedAndKept) {
  const std::string base =
      testing::slurp(std::filesystem::path(UAVCOVER_SOURCE_DIR) / "examples" / "olive-grove.json");
  json j = json::parse(base);
  EXPECT_DOUBLE_EQ(parse_mission(base).battery_reserve, 0.2);
  EXPECT_EQ(json::parse(mission_to_json(parse_mission(base))).count("battery_reserve"), 0u);
  j["battery_reserve"] = 0.3;
  const Mission m = parse_mission(j.dump());
  EXPECT_DOUBLE_EQ(m.battery_reserve, 0.3);
  EXPECT_DOUBLE_EQ(parse_mission(mission_to_json(m)).battery_reserve, 0.3);
  for (const json& bad : {json(-0.1), json(0.95), json("0.2"), json(nullptr)}) {
    j["battery_reserve"] = bad;
    try {
      (void)parse_mission(j.dump());
      FAIL() << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "battery_reserve");
    }
  }
}

/// The thesis rectangle (3 UAVs) with the endurance at which every UAV needs 3 sorties.
TEST(Sorties, AMissionNeedingThreeBatteriesPerUavGivesThreeSorties) {
  json j = json::parse(
      testing::slurp(std::filesystem::path(UAVCOVER_BENCH_DATA) / "mondinelli2025" / "rectangle_3uav.json"));
  // eq. 16's battery count against the sorties: quick climbs and descents, whose time has its own test
  for (auto& u : j["uavs"]) u["climb_mps"] = u["descent_mps"] = 30;
  const Plan base = plan(parse_mission(j.dump()));
  // the longest continuous flight over three batteries with the reserve, then a little longer until
  // every UAV needs exactly three
  double longest = 0;
  for (std::size_t i = 0; i < base.uavs.size(); ++i)
    longest = std::max(longest, evaluation::flight_duration_min(base.uavs[i].length_m, base.uavs[i].turns,
                                                                base.mission.uavs[i]));
  double found = 0;
  for (double e = longest / 3.0 / 0.8; e < longest / 0.8 && found == 0; e *= 1.01) {
    Plan p;
    try {
      p = with_endurance(base, e);
    } catch (const InputError&) {
      continue;  // a leg with its transits does not fit yet
    }
    bool three = true;
    for (const auto& u : p.uavs) three = three && u.sorties.size() == 3;
    if (three) found = e;
  }
  ASSERT_GT(found, 0) << "no endurance gives 3 sorties to every UAV";
  for (auto& u : j["uavs"]) u["endurance_min"] = found;
  const Plan p = plan(parse_mission(j.dump()));  // the engine fills the sorties
  const auto ev = evaluation::evaluate_plan(p);
  EXPECT_EQ(ev.cost.batteries_per_uav, 3);
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    EXPECT_EQ(p.uavs[i].sorties.size(), 3u);
    EXPECT_EQ(ev.cost.uavs[i].batteries, 3);
    expect_valid_sorties(p, i);
  }
  std::cout << "rectangle_3uav: 3 sorties per UAV at endurance " << found << " min\n";
}

TEST(Sorties, StudyBatteryCountsAreTheSortieCounts) {
  Mission m = parse_mission(testing::roi_text("roi01.json"));
  for (auto& u : m.uavs) u.endurance_min = 12.0;  // a leg with its transits and climbs fits one battery
  usecases::StudyOptions so;
  so.counts = {1, 2, 3};
  const auto study = usecases::run_study(m, so);
  ASSERT_EQ(study.rows.size(), 3u);
  for (const auto& row : study.rows) {
    ASSERT_TRUE(row.ok) << row.error;
    PlanOptions po;
    po.seed = so.seed;
    const Plan p = plan(usecases::with_uavs(m, row.uavs), po);
    std::size_t most = 0;
    for (std::size_t i = 0; i < p.uavs.size(); ++i) {
      EXPECT_FALSE(p.uavs[i].sorties.empty()) << row.uavs << " UAVs, " << p.uavs[i].id;
      EXPECT_EQ(row.evaluation.cost.uavs[i].batteries, static_cast<int>(p.uavs[i].sorties.size()));
      most = std::max(most, p.uavs[i].sorties.size());
    }
    EXPECT_EQ(row.evaluation.cost.batteries_per_uav, static_cast<int>(most));
    EXPECT_EQ(row.evaluation.cost.single_battery, most <= 1);
  }
  EXPECT_GT(study.rows.front().evaluation.cost.batteries_per_uav, 1);
}

std::filesystem::path temp_dir(const std::string& name) {
  const auto d =
      std::filesystem::temp_directory_path() /
      ("uavcover-sorties-" + name + "-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

void write_plan_dir(const Plan& p, const std::filesystem::path& dir, json plan_json) {
  io::write_file_atomic(dir / "plan.json", plan_json.dump(1));
  io::write_file_atomic(dir / "paths.geojson", codec::paths_geojson(p).dump(1));
}

TEST(Sorties, PlanJsonRoundTripAndOldFolders) {
  const Plan p = with_endurance(olive_grove(), 12.0);
  const auto dir = temp_dir("roundtrip");
  const json pj = codec::plan_json(p);
  ASSERT_TRUE(pj.at("uavs")[0].contains("sorties"));
  EXPECT_EQ(pj.at("uavs")[0].at("batteries"), p.uavs[0].sorties.size());
  write_plan_dir(p, dir, pj);
  // the paths are unchanged by the sorties (the golden DARP references stay byte-identical)
  EXPECT_EQ(codec::paths_geojson(p).dump(), codec::paths_geojson(olive_grove()).dump());
  const Plan back = io::load_plan_dir(dir);
  ASSERT_EQ(back.uavs.size(), p.uavs.size());
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    ASSERT_EQ(back.uavs[i].sorties.size(), p.uavs[i].sorties.size());
    for (std::size_t k = 0; k < p.uavs[i].sorties.size(); ++k) {
      const Sortie &a = p.uavs[i].sorties[k], &b = back.uavs[i].sorties[k];
      EXPECT_EQ(a.first_waypoint, b.first_waypoint);
      EXPECT_EQ(a.last_waypoint, b.last_waypoint);
      EXPECT_EQ(a.turns, b.turns);
      EXPECT_NEAR(a.length_m, b.length_m, 0.01);
      EXPECT_NEAR(a.duration_min, b.duration_min, 1e-4);
    }
    expect_valid_sorties(back, i);
  }
  // written again: the same sorties
  EXPECT_EQ(codec::plan_json(back).at("uavs")[1].at("sorties").size(), pj.at("uavs")[1].at("sorties").size());

  // an old plan folder (no sorties): they are cut on reading, as plan() would
  json old = pj;
  for (auto& u : old["uavs"]) {
    u.erase("sorties");
    u.erase("batteries");
  }
  old.erase("battery_reserve");
  write_plan_dir(p, dir, old);
  const Plan legacy = io::load_plan_dir(dir);
  for (std::size_t i = 0; i < legacy.uavs.size(); ++i) {
    // the mission of the file says 12 min: the same sorties as plan() would cut
    EXPECT_EQ(legacy.uavs[i].sorties.size(), p.uavs[i].sorties.size());
    expect_valid_sorties(legacy, i);
  }

  // broken sorties are refused naming the field
  auto refused = [&](const std::function<void(json&)>& edit, const std::string& field) {
    json bad = pj;
    edit(bad);
    write_plan_dir(p, dir, bad);
    try {
      (void)io::load_plan_dir(dir);
      ADD_FAILURE() << "accepted a plan.json with a broken " << field;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field().rfind(field, 0), 0u) << e.field() << ": " << e.what();
    }
  };
  refused([](json& j) { j["uavs"][1]["sorties"][1]["first_waypoint"] = 0; },
          "plan.json: uavs[1].sorties[1].first_waypoint");
  refused([](json& j) { j["uavs"][1]["sorties"][0]["last_waypoint"] = 1 << 29; },
          "plan.json: uavs[1].sorties[0].last_waypoint");
  refused([](json& j) { j["uavs"][0]["sorties"][0]["index"] = -1; }, "plan.json: uavs[0].sorties[0].index");
  refused(
      [](json& j) {
        j["uavs"][0]["sorties"][0]["transit_back"] = json::array({json::array({22.9, 40.6})});
      },
      "plan.json: uavs[0].sorties[0].transit_back");
  refused([](json& j) { j["uavs"][2]["sorties"].erase(j["uavs"][2]["sorties"].size() - 1); },
          "plan.json: uavs[2].sorties");
  std::filesystem::remove_all(dir);
}

const Artifact* find(const Artifacts& all, const std::string& name) {
  for (const auto& a : all)
    if (a.name == name) return &a;
  return nullptr;
}

TEST(Sorties, PerSortieExportsAreWholeMissions) {
  const Plan p = with_endurance(olive_grove(), 12.0);
  exporting::ExportOptions opt;
  opt.per_sortie = true;
  const auto arts = exporting::export_artifacts(p, {"qgc,wpl,csv,kml,dji,litchi,geojson"}, opt);
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    const std::string& id = p.uavs[i].id;
    EXPECT_EQ(find(arts, "export/" + id + ".plan"), nullptr);
    EXPECT_NE(find(arts, "export/" + id + ".geojson"), nullptr);  // one per UAV
    EXPECT_EQ(find(arts, "export/" + id + ".s" + std::to_string(p.uavs[i].sorties.size() + 1) + ".plan"),
              nullptr);
    std::vector<int> covered;
    for (std::size_t k = 0; k < p.uavs[i].sorties.size(); ++k) {
      const std::string base = "export/" + id + ".s" + std::to_string(k + 1);
      SCOPED_TRACE(base);
      for (const char* ext : {".plan", ".waypoints", ".csv", ".kml", ".wpml.kmz"})
        EXPECT_NE(find(arts, base + ext), nullptr) << ext;
      EXPECT_TRUE(find(arts, base + ".litchi.csv") != nullptr ||
                  find(arts, base + ".1.litchi.csv") != nullptr);
      // QGroundControl: take-off first, return last
      const Artifact* qgc = find(arts, base + ".plan");
      ASSERT_NE(qgc, nullptr);
      const json doc = strict::parse_json(qgc->bytes, "plan");
      const json& items = doc.at("mission").at("items");
      ASSERT_GE(items.size(), 3u);
      EXPECT_EQ(items.front().at("command"), 22);
      EXPECT_EQ(items.back().at("command"), 20);
      // Mission Planner WPL: header, home row 0, take-off row 1, RTL last
      const Artifact* wpl = find(arts, base + ".waypoints");
      ASSERT_NE(wpl, nullptr);
      std::istringstream in(wpl->bytes);
      std::string line;
      std::vector<std::vector<std::string>> rows;
      std::getline(in, line);
      EXPECT_EQ(line, "QGC WPL 110");
      while (std::getline(in, line)) {
        std::vector<std::string> cols;
        std::istringstream ls(line);
        for (std::string c; std::getline(ls, c, '\t');) cols.push_back(c);
        ASSERT_EQ(cols.size(), 12u) << line;
        EXPECT_EQ(cols[0], std::to_string(rows.size()));
        rows.push_back(cols);
      }
      ASSERT_GE(rows.size(), 3u);
      EXPECT_EQ(rows[1][3], "22");
      EXPECT_EQ(rows.back()[3], "20");
      // the sortie's coverage waypoints, as the mission items give them
      const Plan sp = sorties::sortie_plan(p, i, p.uavs[i].sorties[k]);
      for (const auto& it : waypoints::mission_items(sp, i))
        if (it.waypoint >= 0) covered.push_back(it.waypoint + p.uavs[i].sorties[k].first_waypoint);
    }
    // the sorties' missions visit every coverage waypoint in order, joins repeated
    covered.erase(std::unique(covered.begin(), covered.end()), covered.end());
    ASSERT_EQ(covered.size(), static_cast<std::size_t>(p.uavs[i].turns));
    for (std::size_t g = 0; g < covered.size(); ++g) EXPECT_EQ(covered[g], static_cast<int>(g));
  }
  // off: the names are unchanged
  const auto whole = exporting::export_artifacts(p, {"qgc,wpl"}, {});
  EXPECT_NE(find(whole, "export/alpha.plan"), nullptr);
  EXPECT_NE(find(whole, "export/alpha.waypoints"), nullptr);
  EXPECT_EQ(find(whole, "export/alpha.s1.plan"), nullptr);
}

TEST(Sorties, ResumeFliesTheRestOnce) {
  const Plan p = with_endurance(olive_grove(), 12.0);
  int resumed = 0;
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    const UavPlan& up = p.uavs[i];
    SCOPED_TRACE(up.id);
    const auto wps = sorties::coverage_waypoints(up);
    const int n = static_cast<int>(wps.size());
    if (up.sorties.size() < 2) continue;  // alpha: one sortie
    ++resumed;
    const Sortie& second = up.sorties[1];
    for (const int r :
         {-1, 0, (second.first_waypoint + second.last_waypoint) / 2, second.last_waypoint, n - 2}) {
      SCOPED_TRACE("last reached " + std::to_string(r));
      const auto rest = sorties::resume_sorties(p, i, r);
      ASSERT_FALSE(rest.empty());
      // the flown prefix: every coverage leg of the plan up to waypoint r
      std::multiset<std::pair<std::pair<double, double>, std::pair<double, double>>> flown;
      for (int g = 1; g <= r; ++g) {
        const auto a = wps[static_cast<std::size_t>(g - 1)], b = wps[static_cast<std::size_t>(g)];
        if (a.part != b.part) continue;
        const Point pa = up.parts[a.part].local[a.vertex], pb = up.parts[b.part].local[b.vertex];
        flown.insert({{pa.x(), pa.y()}, {pb.x(), pb.y()}});
      }
      const double budget = p.mission.uavs[i].endurance_min * 0.8;
      int expected_first = r < 0 ? 0 : r;
      if (r >= 0 &&
          (r + 1 >= n || wps[static_cast<std::size_t>(r) + 1].part != wps[static_cast<std::size_t>(r)].part))
        expected_first = r + 1;
      // a sortie done at r leaves the next one whole
      for (const auto& s : up.sorties)
        if (s.last_waypoint == r && r + 1 < n)
          expected_first = up.sorties[static_cast<std::size_t>(s.index) + 1].first_waypoint;
      EXPECT_EQ(rest.front().first_waypoint, expected_first);
      for (const auto& s : rest) {
        EXPECT_LE(s.duration_min, budget * (1 + 1e-9));
        const auto l = legs_of(s.parts);
        flown.insert(l.begin(), l.end());
      }
      EXPECT_EQ(rest.back().last_waypoint, n - 1);
      // the prefix and the resume: every coverage leg of the plan, once
      EXPECT_EQ(flown, legs_of(up.parts));
      // as missions: take-off at the transition altitude, coverage, return
      const auto missions = sorties::resume_items(p, i, r);
      ASSERT_EQ(missions.size(), rest.size());
      std::set<int> waypoints;
      for (int g = 0; g <= r; ++g) waypoints.insert(g);
      for (const auto& items : missions) {
        ASSERT_GE(items.size(), 3u);
        EXPECT_EQ(items.front().command, waypoints::kNavTakeoff);
        EXPECT_FLOAT_EQ(items.front().alt, static_cast<float>(up.transition_altitude_m));
        EXPECT_EQ(items.back().command, waypoints::kNavReturnToLaunch);
        for (const auto& it : items)
          if (it.waypoint >= 0) waypoints.insert(it.waypoint);
      }
      EXPECT_EQ(waypoints.size(), static_cast<std::size_t>(n));
      EXPECT_EQ(*waypoints.rbegin(), n - 1);
    }
    EXPECT_TRUE(sorties::resume_sorties(p, i, n - 1).empty());
    EXPECT_THROW((void)sorties::resume_sorties(p, i, n), InputError);
    EXPECT_THROW((void)sorties::resume_sorties(p, i, -2), InputError);
  }
  EXPECT_EQ(resumed, 2);
}

}  // namespace
}  // namespace uavcover

namespace uavcover {
namespace {

// A field strewn with 400 small no-fly zones (a 20 x 20 lattice of 4 m squares every 40 m) and batteries
// of a few minutes: every sortie's transits out and back go around the zones, and the sorties stay valid.
TEST(Sorties, TransitsOfEverySortieAvoidManyZones) {
  Mission m = testing::zone_lattice_mission(800, 20, 40, 4, 25.0);
  for (int i = 0; i < 2; ++i) {
    Uav u;
    u.id = "u" + std::to_string(i);
    u.share = 0.5;
    u.endurance_min = 11.0;
    u.start = testing::zone_lattice_point(1.0 + 790 * i, 1.0);
    m.uavs.push_back(u);
  }
  const Plan p = plan(m);
  const geodesy::LocalFrame frame(p.origin);
  const geometry::Router router(geometry::unite(geometry::to_local(p.mission.no_fly_zones, frame)));
  std::size_t sorties = 0;
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    expect_valid_sorties(p, i);
    sorties += p.uavs[i].sorties.size();
    for (const auto& s : p.uavs[i].sorties)
      for (const auto& part : s.parts)
        for (std::size_t k = 1; k < part.local.size(); ++k)
          EXPECT_TRUE(router.clear(part.local[k - 1], part.local[k]))
              << p.uavs[i].id << " sortie " << s.index;
  }
  EXPECT_GE(sorties, 4u);  // 0.64 km² at 25 m is ~26 km of coverage: several 11-minute batteries
}

}  // namespace
}  // namespace uavcover

namespace uavcover {
namespace {

/// A heading that is a function of the vertex's position (for checking that a cut keeps each vertex's).
double heading_of(Point p) {
  const double h = std::fmod(std::abs(p.x() * 7.3 + p.y() * 1.1), 360.0);
  return h;
}

}  // namespace

// PathPart::attitude (issue 30): a sortie's piece of a coverage part keeps the part's attitude, with the
// headings of its own vertices.
TEST(Sorties, PiecesKeepTheirPartsAttitude) {
  Plan p = olive_grove();
  std::size_t bravo = 0;
  while (p.uavs[bravo].id != "bravo") ++bravo;
  for (auto& part : p.uavs[bravo].parts) {
    if (part.kind != PartKind::Coverage) continue;
    part.attitude.gimbal_pitch_deg = -30.0;
    part.attitude.altitude_m = 33.0;
    for (const Point& v : part.local) part.attitude.heading_deg.push_back(heading_of(v));
  }
  p = with_endurance(p, 12.0);
  ASSERT_GT(p.uavs[bravo].sorties.size(), 1u);
  std::size_t pieces = 0, vertices = 0;
  for (const Sortie& s : p.uavs[bravo].sorties)
    for (const PathPart& part : s.parts) {
      if (part.kind != PartKind::Coverage) {
        EXPECT_TRUE(part.attitude.empty());
        continue;
      }
      ++pieces;
      EXPECT_EQ(part.attitude.gimbal_pitch_deg, -30.0);
      EXPECT_EQ(part.attitude.altitude_m, 33.0);
      ASSERT_EQ(part.attitude.heading_deg.size(), part.local.size());
      // (a lead-in's start, issue 31, lies inside a segment: its heading is turned between the ends)
      for (std::size_t k = part.lead_in > 0 ? 1 : 0; k < part.local.size(); ++k, ++vertices)
        EXPECT_EQ(part.attitude.heading_deg[k], heading_of(part.local[k])) << k;
    }
  EXPECT_GT(pieces, p.uavs[bravo].sorties.size() - 1);
  EXPECT_GT(vertices, 0u);
}

}  // namespace uavcover

namespace uavcover {
namespace {

/// The length of a polyline.
double along(const std::vector<Point>& pts, std::size_t from, std::size_t to) {
  double s = 0;
  for (std::size_t k = from + 1; k <= to; ++k) s += bg::distance(pts[k - 1], pts[k]);
  return s;
}

/// Distance from `p` to the UAV's own coverage polylines (its plan's coverage parts).
double off_own_coverage(const UavPlan& up, Point p) {
  double best = 1e300;
  for (const auto& part : up.parts)
    if (part.kind == PartKind::Coverage && part.local.size() >= 2) {
      bg::model::linestring<Point> line(part.local.begin(), part.local.end());
      best = std::min(best, static_cast<double>(bg::distance(p, line)));
    }
  return best;
}

// Issue 31, resume with overlap: a resumed flight and every battery sortie after the first start one
// photo base (the camera's trigger distance; resume_backoff_m when given) before their first waypoint,
// back along the UAV's own path, flown at mission altitude with the camera on, so no gap opens at the seam.
TEST(Sorties, ResumeAndLaterSortiesStartOnePhotoBaseBack) {
  const Plan p = with_endurance(olive_grove(), 12.0);
  const double base = *p.mission.trigger_distance_m;
  ASSERT_GT(base, 1.0);
  EXPECT_DOUBLE_EQ(sorties::resume_backoff_m(p, 0), base);
  int checked = 0;
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    const UavPlan& up = p.uavs[i];
    SCOPED_TRACE(up.id);
    const auto wps = sorties::coverage_waypoints(up);
    for (std::size_t k = 0; k < up.sorties.size(); ++k) {
      const Sortie& s = up.sorties[k];
      const auto first = std::find_if(s.parts.begin(), s.parts.end(),
                                      [](const PathPart& q) { return q.kind == PartKind::Coverage; });
      ASSERT_NE(first, s.parts.end());
      const sorties::WaypointRef w = wps[static_cast<std::size_t>(s.first_waypoint)];
      if (k == 0 || w.vertex == 0) {  // the first sortie, or one that starts a coverage part: none
        EXPECT_EQ(first->lead_in, 0U);
        continue;
      }
      ++checked;
      ASSERT_GE(first->lead_in, 1U);
      // the lead-in ends at the sortie's first waypoint, runs back along the UAV's own path for one
      // photo base (or to the part's start), and the transit out ends where it begins
      const Point wp = up.parts[w.part].local[w.vertex];
      EXPECT_LT(bg::distance(first->local[first->lead_in], wp), 1e-9);
      const double avail = along(up.parts[w.part].local, 0, w.vertex);
      EXPECT_NEAR(along(first->local, 0, first->lead_in), std::min(base, avail), 1e-6);
      EXPECT_LT(off_own_coverage(up, first->local.front()), 1e-6);
      EXPECT_LT(bg::distance(std::prev(first)->local.back(), first->local.front()), 0.01);
      // as a mission: the lead-in's waypoints at mission altitude and not counted, the camera started
      // before the sortie's first waypoint
      const auto items = waypoints::mission_items(sorties::sortie_plan(p, i, s), i);
      const auto wp_item =
          std::find_if(items.begin(), items.end(), [](const auto& it) { return it.waypoint == 0; });
      ASSERT_NE(wp_item, items.end());
      int lead = 0;
      bool camera_on = false;
      for (auto it = items.begin(); it != wp_item; ++it) {
        if (it->role == "lead_in") {
          ++lead;
          EXPECT_EQ(it->waypoint, -1);
          EXPECT_FLOAT_EQ(it->alt, static_cast<float>(p.mission.altitude_m));
        }
        if (it->command == waypoints::kDoSetCamTriggDist && it->param1 > 0) camera_on = true;
      }
      EXPECT_EQ(lead, static_cast<int>(first->lead_in));
      EXPECT_TRUE(camera_on);
    }
    // a resume mid-leg: back along the path from the last reached waypoint
    if (up.sorties.size() < 2) continue;
    const int r = (up.sorties[1].first_waypoint + up.sorties[1].last_waypoint) / 2;
    const auto rest = sorties::resume_sorties(p, i, r);
    ASSERT_FALSE(rest.empty());
    const auto cov = std::find_if(rest.front().parts.begin(), rest.front().parts.end(),
                                  [](const PathPart& q) { return q.kind == PartKind::Coverage; });
    const sorties::WaypointRef w = wps[static_cast<std::size_t>(rest.front().first_waypoint)];
    EXPECT_EQ(cov->lead_in > 0, w.vertex > 0);
    // resume_backoff_m 0: starts at the waypoint itself
    Plan zero = p;
    zero.mission.resume_backoff_m = 0.0;
    const auto exact = sorties::resume_sorties(zero, i, r);
    for (const auto& part : exact.front().parts) EXPECT_EQ(part.lead_in, 0U);
    // and a longer one is clipped at the start of the coverage part
    Plan far = p;
    far.mission.resume_backoff_m = 1e5;
    const auto clipped = sorties::resume_sorties(far, i, r);
    const auto c2 = std::find_if(clipped.front().parts.begin(), clipped.front().parts.end(),
                                 [](const PathPart& q) { return q.kind == PartKind::Coverage; });
    if (w.vertex > 0) {
      EXPECT_EQ(c2->lead_in, w.vertex);
      EXPECT_LT(bg::distance(c2->local.front(), up.parts[w.part].local.front()), 1e-9);
    }
  }
  EXPECT_GT(checked, 0);
}

// Issue 31, vehicle limits: a UAV's missions split to what each profile stores (PX4 500, ArduPilot 700
// or the board's max_mission_items, DJI, Litchi 99 waypoints), every piece a whole mission, together
// every coverage waypoint in order.
TEST(Sorties, CapacitySplitFitsEveryProfile) {
  Plan p = olive_grove();
  std::size_t i = 0;  // the UAV with the most coverage waypoints
  for (std::size_t k = 1; k < p.uavs.size(); ++k)
    if (sorties::coverage_waypoints(p.uavs[k]).size() > sorties::coverage_waypoints(p.uavs[i]).size()) i = k;
  const int n = static_cast<int>(sorties::coverage_waypoints(p.uavs[i]).size());
  ASSERT_GT(n, 10);
  for (const auto& profile : kVehicleProfiles) {
    SCOPED_TRACE(std::string(profile.name));
    const std::string name(profile.name);
    const std::size_t whole = exporting::stored_items(p, i, name, {});
    // the profile's own capacity, or a smaller board's where the whole mission fits it
    Plan q = p;
    if (whole <= profile.max_items) q.mission.max_mission_items = static_cast<int>(whole * 2 / 3);
    const std::size_t cap = mission_capacity(profile, q.mission.max_mission_items);
    ASSERT_LT(cap, whole);
    const auto pieces = sorties::capacity_sorties(
        q, i, cap, [&](const Plan& sp, std::size_t u) { return exporting::stored_items(sp, u, name, {}); });
    ASSERT_GE(pieces.size(), (whole + cap - 1) / cap);
    std::vector<int> covered;
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      const Sortie& s = pieces[k];
      EXPECT_EQ(s.index, static_cast<int>(k));
      const Plan sp = sorties::sortie_plan(q, i, s);
      EXPECT_LE(exporting::stored_items(sp, i, name, {}), cap);
      const auto items = waypoints::mission_items(sp, i);
      EXPECT_EQ(items.front().command, waypoints::kNavTakeoff);
      EXPECT_EQ(items.back().command, waypoints::kNavReturnToLaunch);
      for (const auto& it : items)
        if (it.waypoint >= 0) covered.push_back(it.waypoint + s.first_waypoint);
    }
    covered.erase(std::unique(covered.begin(), covered.end()), covered.end());
    ASSERT_EQ(covered.size(), static_cast<std::size_t>(n));
    for (int g = 0; g < n; ++g) EXPECT_EQ(covered[static_cast<std::size_t>(g)], g);
  }
  // a capacity below one leg's mission names the field
  EXPECT_THROW(
      (void)sorties::capacity_sorties(
          p, i, 3, [](const Plan& sp, std::size_t u) { return exporting::stored_items(sp, u, "px4", {}); }),
      InputError);
  // the export writes the pieces as whole missions (export/<id>.s<k>.plan), each within the capacity
  const int cap = static_cast<int>(exporting::stored_items(p, i, "ardupilot", {}) * 2 / 3);
  p.mission.max_mission_items = cap;
  exporting::ExportOptions opt;
  opt.split_capacity = true;
  opt.autopilot = "ardupilot";
  const auto arts = exporting::export_artifacts(p, {"qgc"}, opt);
  int files = 0;
  for (const auto& a : arts) {
    if (a.name.find("export/" + p.uavs[i].id + ".s") != 0) continue;
    ++files;
    const json doc = strict::parse_json(a.bytes, "plan");
    EXPECT_LE(doc.at("mission").at("items").size() + 1, static_cast<std::size_t>(cap)) << a.name;  // + home
  }
  EXPECT_GE(files, 2);
}

}  // namespace
}  // namespace uavcover
