// Corridors and the pattern options (docs/patterns.md, issue 30), planned through the whole pipeline
// (parse_mission, plan, evaluation, mission items and the exports), on geometry a person can check.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "autopilot/rules.hpp"
#include "evaluation/evaluate.hpp"
#include "export/export.hpp"
#include "geodesy/local_frame.hpp"
#include "support/errors.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"
#include "waypoints/waypoints.hpp"

using namespace uavcover;
using nlohmann::json;

namespace {

constexpr double kLat = 45.0, kLon = 10.0;

/// The position `east_m`, `north_m` metres from (kLon, kLat), in the tangent frame there (GeographicLib), so
/// that the lengths the tests expect are the lengths in the plan's own frame.
LonLat ll_at(double east_m, double north_m) {
  static const geodesy::LocalFrame f(LonLat{kLon, kLat});
  return f.to_wgs84(Point(east_m, north_m));
}
json at(double east_m, double north_m) {
  const LonLat p = ll_at(east_m, north_m);
  return {p.lon, p.lat};
}

json corridor_mission(std::vector<std::pair<double, double>> line, double width, double spacing,
                      const std::string& planner = "boustrophedon", int uavs = 1) {
  json coords = json::array();
  for (auto [e, n] : line) coords.push_back(at(e, n));
  json u = json::array();
  for (int i = 0; i < uavs; ++i) u.push_back({{"id", "u" + std::to_string(i + 1)}});
  return {{"name", "corridor"},
          {"corridor", {{"line", {{"type", "LineString"}, {"coordinates", coords}}}, {"width_m", width}}},
          {"spacing_m", spacing},
          {"altitude_m", 40},
          {"uavs", u},
          {"planner", planner},
          {"seed", 7}};
}

Plan plan_of(const json& j) { return plan(parse_mission(j.dump())); }

/// The camera-on runs of a UAV's coverage, in flight order: the legs it shoots.
std::vector<std::vector<Point>> shot_runs(const UavPlan& u) {
  std::vector<std::vector<Point>> out;
  for (const auto& part : u.parts) {
    if (part.kind != PartKind::Coverage) continue;
    std::vector<Point> cur;
    for (std::size_t k = 1; k < part.local.size(); ++k) {
      if (part.camera_on(k - 1)) {
        if (cur.empty()) cur.push_back(part.local[k - 1]);
        cur.push_back(part.local[k]);
      } else if (!cur.empty()) {
        out.push_back(std::move(cur));
        cur.clear();
      }
    }
    if (!cur.empty()) out.push_back(std::move(cur));
  }
  return out;
}

double seg_len(Point a, Point b) { return std::hypot(a.x() - b.x(), a.y() - b.y()); }

double run_length(const std::vector<Point>& r) {
  double l = 0;
  for (std::size_t k = 1; k < r.size(); ++k) l += seg_len(r[k - 1], r[k]);
  return l;
}

/// Local point of (east_m, north_m) in the plan's frame.
Point local_of(const Plan& p, double e, double n) {
  const geodesy::LocalFrame f(p.origin);
  return f.to_local(ll_at(e, n));
}

double distance_to(const std::vector<Point>& line, Point p) {
  bg::model::linestring<Point> ls(line.begin(), line.end());
  return bg::distance(p, ls);
}

/// `got` is `want`, or its mirror image (`mirror` on every lane), either way round.
bool same_up_to_symmetry(const std::vector<long>& got, const std::vector<long>& want,
                         const std::function<long(long)>& mirror) {
  std::vector<long> m = got;
  for (auto& x : m) x = mirror(x);
  for (auto v : {got, m}) {
    if (v == want) return true;
    std::reverse(v.begin(), v.end());
    if (v == want) return true;
  }
  return false;
}

using uavcover::testing::field_of;

}  // namespace

