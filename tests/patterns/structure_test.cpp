// Structure (facade) scans (docs/patterns.md, issue 30), planned through the whole pipeline (parse_mission,
// plan, the facade evaluator) on buildings whose geometry a person can check by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>

#include "evaluation/evaluate.hpp"
#include "evaluation/facade.hpp"
#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "support/errors.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"

using namespace uavcover;
using nlohmann::json;

namespace {

constexpr double kLat = 45.0, kLon = 10.0;
constexpr double kPi = std::numbers::pi;

json at(double east_m, double north_m) {
  static const geodesy::LocalFrame f(LonLat{kLon, kLat});
  const LonLat p = f.to_wgs84(Point(east_m, north_m));
  return {p.lon, p.lat};
}

json footprint(const std::vector<std::pair<double, double>>& pts) {
  json ring = json::array();
  for (auto [e, n] : pts) ring.push_back(at(e, n));
  ring.push_back(ring.front());
  return {{"type", "Polygon"}, {"coordinates", {ring}}};
}

/// A DJI Phantom 4 Pro like camera (13.2 x 8.8 mm, 8.8 mm lens, 5472 x 3648 px): at 15 m from the wall a
/// photo is 22.5 m wide and 15 m high, 4.1 mm/px.
json qgc_camera(double side_overlap = 0.7, double front_overlap = 0.8) {
  return {{"altitude_m", 20},
          {"sensor_width_mm", 13.2},
          {"focal_length_mm", 8.8},
          {"image_width_px", 5472},
          {"image_height_px", 3648},
          {"side_overlap", side_overlap},
          {"front_overlap", front_overlap}};
}

/// The paper's convention (HFOV 73.4 degrees, overlap po 0.5 on both sides: a quarter), the default front
/// overlap (0.75) and the default 4:3 image.
json paper_camera() { return {{"altitude_m", 20}, {"hfov_deg", 73.4}, {"overlap", 0.5}}; }

/// A 30 m x 30 m building, 40 m high, orbited at 15 m.
json square_mission(const json& camera, int uavs = 1, const std::string& planner = "boustrophedon") {
  json u = json::array();
  const std::vector<std::pair<double, double>> starts{{0, -60}, {0, 60}, {60, 0}};
  for (int i = 0; i < uavs; ++i)
    u.push_back({{"id", "u" + std::to_string(i + 1)}, {"start", at(starts[i].first, starts[i].second)}});
  return {{"name", "square building"},
          {"structure",
           {{"footprint", footprint({{-15, -15}, {15, -15}, {15, 15}, {-15, 15}})},
            {"height_m", 40},
            {"standoff_m", 15}}},
          {"camera", camera},
          {"uavs", u},
          {"planner", planner},
          {"seed", 3}};
}

Plan plan_of(const json& j) { return plan(parse_mission(j.dump())); }

Polygon footprint_of(const Plan& p) {
  Polygon fp = geometry::to_local(p.mission.structure->footprint, geodesy::LocalFrame(p.origin));
  bg::correct(fp);
  return fp;
}

std::vector<const PathPart*> layers_of(const UavPlan& u) {
  std::vector<const PathPart*> out;
  for (const auto& part : u.parts)
    if (part.kind == PartKind::Coverage && part.attitude.gimbal_pitch_deg &&
        *part.attitude.gimbal_pitch_deg == 0)
      out.push_back(&part);
  return out;
}

/// `f` throws an InputError naming `field` whose message mentions `word`.
void expect_refused(const std::function<void()>& f, const std::string& field, const std::string& word) {
  try {
    f();
    ADD_FAILURE() << "accepted; expected a refusal naming " << field;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.field()), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
  }
}

double angle_diff(double a, double b) { return std::fabs(std::fmod(a - b + 540.0, 360.0) - 180.0); }

}  // namespace

