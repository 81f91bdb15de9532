// Obliques (Smart Oblique style, docs/patterns.md "Obliques", issue 30): the tilted camera's trapezoid
// (Balampanis et al. 2017, eq. 6-8) against hand-computed numbers, the passes the boustrophedon planner
// flies (fixed headings, the area grown by h tan(tilt)), their coverage, the refusals, determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "evaluation/evaluate.hpp"
#include "geodesy/local_frame.hpp"
#include "photo/oblique.hpp"
#include "planners/planner.hpp"
#include "support/errors.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"

using namespace uavcover;
using nlohmann::json;
using uavcover::testing::field_of;

namespace {

constexpr double kLat = 45.0, kLon = 10.0;

LonLat ll_at(double east_m, double north_m) {
  static const geodesy::LocalFrame f(LonLat{kLon, kLat});
  return f.to_wgs84(Point(east_m, north_m));
}
json at(double east_m, double north_m) {
  const LonLat p = ll_at(east_m, north_m);
  return {p.lon, p.lat};
}

/// A 300 m square field, camera at 100 m with hfov 60 and vfov 45 degrees (nadir footprint 115.5 x 82.8 m,
/// spacing (2 - 1.4) * 100 tan 30 = 34.6 m), legs north-south (angle_deg 0): headings 0, 90, 180, 270.
json oblique_mission(int uavs = 1, const std::string& planner = "boustrophedon") {
  json u = json::array();
  for (int i = 0; i < uavs; ++i)
    u.push_back({{"id", "u" + std::to_string(i + 1)}, {"start", at(-50.0 * i, -50)}});
  json j = {{"name", "oblique"},
            {"area",
             {{"type", "Polygon"},
              {"coordinates", {json::array({at(0, 0), at(300, 0), at(300, 300), at(0, 300), at(0, 0)})}}}},
            {"camera", {{"altitude_m", 100}, {"hfov_deg", 60}, {"vfov_deg", 45}, {"overlap", 1.4}}},
            {"pattern", {{"oblique", {{"gimbal_pitch_deg", -45}, {"directions", 4}, {"nadir", true}}}}},
            {"uavs", u},
            {"planner", planner},
            {"seed", 3}};
  if (planner == "boustrophedon") j["planner_params"] = {{"angle_deg", 0}};
  return j;
}

Plan plan_of(const json& j) { return plan(parse_mission(j.dump())); }

bool is_oblique(const PathPart& part) {
  return part.kind == PartKind::Coverage && part.attitude.gimbal_pitch_deg &&
         *part.attitude.gimbal_pitch_deg > -90;
}

}  // namespace

// The trapezoid at h = 100 m, pitch -45 (tilt 45), hfov 60, vfov 45, worked by hand:
//   near edge h tan(45 - 22.5) = 41.421 m ahead, far edge h tan(67.5) = 241.421 m, axis at h tan 45 = 100 m;
//   an edge at e from nadir is 2 h tan(30) cos(22.5) / cos(e) long: near 115.470 m (e = 22.5: the cosines
//   cancel), far 115.470 * cos 22.5 / cos 67.5 = 115.470 * 2.41421 = 278.769 m.
TEST(ObliqueFootprint, TrapezoidMatchesHandComputedNumbers) {
  const photo::ObliqueFootprint f = photo::oblique_footprint(100, -45, 60, 45);
  EXPECT_NEAR(f.near_m, 41.4214, 1e-3);
  EXPECT_NEAR(f.far_m, 241.4214, 1e-3);
  EXPECT_NEAR(f.centre_m, 100.0, 1e-9);
  EXPECT_NEAR(f.near_width_m, 115.4701, 1e-3);
  EXPECT_NEAR(f.far_width_m, 278.7694, 1e-3);
  EXPECT_NEAR(f.depth_m(), 200.0, 1e-9);
  // looking straight down it is the nadir rectangle 2 h tan(hfov/2) x 2 h tan(vfov/2), centred below
  const photo::ObliqueFootprint n = photo::oblique_footprint(100, -90, 60, 45);
  EXPECT_NEAR(n.near_m, -41.4214, 1e-3);
  EXPECT_NEAR(n.far_m, 41.4214, 1e-3);
  EXPECT_NEAR(n.near_width_m, 115.4701, 1e-3);
  EXPECT_NEAR(n.far_width_m, 115.4701, 1e-3);
  // the corners on the ground, camera facing east (90) from (0, 0): near edge at x = 41.4, far at 241.4
  const auto c = photo::footprint_corners(f, Point(0, 0), 90);
  EXPECT_NEAR(c[0].x(), 41.4214, 1e-3);
  EXPECT_NEAR(c[0].y(), 57.735, 1e-3);  // near-left is north of the track when facing east
  EXPECT_NEAR(c[1].y(), -57.735, 1e-3);
  EXPECT_NEAR(c[2].x(), 241.4214, 1e-3);
  EXPECT_NEAR(c[2].y(), -139.385, 1e-3);
  // every corner's ray from the camera (0, 0, 100) makes hfov/2 with the vertical plane through the axis
  // at its image row: lateral offset / distance along the axis's ground direction and height = tan 30
  // cos 22.5
  for (const auto& p : c) {
    const double ahead = p.x(), lateral = std::abs(p.y());
    EXPECT_NEAR(lateral / std::hypot(ahead, 100.0), std::tan(M_PI / 6) * std::cos(M_PI / 8), 1e-9);
  }
  // trigger distance, front overlap 0.75: along the axis a quarter of the depth (50 m), across it a
  // quarter of the near width (28.9 m)
  EXPECT_NEAR(photo::oblique_trigger_distance(f, 0, 0, 0.75), 50.0, 1e-9);
  EXPECT_NEAR(photo::oblique_trigger_distance(f, 0, 90, 0.75), 28.8675, 1e-3);
  EXPECT_NEAR(photo::oblique_trigger_distance(f, 180, 0, 0.75), 50.0, 1e-9);
}