// A straight corridor of width W at spacing ds: ceil(W / ds) lanes parallel to the line, at the offsets
// (k - (n - 1) / 2) ds, each the whole corridor long.
TEST(Corridor, StraightCorridorGivesCeilWidthOverSpacingLanes) {
  for (auto [width, spacing] : std::vector<std::pair<double, double>>{{120, 25}, {100, 20}, {30, 40}}) {
    json j = corridor_mission({{0, 0}, {800, 0}}, width, spacing);
    j["pattern"] = json::object();  // the camera off in turns, so the runs are the lanes
    const Plan p = plan_of(j);
    const auto runs = shot_runs(p.uavs[0]);
    const int n = static_cast<int>(std::ceil(width / spacing));
    ASSERT_EQ(static_cast<int>(runs.size()), n) << width << " / " << spacing;
    const Point a = local_of(p, 0, 0), b = local_of(p, 800, 0);
    const double dx = b.x() - a.x(), dy = b.y() - a.y(), len = std::hypot(dx, dy);
    std::vector<double> offsets;
    for (const auto& r : runs) {
      ASSERT_EQ(r.size(), 2u);
      const double side0 = ((r[0].x() - a.x()) * dy - (r[0].y() - a.y()) * dx) / len;
      const double side1 = ((r[1].x() - a.x()) * dy - (r[1].y() - a.y()) * dx) / len;
      EXPECT_NEAR(side0, side1, 0.05);  // parallel to the line
      EXPECT_NEAR(run_length(r), 800.0, 0.5);
      offsets.push_back(side0);
    }
    std::sort(offsets.begin(), offsets.end());
    for (int k = 0; k < n; ++k) EXPECT_NEAR(offsets[k], (k - 0.5 * (n - 1)) * spacing, 0.05);
  }
}

// A bent corridor keeps the spacing: every point of a lane stays at the lane's offset from the centre line
// (round outside the bends, mitred inside), the offsets one spacing apart, all inside the corridor.
TEST(Corridor, BentCorridorKeepsTheSpacing) {
  json j = corridor_mission({{0, 0}, {500, 0}, {500, 400}, {900, 700}}, 100, 20);
  j["pattern"] = json::object();
  const Plan p = plan_of(j);
  const auto runs = shot_runs(p.uavs[0]);
  ASSERT_EQ(runs.size(), 5u);
  std::vector<Point> centre{local_of(p, 0, 0), local_of(p, 500, 0), local_of(p, 500, 400),
                            local_of(p, 900, 700)};
  std::multiset<long> offsets;
  for (const auto& run : runs) {
    const double d = distance_to(centre, run.front());
    offsets.insert(std::lround(d));
    EXPECT_GE(run.size(), 4u);  // the bends are in the lane
    for (std::size_t k = 1; k < run.size(); ++k)
      for (int s = 0; s <= 10; ++s) {
        const Point a = run[k - 1], b = run[k];
        const Point q{a.x() + (b.x() - a.x()) * s / 10.0, a.y() + (b.y() - a.y()) * s / 10.0};
        // 5-degree chords of the outer arcs sag by at most 40 (1 - cos 2.5 deg) = 0.04 m
        EXPECT_NEAR(distance_to(centre, q), d, 0.05) << "offset " << d << " segment " << k;
      }
  }
  EXPECT_EQ(offsets, (std::multiset<long>{0, 20, 20, 40, 40}));
}

// No-fly zones cut the legs, and nothing flies through them (coverage or transit).
TEST(Corridor, NoFlyZonesCutTheLegsAndPathsStayOut) {
  json j = corridor_mission({{0, 0}, {1000, 0}}, 100, 20);
  j["pattern"] = json::object();
  json zone = json::array({at(400, -60), at(500, -60), at(500, 10), at(400, 10), at(400, -60)});
  j["no_fly_zones"] = json::array({{{"type", "Polygon"}, {"coordinates", {zone}}}});
  const Plan p = plan_of(j);
  const auto runs = shot_runs(p.uavs[0]);
  // lanes at -40, -20 and 0 m cross the zone: each in two runs; the ones at 20 and 40 m pass it
  EXPECT_EQ(runs.size(), 8u);
  const MultiPolygon z = [&] {
    MultiPolygon out;
    Polygon poly;
    for (auto [e, n] : std::vector<std::pair<double, double>>{
             {400.1, -59.9}, {400.1, 9.9}, {499.9, 9.9}, {499.9, -59.9}, {400.1, -59.9}})
      poly.outer().push_back(local_of(p, e, n));
    bg::correct(poly);
    out.push_back(poly);
    return out;
  }();
  for (const auto& part : p.uavs[0].parts)
    for (std::size_t k = 1; k < part.local.size(); ++k) {
      bg::model::segment<Point> s{part.local[k - 1], part.local[k]};
      EXPECT_FALSE(bg::intersects(s, z)) << (part.kind == PartKind::Coverage ? "coverage" : "transit");
    }
}

