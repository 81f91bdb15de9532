// The evaluation over a GDAL-written hill: each coverage footprint is sized by the height above the
// ground under it, so it shrinks over the hill when the UAV flies flat and stays the camera's when it
// follows the terrain.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "evaluation/evaluate.hpp"
#include "io/dem.hpp"
#include "support/terrain_mission.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover {
namespace {

using testdem::Hill;
using testdem::kOrigin;
using testdem::TempDir;

const Hill kLowHill{200, 20, 50, 0, 0};
const double kFootprint = 2 * 40 * std::tan(30 * std::numbers::pi / 180);  // HFOV 60° at 40 m

// One UAV flying one straight coverage leg over the hill's top, west to east along y = 0.
Plan one_leg(const TempDir& dir, const std::string& mode) {
  testdem::write_hill(dir.path / "hill.tif", geodesy::LocalFrame(kOrigin), kLowHill);
  Mission m = parse_mission(testdem::mission_text("hill.tif", mode));
  io::load_terrain(m, dir.path);
  Plan p;
  p.origin = geodesy::centroid(m.area);
  p.mission = m;
  const geodesy::LocalFrame f(p.origin);
  const geodesy::LocalFrame hf(kOrigin);
  UavPlan u;
  u.id = "a";
  PathPart leg{PartKind::Coverage, {}, {}};
  for (const double x : {-140.0, 140.0}) {
    const LonLat g = hf.to_wgs84({x, 0});
    leg.wgs84.push_back(g);
    leg.local.push_back(f.to_local(g));
  }
  u.parts.push_back(leg);
  p.uavs.push_back(u);
  return p;
}

// Width of the scanned band (metres) in the lattice column nearest local x (the hill's frame)
double band_width(const evaluation::CoverageResult& c, const Plan& p, double x) {
  const Point q = geodesy::LocalFrame(p.origin).to_local(geodesy::LocalFrame(kOrigin).to_wgs84({x, 0}));
  const int col = static_cast<int>(std::lround((q.x() - c.lattice_origin.x()) / c.lattice_m));
  int n = 0;
  for (int r = 0; r < c.lattice_rows; ++r)
    n += c.scans[static_cast<std::size_t>(r) * static_cast<std::size_t>(c.lattice_cols) +
                 static_cast<std::size_t>(col)] > 0
             ? 1
             : 0;
  return n * c.lattice_m;
}

TEST(TerrainEvaluation, FlyingFlatTheFootprintShrinksOverTheHillAndGrowsBeyond) {
  TempDir dir("terrain_eval_off");
  const Plan p = one_leg(dir, "off");
  const auto ev = evaluation::evaluate_plan(p);
  const double home = p.mission.terrain->grid->at(p.mission.uavs[0].start_resolved);
  const double flight = home + 40.0;  // flat, 40 m above the take-off's ground
  for (const double x : {-120.0, -60.0, -30.0, 0.0, 30.0, 60.0, 120.0}) {
    const double expected = kFootprint * (flight - kLowHill(x, 0)) / 40.0;
    EXPECT_NEAR(band_width(ev.coverage, p, x), expected, 2.5 * ev.coverage.lattice_m) << "x = " << x;
  }
  EXPECT_LT(band_width(ev.coverage, p, 0), 0.6 * band_width(ev.coverage, p, -120));
  ASSERT_TRUE(ev.terrain.has_value());
  EXPECT_NEAR(ev.terrain->height_min_m, flight - kLowHill(0, 0), 0.5);
  EXPECT_NEAR(ev.terrain->footprint_max_m, kFootprint * (flight - kLowHill(-140, 0)) / 40.0, 0.5);
  EXPECT_LT(ev.terrain->footprint_min_m, 0.6 * ev.terrain->footprint_max_m);
  // the summary carries them
  EXPECT_TRUE(evaluation::to_json(ev).contains("terrain_footprints"));
}

TEST(TerrainEvaluation, FollowingTheTerrainKeepsTheCamerasFootprint) {
  TempDir dir("terrain_eval_follow");
  const Plan p = one_leg(dir, "follow");  // tolerance 1 m: heights 39..41 m above ground
  const auto ev = evaluation::evaluate_plan(p);
  ASSERT_TRUE(ev.terrain.has_value());
  EXPECT_GE(ev.terrain->height_min_m, 39.0 - 1e-6);
  EXPECT_LE(ev.terrain->height_max_m, 41.0 + 1e-6);
  EXPECT_GE(ev.terrain->footprint_min_m, kFootprint * 39.0 / 40.0 - 1e-6);
  EXPECT_LE(ev.terrain->footprint_max_m, kFootprint * 41.0 / 40.0 + 1e-6);
  for (const double x : {-120.0, 0.0, 120.0})
    EXPECT_NEAR(band_width(ev.coverage, p, x), kFootprint, 2.5 * ev.coverage.lattice_m) << "x = " << x;
}

}  // namespace
}  // namespace uavcover
