// The pictures are produced, non-empty and of the requested size.
#include <gtest/gtest.h>

#include <numbers>

#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "evaluation/evaluate.hpp"
#include "geodesy/local_frame.hpp"
#include "io/plan_io.hpp"
#include "render/render.hpp"
#include "support/files.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"

using namespace uavcover;
namespace fs = std::filesystem;

namespace {

/// UAVCOVER_RENDER_KEEP=DIR keeps the pictures there for a look.
fs::path out_dir() {
  if (const char* keep = std::getenv("UAVCOVER_RENDER_KEEP")) return keep;
  const fs::path d = fs::temp_directory_path() / ("uavcover_render_test_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

std::pair<std::uint32_t, std::uint32_t> png_size(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  unsigned char h[24] = {};
  in.read(reinterpret_cast<char*>(h), 24);
  EXPECT_EQ(in.gcount(), 24);
  const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  EXPECT_EQ(std::memcmp(h, sig, 8), 0) << p;
  EXPECT_EQ(std::memcmp(h + 12, "IHDR", 4), 0) << p;
  auto be = [&](int o) {
    return (std::uint32_t{h[o]} << 24) | (std::uint32_t{h[o + 1]} << 16) | (std::uint32_t{h[o + 2]} << 8) |
           h[o + 3];
  };
  return {be(16), be(20)};
}

/// A hand-made two-UAV plan over a 400 m x 200 m rectangle with a no-fly zone.
Plan sample_plan() {
  Plan p;
  p.origin = {24.41, 40.93};
  const geodesy::LocalFrame f(p.origin);
  auto ring = [&](std::vector<Point> pts) {
    GeoRing r;
    for (auto q : pts) r.push_back(f.to_wgs84(q));
    r.push_back(r.front());
    return r;
  };
  p.mission.name = "render test";
  p.mission.spacing_m = 20;
  p.mission.area = {{ring({{-200, -100}, {200, -100}, {200, 100}, {-200, 100}})}};
  p.mission.no_fly_zones = {{ring({{20, -20}, {60, -20}, {60, 20}, {20, 20}})}};
  p.free_area_m2 = 80000 - 1600;
  for (int i = 0; i < 2; ++i) {
    Uav u;
    u.id = "uav-" + std::to_string(i + 1);
    u.share = 0.5;
    u.start_resolved = f.to_wgs84(Point{i == 0 ? -220.0 : 220.0, -120.0});
    p.mission.uavs.push_back(u);
    UavPlan up;
    up.id = u.id;
    up.share_actual = 0.5;
    const double x0 = i == 0 ? -190 : 10, x1 = i == 0 ? -10 : 190;
    std::vector<Point> loop;
    for (int k = 0; k < 5; ++k) {
      const double y = -80 + 40 * k;
      if (k % 2 == 0)
        loop.insert(loop.end(), {Point{x0, y}, Point{x1, y}});
      else
        loop.insert(loop.end(), {Point{x1, y}, Point{x0, y}});
    }
    loop.push_back(loop.front());
    const Point s = f.to_local(u.start_resolved);
    up.parts.push_back({PartKind::Transit, {s, loop.front()}, {}});
    up.parts.push_back({PartKind::Coverage, loop, {}});
    up.parts.push_back({PartKind::Transit, {loop.back(), s}, {}});
    p.uavs.push_back(up);
  }
  bg::read_wkt("MULTIPOLYGON(((-200 -100,-200 100,0 100,0 -100,-200 -100)))", p.uavs[0].region_local);
  bg::read_wkt("MULTIPOLYGON(((0 -100,0 100,200 100,200 -100,0 -100)))", p.uavs[1].region_local);
  for (auto& u : p.uavs) bg::correct(u.region_local);
  return p;
}

/// Writes the artifact into dir (through io, as the CLI does) and returns its path.
fs::path save(const fs::path& dir, const Artifact& a) {
  io::write_artifacts(dir, {a});
  return dir / a.name;
}

}  // namespace

TEST(Render, PlanPngAndSvgHaveTheRequestedSize) {
  const auto dir = out_dir();
  const Plan p = sample_plan();
  save(dir, render::plan_png(p, "plan.png", 1000, 700));
  EXPECT_EQ(png_size(dir / "plan.png"), std::make_pair(1000u, 700u));
  EXPECT_GT(fs::file_size(dir / "plan.png"), 5000u);
  save(dir, render::plan_svg(p, "plan.svg", 800, 600));
  std::ifstream in(dir / "plan.svg");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string svg = ss.str();
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("width=\"800"), std::string::npos);
  EXPECT_NE(svg.find("height=\"600"), std::string::npos);
  EXPECT_GT(svg.size(), 5000u);
  if (!std::getenv("UAVCOVER_RENDER_KEEP")) fs::remove_all(dir);
}

TEST(Render, HeatmapHistogramAndStudyPictures) {
  const auto dir = out_dir();
  const Plan p = sample_plan();
  const auto ev = evaluation::evaluate_plan(p);
  EXPECT_GT(ev.coverage.total.poc, 0.8);
  save(dir, render::heatmap_png(ev.coverage, nullptr, "heatmap.png", 900, 640));
  EXPECT_EQ(png_size(dir / "heatmap.png"), std::make_pair(900u, 640u));
  save(dir, render::histogram_png(ev.coverage.total, "histogram.png", 640, 480));
  EXPECT_EQ(png_size(dir / "histogram.png"), std::make_pair(640u, 480u));
  std::vector<render::StudyPoint> pts{{1, 30, 38, 0.5}, {2, 16, 27, 0.55}, {3, 11, 25, 0.57}};
  save(dir, render::study_png(pts, "study.png", 1100, 700, 3));
  EXPECT_EQ(png_size(dir / "study.png"), std::make_pair(1100u, 700u));
  for (const char* f : {"heatmap.png", "histogram.png", "study.png"})
    EXPECT_GT(fs::file_size(dir / f), 3000u) << f;
  if (!std::getenv("UAVCOVER_RENDER_KEEP")) fs::remove_all(dir);
}

TEST(Render, RefusesBadSizes) {
  const Plan p = sample_plan();
  EXPECT_THROW((void)render::plan_png(p, "x.png", 10, 10), InputError);
  EXPECT_THROW((void)render::plan_svg(p, "x.svg", 400, 30000), InputError);
}

TEST(Render, PicturesStayProportionateForHugePolygons) {
  // an area of 100 000 vertices (a circle of 2 km): the SVG follows the pixels, not the vertices
  Plan p = sample_plan();
  const geodesy::LocalFrame f(p.origin);
  GeoRing ring;
  for (int k = 0; k <= 100000; ++k) {
    const double t = 2 * std::numbers::pi * k / 100000.0;
    ring.push_back(f.to_wgs84({2000 * std::cos(t), 2000 * std::sin(t)}));
  }
  ring.back() = ring.front();
  p.mission.area = {{ring}};
  for (auto& u : p.uavs) {
    MultiPolygon circle;
    Polygon poly;
    for (const auto& ll : ring) bg::append(poly.outer(), f.to_local(ll));
    bg::correct(poly);
    circle.push_back(poly);
    u.region_local = circle;  // every region as detailed as the area
  }
  const Artifact svg = render::plan_svg(p);
  RecordProperty("svg_bytes", std::to_string(svg.bytes.size()));
  EXPECT_LT(svg.bytes.size(), 3u * 1024 * 1024);
  EXPECT_LT(render::plan_png(p).bytes.size(), 3u * 1024 * 1024);
}

TEST(Render, PlannedMissionWithThreeUavsAndNoFlyZones) {
  const Mission m =
      uavcover::testing::with_equal_uavs(parse_mission(uavcover::testing::roi_text("roi09.json")), 3);
  const Plan p = plan(m);
  ASSERT_EQ(p.uavs.size(), 3u);
  const auto dir = out_dir();
  save(dir, render::plan_png(p, "plan3.png", 1400, 1000));
  EXPECT_EQ(png_size(dir / "plan3.png"), std::make_pair(1400u, 1000u));
  const auto ev = evaluation::evaluate_plan(p);
  const MultiPolygon free = evaluation::free_area(p.mission, geodesy::LocalFrame(p.origin));
  save(dir, render::heatmap_png(ev.coverage, &free, "heatmap3.png", 1200, 900));
  EXPECT_EQ(png_size(dir / "heatmap3.png"), std::make_pair(1200u, 900u));
  if (!std::getenv("UAVCOVER_RENDER_KEEP")) fs::remove_all(dir);
}