// Three UAVs get consecutive pieces by share, each flying every lane of its piece from the end nearest
// its start; the evaluator sees the buffered corridor covered.
TEST(Corridor, ThreeUavsGetConsecutivePiecesByShare) {
  json j = corridor_mission({{0, 0}, {1200, 0}}, 60, 20, "boustrophedon", 3);
  const std::vector<double> shares{0.5, 0.3, 0.2};
  const std::vector<double> start_e{1250, -50, 700};  // not in the pieces' order
  for (int i = 0; i < 3; ++i) {
    j["uavs"][i]["share"] = shares[i];
    j["uavs"][i]["start"] = at(start_e[i], -80);
  }
  j["pattern"] = json::object();
  const Plan p = plan_of(j);
  // along the line: u2 (start at -50, share 0.3) first, then u3 (700, 0.2), then u1 (1250, 0.5)
  const std::vector<std::pair<double, double>> pieces{{600, 1200}, {0, 360}, {360, 600}};
  for (int i = 0; i < 3; ++i) {
    const auto runs = shot_runs(p.uavs[i]);
    ASSERT_EQ(runs.size(), 3u) << i;
    double lo = 1e9, hi = -1e9;
    const Point o = local_of(p, 0, 0), e = local_of(p, 1200, 0);
    const double ux = (e.x() - o.x()) / 1200, uy = (e.y() - o.y()) / 1200;
    for (const auto& r : runs)
      for (const auto& q : r) {
        const double s = (q.x() - o.x()) * ux + (q.y() - o.y()) * uy;
        lo = std::min(lo, s), hi = std::max(hi, s);
      }
    EXPECT_NEAR(lo, pieces[i].first, 0.5) << "uav " << i;
    EXPECT_NEAR(hi, pieces[i].second, 0.5) << "uav " << i;
    EXPECT_NEAR(p.uavs[i].share_actual, shares[i], 0.01);
    // the first waypoint at the piece's end nearest the start
    const Point first = runs.front().front();
    const double s_first = (first.x() - o.x()) * ux + (first.y() - o.y()) * uy;
    const double near_end = std::fabs(start_e[i] - pieces[i].first) < std::fabs(start_e[i] - pieces[i].second)
                                ? pieces[i].first
                                : pieces[i].second;
    EXPECT_NEAR(s_first, near_end, 0.5) << "uav " << i;
  }
  const auto ev = evaluation::evaluate_plan(p);
  EXPECT_NEAR(ev.coverage.total.area_m2, 1200.0 * 60.0, 1200.0 * 60.0 * 0.002);  // the buffered corridor
  EXPECT_GT(ev.coverage.total.poc, 0.99);
}

// Crosshatch: two perpendicular sweeps (corridor and area); the evaluator reports the double coverage.
TEST(Pattern, CrosshatchGivesTwoPerpendicularSweeps) {
  json c = corridor_mission({{0, 0}, {400, 0}}, 80, 20);
  c["pattern"] = {{"crosshatch", true}};
  json a = c;
  a.erase("corridor");
  a["area"] = {{"type", "Polygon"},
               {"coordinates", {json::array({at(0, 0), at(300, 0), at(300, 200), at(0, 200), at(0, 0)})}}};
  for (const json& j : {c, a}) {
    const Plan p = plan_of(j);
    std::map<long, double> by_bearing;  // bearing (degrees mod 180) -> length shot
    for (const auto& r : shot_runs(p.uavs[0]))
      for (std::size_t k = 1; k < r.size(); ++k) {
        double b = std::atan2(r[k].x() - r[k - 1].x(), r[k].y() - r[k - 1].y()) * 180 / M_PI;
        b = std::fmod(b + 360.0, 180.0);
        by_bearing[std::lround(b) % 180] += seg_len(r[k - 1], r[k]);
      }
    ASSERT_EQ(by_bearing.size(), 2u) << j.contains("corridor");
    const long b0 = by_bearing.begin()->first, b1 = std::next(by_bearing.begin())->first;
    EXPECT_EQ(b1 - b0, 90);
    const auto ev = evaluation::evaluate_plan(p);
    EXPECT_GT(ev.coverage.total.poc, 0.98);
    EXPECT_GT(ev.coverage.total.pooc, 0.9);  // every point seen by both sweeps
    // without crosshatch, the lanes hardly overlap
    json single = j;
    single["pattern"]["crosshatch"] = false;
    // (footprint 1.5 spacings: neighbouring lanes overlap by half a spacing, so about half is seen twice)
    EXPECT_LT(evaluation::evaluate_plan(plan_of(single)).coverage.total.pooc, 0.7);
  }
}