// Each pass keeps one heading, every vertex; the passes face the lane direction and its quarter turns;
// nadir parts keep the mission's attitude; the passes come after the nadir grid.
TEST(Oblique, HeadingsAreFixedPerPass) {
  const Plan p = plan_of(oblique_mission());
  std::vector<double> order;  // headings in flight order, one entry per change
  bool seen_oblique = false;
  int nadir_parts = 0;
  for (const auto& part : p.uavs[0].parts) {
    if (part.kind != PartKind::Coverage) continue;
    if (!is_oblique(part)) {
      EXPECT_FALSE(seen_oblique) << "a nadir part after the obliques";
      EXPECT_TRUE(part.attitude.empty());
      ++nadir_parts;
      continue;
    }
    seen_oblique = true;
    EXPECT_EQ(*part.attitude.gimbal_pitch_deg, -45);
    ASSERT_EQ(part.attitude.heading_deg.size(), part.local.size());
    for (double h : part.attitude.heading_deg) EXPECT_EQ(h, part.attitude.heading_deg.front());
    if (order.empty() || order.back() != part.attitude.heading_deg.front())
      order.push_back(part.attitude.heading_deg.front());
  }
  EXPECT_GT(nadir_parts, 0);
  ASSERT_EQ(order.size(), 4u);  // one run per direction: each pass flown whole
  std::set<long> headings;
  for (double h : order) headings.insert(std::lround(h));
  EXPECT_EQ(headings, (std::set<long>{0, 90, 180, 270}));
}

// The area each pass flies grows by h tan(tilt) = 100 m on the side away from where the camera faces (so
// the camera looks back over the edge): the north-facing pass reaches 100 m south of the field, and no
// further than that plus the sweep's half spacing; it stops at the north edge.
TEST(Oblique, PassesFlyTheAreaGrownBehindTheCamera) {
  const Plan p = plan_of(oblique_mission());
  const geodesy::LocalFrame frame(p.origin);
  const Point sw = frame.to_local(ll_at(0, 0)), ne = frame.to_local(ll_at(300, 300));
  std::map<long, std::array<double, 4>> box;  // heading -> min x, max x, min y, max y
  for (const auto& part : p.uavs[0].parts) {
    if (!is_oblique(part)) continue;
    auto& b = box.try_emplace(std::lround(part.attitude.heading_deg.front()),
                              std::array<double, 4>{1e9, -1e9, 1e9, -1e9})
                  .first->second;
    for (const auto& q : part.local)
      b = {std::min(b[0], q.x()), std::max(b[1], q.x()), std::min(b[2], q.y()), std::max(b[3], q.y())};
  }
  ASSERT_EQ(box.size(), 4u);
  const double half = 0.5 * 34.64 + 1.0;
  // facing north (0): legs from y = south - 100 to north
  EXPECT_NEAR(box[0][2], sw.y() - 100, 0.5);
  EXPECT_NEAR(box[0][3], ne.y(), 0.5);
  // facing south (180): from south to north + 100
  EXPECT_NEAR(box[180][2], sw.y(), 0.5);
  EXPECT_NEAR(box[180][3], ne.y() + 100, 0.5);
  // facing east (90): lanes from west - 100 (within half a spacing) to east
  EXPECT_LT(box[90][0], sw.x() - 100 + half);
  EXPECT_GT(box[90][0], sw.x() - 100);
  EXPECT_LT(box[90][1], ne.x());
  EXPECT_GT(box[90][1], ne.x() - half);
  // facing west (270)
  EXPECT_GT(box[270][1], ne.x() + 100 - half);
  EXPECT_LT(box[270][1], ne.x() + 100);
  EXPECT_GT(box[270][0], sw.x());
}