// 40 m wall, the photo 15 m high at 15 m, side overlap 0.7: layers 4.5 m apart, the bottom one at the
// safe height 5 m (above 4.5 / 2), then every 4.5 m until the top one is within 2.25 m of 40 m: 5, 9.5,
// ..., 41 (nine). Every waypoint is 15 m from the footprint, the camera horizontal, facing the wall, and
// shooting every 22.5 * (1 - 0.8) = 4.5 m.
TEST(Structure, SquareBuildingGivesLayersAtTheRightHeightsFacingTheWalls) {
  const Plan p = plan_of(square_mission(qgc_camera()));
  ASSERT_EQ(p.uavs.size(), 1u);
  const Polygon fp = footprint_of(p);
  const auto layers = layers_of(p.uavs[0]);
  std::vector<double> heights;
  for (const auto* l : layers) heights.push_back(*l->attitude.altitude_m);
  const std::vector<double> expected{5, 9.5, 14, 18.5, 23, 27.5, 32, 36.5, 41};
  ASSERT_EQ(heights.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k) EXPECT_NEAR(heights[k], expected[k], 1e-6) << k;
  int checked = 0;
  for (const auto* l : layers) {
    ASSERT_EQ(l->attitude.heading_deg.size(), l->local.size());
    ASSERT_TRUE(l->attitude.trigger_distance_m);
    EXPECT_NEAR(*l->attitude.trigger_distance_m, 4.5, 1e-9);
    // a closed loop around the building: 4 sides of 30 m and four quarter circles of 15 m
    EXPECT_NEAR(geometry::length(l->local), 120 + 2 * kPi * 15, 0.5);
    EXPECT_LT(bg::distance(l->local.front(), l->local.back()), 1e-6);
    for (std::size_t k = 0; k < l->local.size(); ++k) {
      const Point q = l->local[k];
      EXPECT_NEAR(bg::distance(q, fp), 15.0, 0.5) << "waypoint " << k;
      // 15.5 m along the heading lands in (or on) the footprint: the camera looks at the wall
      const double h = l->attitude.heading_deg[k] * kPi / 180;
      const Point ahead(q.x() + 15.5 * std::sin(h), q.y() + 15.5 * std::cos(h));
      EXPECT_LT(bg::distance(ahead, fp), 1e-6)
          << "waypoint " << k << " heading " << l->attitude.heading_deg[k];
      // on a straight side the heading is the inward normal: towards the nearest point of the wall
      const Point c(0.25 * (fp.outer()[0].x() + fp.outer()[1].x() + fp.outer()[2].x() + fp.outer()[3].x()),
                    0.25 * (fp.outer()[0].y() + fp.outer()[1].y() + fp.outer()[2].y() + fp.outer()[3].y()));
      const double dx = q.x() - c.x(), dy = q.y() - c.y();
      double expected = -1;  // north side: facing south, and so on
      if (std::fabs(dx) < 15.01) expected = dy > 0 ? 180 : 0;
      if (std::fabs(dy) < 15.01) expected = dx > 0 ? 270 : 90;
      if (expected >= 0) {
        EXPECT_LT(angle_diff(l->attitude.heading_deg[k], expected), 3) << "waypoint " << k;
        ++checked;
      }
    }
  }
  EXPECT_GE(checked, 8 * 9);  // every side's two ends in each layer
  // the transit legs keep out of the building
  for (const auto& part : p.uavs[0].parts) {
    if (part.kind != PartKind::Transit) continue;
    for (std::size_t k = 1; k < part.local.size(); ++k)
      EXPECT_FALSE(geometry::segment_enters(fp, part.local[k - 1], part.local[k], 0.01));
  }
  EXPECT_EQ(p.diagnostics["structure"]["layers_m"].size(), 9u);
}