// turnaround_m: every lane extends by it at both ends, camera off; the exports shoot the lanes only.
TEST(Pattern, TurnaroundLegsExtendWithTheCameraOff) {
  json j = corridor_mission({{0, 0}, {600, 0}}, 60, 20);
  j.erase("spacing_m");
  j.erase("altitude_m");
  j["camera"] = {{"altitude_m", 40}, {"hfov_deg", 60}, {"overlap", 0.3}};
  j["pattern"] = {{"turnaround_m", 15}};
  const Plan p = plan_of(j);
  const auto& cov = p.uavs[0].parts;
  int turnarounds = 0;
  for (const auto& part : cov) {
    if (part.kind != PartKind::Coverage) continue;
    for (std::size_t k = 1; k < part.local.size(); ++k) {
      const double l = seg_len(part.local[k - 1], part.local[k]);
      if (!part.camera_on(k - 1) && std::fabs(l - 15.0) < 1e-6) ++turnarounds;
    }
  }
  const auto runs = shot_runs(p.uavs[0]);
  const int lanes = static_cast<int>(runs.size());
  EXPECT_EQ(lanes, static_cast<int>(std::ceil(60.0 / p.mission.spacing_m)));
  EXPECT_EQ(turnarounds, 2 * lanes);
  for (const auto& r : runs) EXPECT_NEAR(run_length(r), 600.0, 0.5);  // the lanes, not the turnarounds
  // the mission items: one distance trigger per lane, started at its first waypoint and stopped at its last
  const auto items = waypoints::mission_items(p, 0);
  int starts = 0, stops = 0;
  for (const auto& it : items)
    if (it.command == waypoints::kDoSetCamTriggDist) (it.param1 > 0 ? starts : stops) += 1;
  EXPECT_EQ(starts, lanes);
  EXPECT_EQ(stops, lanes);
  // and the autopilots accept them; every format exports
  EXPECT_TRUE(autopilot::ardupilot_problems(items).empty());
  for (const auto& pr : autopilot::px4_problems(items, p.mission.uavs[0].start_resolved, 0.0))
    EXPECT_FALSE(pr.fatal) << pr.message;
  EXPECT_NO_THROW(exporting::qgc_plan(p, 0));
  EXPECT_NO_THROW(exporting::wpl_text(p, 0));
  EXPECT_NO_THROW(exporting::dji_wpml(p, 0));
  EXPECT_NO_THROW(exporting::litchi_csv(p, 0));
  // capture_in_turnaround keeps the camera on: no segment is off
  j["pattern"]["capture_in_turnaround"] = true;
  for (const auto& part : plan_of(j).uavs[0].parts)
    for (auto f : part.camera_off) EXPECT_EQ(f, 0);
}

// entry: the first leg starts from the corner asked for.
// On an area the boustrophedon tour counted the return to the start too, so a one-cell tour could enter at
// either end; a fixed entry now weighs the first leg (planners/boustrophedon/ordering.hpp).
TEST(Pattern, EntryCornersAreHonoured) {
  json a = corridor_mission({{0, 0}, {400, 0}}, 80, 20);
  a.erase("corridor");
  a["area"] = {{"type", "Polygon"},
               {"coordinates", {json::array({at(0, 0), at(300, 0), at(300, 200), at(0, 200), at(0, 0)})}}};
  a["uavs"][0]["start"] = at(150, 100);
  json c = corridor_mission({{0, 100}, {300, 100}}, 200, 20);
  c["uavs"][0]["start"] = at(150, 100);
  for (const json& base : {a, c})
    for (const std::string corner : {"nw", "ne", "sw", "se"}) {
      json j = base;
      j["pattern"] = {{"entry", corner}};
      const Plan p = plan_of(j);
      const Point first = shot_runs(p.uavs[0]).front().front();
      const Point want = local_of(p, corner[1] == 'e' ? 300 : 0, corner[0] == 'n' ? 200 : 0);
      EXPECT_LT(seg_len(first, want), 20.0 * std::sqrt(2.0)) << corner << " " << base.contains("corridor");
    }
}