// Every direction's oblique footprints reach the field's edges: each direction alone sees >= 95 % of the
// field, and the nadir grid too.
TEST(Oblique, FootprintsReachTheFieldEdges) {
  for (int uavs : {1, 2}) {
    const Plan p = plan_of(oblique_mission(uavs));
    const auto ev = evaluation::evaluate_plan(p);
    ASSERT_TRUE(ev.coverage.nadir_poc);
    EXPECT_GT(*ev.coverage.nadir_poc, 0.98) << uavs;
    ASSERT_EQ(ev.coverage.oblique.size(), 4u);
    for (const auto& d : ev.coverage.oblique) {
      EXPECT_GE(d.poc, 0.95) << uavs << " UAVs, heading " << d.heading_deg;
      EXPECT_EQ(d.gimbal_pitch_deg, -45);
    }
    const json j = evaluation::evaluation_json(ev);
    ASSERT_TRUE(j.contains("oblique"));
    EXPECT_EQ(j["oblique"]["directions"].size(), 4u);
    // the photogrammetry estimate counts the oblique images
    ASSERT_TRUE(ev.images);
    EXPECT_GT(ev.images->oblique_images, 0);
    EXPECT_LT(ev.images->oblique_images, ev.images->images);
  }
}

// Two UAVs on an L-shaped field, the sweep direction left to the planner: both fly the same four headings
// (from the division's direction), and each direction alone still sees >= 95 % of the field.
TEST(Oblique, SharedAmongUavsOnAnLShape) {
  json j = oblique_mission(2);
  j.erase("planner_params");
  j["area"]["coordinates"] = {
      json::array({at(0, 0), at(400, 0), at(400, 200), at(200, 200), at(200, 400), at(0, 400), at(0, 0)})};
  j["uavs"][0]["start"] = at(-30, -30);
  j["uavs"][1]["start"] = at(430, -30);
  // (the case where the region swept north of the east UAV's part once lost its area in the overlay: edges
  // nearly along the growth)
  j["camera"] = {{"altitude_m", 80}, {"hfov_deg", 70}, {"vfov_deg", 50}, {"overlap", 1.4}};
  j["pattern"]["oblique"]["gimbal_pitch_deg"] = -50;
  j["no_fly_zones"] = json::array(
      {{{"type", "Polygon"},
        {"coordinates",
         {json::array({at(250, -90), at(350, -90), at(350, -30), at(250, -30), at(250, -90)})}}}});
  const Plan p = plan_of(j);
  std::array<std::set<long>, 2> headings;
  for (std::size_t u = 0; u < 2; ++u)
    for (const auto& part : p.uavs[u].parts)
      if (is_oblique(part)) headings[u].insert(std::lround(part.attitude.heading_deg.front() * 1000));
  EXPECT_EQ(headings[0].size(), 4u);
  EXPECT_EQ(headings[0], headings[1]);
  const auto ev = evaluation::evaluate_plan(p);
  ASSERT_EQ(ev.coverage.oblique.size(), 4u);
  for (const auto& d : ev.coverage.oblique) EXPECT_GE(d.poc, 0.95) << d.heading_deg;
  EXPECT_GT(*ev.coverage.nadir_poc, 0.98);
  // every pass's grown area is at least its UAV's region (diagnostics.oblique_passes[].area_m2)
  for (const auto& u : p.uavs)
    for (const auto& pass : u.diagnostics["oblique_passes"])
      EXPECT_GE(pass["area_m2"].get<double>(), 0.99 * bg::area(u.region_local)) << u.id;
}