// The facade evaluator on that plan: the whole wall is seen, almost all of it by 3 or more photos; the
// paper's camera with its default front overlap (0.75) and a quarter side overlap does so too.
TEST(Structure, FacadeIsCoveredWithThreeViewsOrMoreForDefaultOverlaps) {
  for (const json& camera : {qgc_camera(), paper_camera()}) {
    const Plan p = plan_of(square_mission(camera));
    const auto f = evaluation::evaluate_facade(p);
    ASSERT_TRUE(f);
    // 4 walls of 30 m at 0.5 m: 240 columns, 80 rows
    EXPECT_NEAR(f->cols, 240, 4);
    EXPECT_EQ(f->rows, 80);
    EXPECT_EQ(f->wall_samples, f->cols * 80);
    EXPECT_GE(f->total.covered_share, 0.95) << camera.dump();
    EXPECT_GE(f->total.share_3plus, 0.8) << camera.dump();
    EXPECT_GT(f->total.images, 0);
    // the evaluation block of plan.json carries it
    const auto ev = evaluation::evaluate_plan(p);
    ASSERT_TRUE(ev.facade);
    const json j = evaluation::to_json(ev);
    ASSERT_TRUE(j.contains("facade"));
    EXPECT_DOUBLE_EQ(j["facade"]["covered_share"].get<double>(), f->total.covered_share);
    EXPECT_EQ(j["facade"]["unrolled"]["views"].size(), 80u);
  }
  // GSD on the wall at 15 m: 15 * 13.2 / (8.8 * 5472) = 4.11 mm/px
  const auto f = evaluation::evaluate_facade(plan_of(square_mission(qgc_camera())));
  ASSERT_TRUE(f && f->gsd_wall_m);
  EXPECT_NEAR(*f->gsd_wall_m, 15 * 13.2 / (8.8 * 5472), 1e-9);
}

// The evaluator can fail. The paper's camera (photos 16.8 m high at 15 m, layers 12.6 m apart at 6.3, 18.9,
// 31.5 and 44.1 m): without the bottom layer the next one sees the wall from 18.9 - 8.4 = 10.5 m up in front
// of it, and from about 5 m up obliquely (arc photos up to 60 degrees off the wall's normal, deeper
// away); the foot of the wall is seen by nobody. Without a middle layer its band is seen less.
TEST(Structure, RemovingALayerDropsTheFacadeCoverage) {
  const Plan full_plan = plan_of(square_mission(paper_camera()));
  const auto full = evaluation::evaluate_facade(full_plan);
  const auto layers = layers_of(full_plan.uavs[0]);
  ASSERT_EQ(layers.size(), 4u);
  EXPECT_NEAR(*layers[0]->attitude.altitude_m, 6.3, 0.05);
  auto without = [&](double height) {
    Plan p = full_plan;
    auto& parts = p.uavs[0].parts;
    parts.erase(std::find_if(parts.begin(), parts.end(), [height](const PathPart& q) {
      return q.kind == PartKind::Coverage && q.attitude.altitude_m && *q.attitude.altitude_m == height;
    }));
    return evaluation::evaluate_facade(p);
  };
  const auto no_bottom = without(*layers[0]->attitude.altitude_m);
  EXPECT_LT(no_bottom->total.covered_share, full->total.covered_share - 0.08);
  for (int c = 0; c < no_bottom->cols; ++c) EXPECT_EQ(no_bottom->views[static_cast<std::size_t>(c)], 0) << c;
  const auto no_middle = without(*layers[1]->attitude.altitude_m);
  EXPECT_LT(no_middle->total.covered_share, full->total.covered_share - 0.02);
  EXPECT_LT(no_middle->total.share_3plus, full->total.share_3plus - 0.1);
}