// alternate_transects: every other lane, then back over the rest (0, 2, 4, 3, 1 of five).
// The area gave 11 lanes: its width in the plan's frame is a hair over 200 m and leg_count took ceil with a
// 1e-9 tolerance; a lane count now ignores the last 0.1 % of a spacing (planners/boustrophedon/sweep.cpp).
TEST(Pattern, AlternateTransectsFlyEveryOtherLaneFirst) {
  json j = corridor_mission({{0, 0}, {500, 0}}, 100, 20);
  j["pattern"] = {{"alternate_transects", true}};
  const Plan p = plan_of(j);
  const auto runs = shot_runs(p.uavs[0]);
  ASSERT_EQ(runs.size(), 5u);
  const Point a = local_of(p, 0, 0), b = local_of(p, 500, 0);
  std::vector<long> order;
  for (const auto& r : runs)
    order.push_back(std::lround(
        ((r[0].x() - a.x()) * (b.y() - a.y()) - (r[0].y() - a.y()) * (b.x() - a.x())) / 500 / 20));
  // from one side: -2, 0, 2, 1, -1 (from either side, either way round)
  EXPECT_TRUE(same_up_to_symmetry(order, {-2, 0, 2, 1, -1}, [](long o) { return -o; }))
      << ::testing::PrintToString(order);
  // on an area with the boustrophedon planner too: the runs' order is 0, 2, 4, ..., then back
  json area = j;
  area.erase("corridor");
  area["area"] = {{"type", "Polygon"},
                  {"coordinates", {json::array({at(0, 0), at(200, 0), at(200, 100), at(0, 100), at(0, 0)})}}};
  area["planner_params"] = {{"angle_deg", 0}};
  const Plan q = plan_of(area);
  std::vector<long> xs;
  for (const auto& r : shot_runs(q.uavs[0]))
    xs.push_back(std::lround((r[0].x() - local_of(q, 0, 0).x()) / 20.0 - 0.5));
  ASSERT_EQ(xs.size(), 10u);
  EXPECT_TRUE(same_up_to_symmetry(xs, {0, 2, 4, 6, 8, 9, 7, 5, 3, 1}, [](long x) { return 9 - x; }))
      << ::testing::PrintToString(xs);
}

// What is refused, naming the field.
TEST(Pattern, RefusalsNameTheField) {
  const json c = corridor_mission({{0, 0}, {500, 0}}, 100, 20);
  EXPECT_EQ(field_of([&] { plan_of(corridor_mission({{0, 0}, {500, 0}}, 100, 20, "darp")); }), "corridor");
  json both = c;
  both["area"] = {{"type", "Polygon"},
                  {"coordinates", {json::array({at(0, 0), at(1, 0), at(1, 1), at(0, 0)})}}};
  EXPECT_EQ(field_of([&] { parse_mission(both.dump()); }), "corridor");
  json bad = c;
  bad["corridor"]["width_m"] = -3;
  EXPECT_EQ(field_of([&] { parse_mission(bad.dump()); }), "corridor.width_m");
  bad = c;
  bad["corridor"]["line"]["coordinates"] = json::array({at(0, 0)});
  EXPECT_EQ(field_of([&] { parse_mission(bad.dump()); }), "corridor.line.coordinates");
  bad = c;
  bad["pattern"] = {{"entry", "north"}};
  EXPECT_EQ(field_of([&] { parse_mission(bad.dump()); }), "pattern.entry");
  bad["pattern"] = {{"turnaround_m", -1}};
  EXPECT_EQ(field_of([&] { parse_mission(bad.dump()); }), "pattern.turnaround_m");
  bad["pattern"] = {{"oblique_typo", 1}};
  EXPECT_EQ(field_of([&] { parse_mission(bad.dump()); }), "pattern.oblique_typo");
  json darp = c;
  darp.erase("corridor");
  darp["area"] = {{"type", "Polygon"},
                  {"coordinates", {json::array({at(0, 0), at(200, 0), at(200, 100), at(0, 100), at(0, 0)})}}};
  darp["planner"] = "darp";
  darp["pattern"] = {{"crosshatch", true}};
  EXPECT_EQ(field_of([&] { plan_of(darp); }), "pattern.crosshatch");
}

// The normalised mission writes the corridor back, and reads as the same mission.
TEST(Corridor, RoundTripsThroughTheMissionJson) {
  json j = corridor_mission({{0, 0}, {500, 0}, {700, 300}}, 100, 20);
  j["pattern"] = {{"turnaround_m", 5}, {"entry", "se"}};
  const Mission m = parse_mission(j.dump());
  const json back = json::parse(mission_to_json(m));
  EXPECT_FALSE(back.contains("area"));
  const Mission again = parse_mission(back.dump());
  ASSERT_TRUE(again.corridor && again.pattern);
  EXPECT_EQ(again.corridor->line.size(), 3u);
  EXPECT_EQ(again.corridor->width_m, 100);
  EXPECT_EQ(again.pattern->entry, "se");
  EXPECT_EQ(again.area.size(), m.area.size());
  ASSERT_EQ(again.area[0][0].size(), m.area[0][0].size());
  for (std::size_t k = 0; k < m.area[0][0].size(); ++k) {
    EXPECT_NEAR(again.area[0][0][k].lon, m.area[0][0][k].lon, 1e-9);
    EXPECT_NEAR(again.area[0][0][k].lat, m.area[0][0][k].lat, 1e-9);
  }
}