// The growth matters: the same passes flown over the field itself (no growth) leave a strip along the edge
// behind the camera unseen (h tan(tilt - vfov/2) = 41 m of 300 m): each direction sees < 90 %.
TEST(Oblique, WithoutTheGrowthTheEdgesAreMissed) {
  const Plan p = plan_of(oblique_mission());
  const auto grown = evaluation::evaluate_plan(p);
  // the nadir grid's parts (the lanes over the field), flown again with each oblique heading
  std::vector<PathPart> nadir;
  for (const auto& part : p.uavs[0].parts)
    if (part.kind == PartKind::Coverage && !is_oblique(part)) nadir.push_back(part);
  ASSERT_FALSE(nadir.empty());
  evaluation::Flight flight;
  for (double heading : {0.0, 90.0, 180.0, 270.0})
    for (PathPart part : nadir) {
      part.attitude.gimbal_pitch_deg = -45;
      part.attitude.heading_deg.assign(part.local.size(), heading);
      flight.push_back(std::move(part));
    }
  evaluation::CoverageOptions o;
  o.footprint_m = grown.footprint_m;
  o.lattice_m = grown.coverage.lattice_m;
  o.altitude_m = 100;
  o.hfov_deg = 60;
  o.vfov_deg = 45;
  const auto cov = evaluation::evaluate_coverage(grown.free, {flight}, o);
  ASSERT_EQ(cov.oblique.size(), 4u);
  for (const auto& d : cov.oblique) EXPECT_LT(d.poc, 0.9) << d.heading_deg;
  for (const auto& d : grown.coverage.oblique) EXPECT_GE(d.poc, 0.95) << d.heading_deg;
}

// The grown area leaves the field but never enters a no-fly zone; two UAVs' passes stay out of each
// other's regions.
TEST(Oblique, GrownPassesStayOutOfNoFlyZonesAndOtherRegions) {
  json j = oblique_mission(2);
  // a zone south of the field, where the north-facing pass would fly
  j["no_fly_zones"] = json::array(
      {{{"type", "Polygon"},
        {"coordinates",
         {json::array({at(100, -80), at(200, -80), at(200, -20), at(100, -20), at(100, -80)})}}}});
  const Plan p = plan_of(j);
  const geodesy::LocalFrame frame(p.origin);
  MultiPolygon zone;
  zone.emplace_back();
  for (const auto& q : {ll_at(100, -80), ll_at(200, -80), ll_at(200, -20), ll_at(100, -20), ll_at(100, -80)})
    zone[0].outer().push_back(frame.to_local(q));
  bg::correct(zone);
  int oblique_parts = 0;
  for (std::size_t u = 0; u < p.uavs.size(); ++u)
    for (const auto& part : p.uavs[u].parts) {
      if (!is_oblique(part)) continue;
      ++oblique_parts;
      const Polyline line(part.local.begin(), part.local.end());
      EXPECT_FALSE(bg::intersects(line, zone)) << p.uavs[u].id;
      const auto& other = p.uavs[1 - u].region_local;
      for (const auto& q : part.local) EXPECT_GT(bg::distance(q, other), 0.01) << p.uavs[u].id;
    }
  EXPECT_GT(oblique_parts, 8);
}

// Only the nadir grid's absence: nadir false flies the oblique passes alone.
TEST(Oblique, NadirFalseFliesObliquesOnly) {
  json j = oblique_mission();
  j["pattern"]["oblique"]["nadir"] = false;
  j["pattern"]["oblique"]["directions"] = 2;
  const Plan p = plan_of(j);
  std::set<long> headings;
  for (const auto& part : p.uavs[0].parts) {
    if (part.kind != PartKind::Coverage) continue;
    ASSERT_TRUE(is_oblique(part));
    headings.insert(std::lround(part.attitude.heading_deg.front()));
  }
  EXPECT_EQ(headings, (std::set<long>{0, 180}));
  const auto ev = evaluation::evaluate_plan(p);
  EXPECT_EQ(*ev.coverage.nadir_poc, 0.0);
  EXPECT_EQ(ev.coverage.oblique.size(), 2u);
}