// Two UAVs: every layer is flown once all round the building, by one UAV at a time at any place: each
// height's flown length adds up to one orbit, sectors' regions do not overlap and shared layers keep the
// UAVs in separate height blocks. The strategy chosen is the one the planner estimated to finish sooner.
TEST(Structure, TwoUavsShareTheFacadeWithoutOverlap) {
  std::set<std::string> strategies;
  for (const json& camera : {qgc_camera(), paper_camera(), qgc_camera(0.6, 0.75)}) {
    const Plan p = plan_of(square_mission(camera, 2));
    ASSERT_EQ(p.uavs.size(), 2u);
    const json& d = p.diagnostics["structure"];
    const std::string strategy = d["strategy"];
    strategies.insert(strategy);
    const double mine = d["estimated_finish_min"][strategy].get<double>();
    const double other = d["estimated_finish_min"][strategy == "layers" ? "sectors" : "layers"].get<double>();
    EXPECT_LE(mine, other + 1e-9);
    const double orbit = d["orbit_length_m"].get<double>();
    std::map<long, double> per_height;
    std::map<long, std::set<std::size_t>> who;
    for (std::size_t i = 0; i < 2; ++i) {
      EXPECT_FALSE(layers_of(p.uavs[i]).empty()) << "UAV " << i << " has no work";
      for (const auto* l : layers_of(p.uavs[i])) {
        const long key = std::lround(*l->attitude.altitude_m * 1000);
        per_height[key] += geometry::length(l->local);
        who[key].insert(i);
      }
    }
    for (const auto& [h, len] : per_height) EXPECT_NEAR(len, orbit, 0.01 * orbit) << "height " << h / 1000.0;
    if (strategy == "sectors") {
      MultiPolygon both;
      bg::intersection(p.uavs[0].region_local, p.uavs[1].region_local, both);
      EXPECT_LT(bg::area(both), 1e-3 * bg::area(p.uavs[0].region_local));
      EXPECT_GT(bg::area(p.uavs[0].region_local), 0);
      EXPECT_GT(bg::area(p.uavs[1].region_local), 0);
    } else {
      for (const auto& [h, uavs] : who) EXPECT_EQ(uavs.size(), 1u) << "height " << h / 1000.0;
      EXPECT_GE(d["vertical_separation"]["min_m"].get<double>(), d["layer_spacing_m"].get<double>() - 1e-9);
    }
    const auto f = evaluation::evaluate_facade(p);
    EXPECT_GE(f->total.covered_share, 0.95) << camera.dump();
    // each UAV sees its share of the wall: neither sees all of it on its own
    EXPECT_LT(f->uavs[0].covered_share, 0.9);
    EXPECT_LT(f->uavs[1].covered_share, 0.9);
  }
  EXPECT_EQ(strategies.size(), 2u) << "both strategies should be exercised by these cameras";
}

// top: a nadir pass over the roof at height_m + the camera's altitude (40 + 20 m), lanes inside the
// footprint, camera pointing down; the roof's samples are seen.
TEST(Structure, TopAddsANadirPassOverTheRoof) {
  json j = square_mission(qgc_camera());
  j["structure"]["top"] = true;
  const Plan p = plan_of(j);
  const Polygon fp = footprint_of(p);
  const PathPart* roof = nullptr;
  for (const auto& part : p.uavs[0].parts)
    if (part.kind == PartKind::Coverage && part.attitude.gimbal_pitch_deg &&
        *part.attitude.gimbal_pitch_deg == -90)
      roof = &part;
  ASSERT_NE(roof, nullptr);
  EXPECT_NEAR(*roof->attitude.altitude_m, 60.0, 1e-9);
  // its shot lanes lie over the roof
  int lanes = 0;
  for (std::size_t k = 0; k + 1 < roof->local.size(); ++k)
    if (roof->camera_on(k)) {
      ++lanes;
      EXPECT_LT(bg::distance(roof->local[k], fp), 1e-6);
      EXPECT_LT(bg::distance(roof->local[k + 1], fp), 1e-6);
    }
  EXPECT_GE(lanes, 1);
  const auto f = evaluation::evaluate_facade(p);
  EXPECT_NEAR(f->roof_samples, 60 * 60, 130);
  EXPECT_GE(f->total.covered_share, 0.95);
}

TEST(Structure, RefusesWhatItCannotPlanNamingTheField) {
  expect_refused([] { (void)plan_of(square_mission(qgc_camera(), 1, "darp")); }, "structure", "darp");
  json j = square_mission(qgc_camera());
  j["uavs"][0]["start"] = at(0, 0);
  expect_refused([&] { (void)plan_of(j); }, "uavs[0].start", "structure");
  j = square_mission(qgc_camera());
  j["pattern"] = {{"crosshatch", true}};
  expect_refused([&] { (void)plan_of(j); }, "pattern.crosshatch", "structure");
  // planners list the capability
  int with = 0;
  for (const auto& d : available_planners()) with += d.schema["supports"]["structure"].get<bool>() ? 1 : 0;
  EXPECT_GE(with, 1);
}