TEST(Oblique, RefusalsNameTheField) {
  auto with = [](const std::function<void(json&)>& edit) {
    json j = oblique_mission();
    edit(j);
    return field_of([&] { plan_of(j); });
  };
  EXPECT_EQ(with([](json& j) { j["pattern"]["oblique"]["gimbal_pitch_deg"] = -90; }),
            "pattern.oblique.gimbal_pitch_deg");
  EXPECT_EQ(with([](json& j) { j["pattern"]["oblique"]["gimbal_pitch_deg"] = 0; }),
            "pattern.oblique.gimbal_pitch_deg");
  EXPECT_EQ(with([](json& j) { j["pattern"]["oblique"]["gimbal_pitch_deg"] = "steep"; }),
            "pattern.oblique.gimbal_pitch_deg");
  // -30 with vfov 45: the far edge at 60 + 22.5 = 82.5 degrees from nadir, beyond 80
  EXPECT_EQ(with([](json& j) { j["pattern"]["oblique"]["gimbal_pitch_deg"] = -30; }),
            "pattern.oblique.gimbal_pitch_deg");
  EXPECT_EQ(with([](json& j) { j["pattern"]["oblique"]["gimbal_pitch_deg"] = -33; }), "(no error)");
  EXPECT_EQ(with([](json& j) { j["pattern"]["oblique"]["directions"] = 0; }), "pattern.oblique.directions");
  EXPECT_EQ(with([](json& j) { j["pattern"]["oblique"]["directions"] = 9; }), "pattern.oblique.directions");
  EXPECT_EQ(with([](json& j) { j["pattern"]["oblique"]["directions"] = 2.5; }), "pattern.oblique.directions");
  EXPECT_EQ(with([](json& j) { j["pattern"]["oblique"]["nadir"] = "yes"; }), "pattern.oblique.nadir");
  EXPECT_EQ(with([](json& j) { j["pattern"]["oblique"]["tilt"] = 3; }), "pattern.oblique.tilt");
  EXPECT_EQ(with([](json& j) { j["pattern"]["oblique"] = 4; }), "pattern.oblique");
  EXPECT_EQ(with([](json& j) {
              j.erase("camera");
              j["spacing_m"] = 30;
            }),
            "pattern.oblique");
  EXPECT_EQ(with([](json& j) {
              j["pattern"]["oblique"]["nadir"] = false;
              j["pattern"]["crosshatch"] = true;
            }),
            "pattern.crosshatch");
  EXPECT_EQ(with([](json& j) {
              j["uavs"][0]["camera"] = {{"altitude_m", 100}, {"hfov_deg", 50}, {"overlap", 1.4}};
            }),
            "uavs[0].camera");
  // the planners that do not fly obliques, by the capabilities table
  for (const auto& info : planners::registry()) {
    if (info.name == "boustrophedon") {
      EXPECT_TRUE(info.supports.oblique);
      continue;
    }
    EXPECT_FALSE(info.supports.oblique) << info.name;
    EXPECT_EQ(with([&](json& j) {
                j["planner"] = info.name;
                j.erase("planner_params");
              }),
              "pattern.oblique")
        << info.name;
  }
  // corridors: obliques are planned over areas
  EXPECT_EQ(with([](json& j) {
              j.erase("area");
              j["corridor"] = {{"line", {{"type", "LineString"}, {"coordinates", {at(0, 0), at(500, 0)}}}},
                               {"width_m", 100}};
            }),
            "pattern.oblique");
}

TEST(Oblique, IsDeterministicAndRoundTrips) {
  const json j = oblique_mission(2);
  const Plan a = plan_of(j), b = plan_of(j);
  ASSERT_EQ(a.uavs.size(), b.uavs.size());
  for (std::size_t u = 0; u < a.uavs.size(); ++u) {
    ASSERT_EQ(a.uavs[u].parts.size(), b.uavs[u].parts.size());
    for (std::size_t k = 0; k < a.uavs[u].parts.size(); ++k) {
      const auto &pa = a.uavs[u].parts[k], &pb = b.uavs[u].parts[k];
      ASSERT_EQ(pa.local.size(), pb.local.size());
      for (std::size_t i = 0; i < pa.local.size(); ++i) {
        EXPECT_EQ(pa.local[i].x(), pb.local[i].x());
        EXPECT_EQ(pa.local[i].y(), pb.local[i].y());
      }
      EXPECT_EQ(pa.attitude.heading_deg, pb.attitude.heading_deg);
      EXPECT_EQ(pa.attitude.gimbal_pitch_deg, pb.attitude.gimbal_pitch_deg);
      EXPECT_EQ(pa.attitude.trigger_distance_m, pb.attitude.trigger_distance_m);
    }
  }
  // the normalised mission writes the oblique block back
  json edited = j;
  edited["pattern"]["oblique"] = {{"gimbal_pitch_deg", -60}, {"directions", 3}, {"nadir", false}};
  const Mission m = parse_mission(edited.dump());
  const json back = json::parse(mission_to_json(m));
  EXPECT_EQ(back["pattern"]["oblique"]["gimbal_pitch_deg"], -60);
  EXPECT_EQ(back["pattern"]["oblique"]["directions"], 3);
  EXPECT_EQ(back["pattern"]["oblique"]["nadir"], false);
  const Mission again = parse_mission(back.dump());
  ASSERT_TRUE(again.pattern && again.pattern->oblique);
  EXPECT_EQ(again.pattern->oblique->directions, 3);
  // defaults: pitch -45, 4 directions, nadir true
  edited["pattern"]["oblique"] = json::object();
  const Mission d = parse_mission(edited.dump());
  EXPECT_EQ(d.pattern->oblique->gimbal_pitch_deg, -45);
  EXPECT_EQ(d.pattern->oblique->directions, 4);
  EXPECT_TRUE(d.pattern->oblique->nadir);
}
