// The boustrophedon planner on hand-checkable shapes, called directly through the registry.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>
#include <stop_token>
#include <thread>

#include "engine/local_mission.hpp"
#include "geometry/geometry.hpp"
#include "planners/boustrophedon/decomposition.hpp"
#include "planners/planner.hpp"
#include "support/files.hpp"
#include "support/shapes.hpp"
#include "uavcover/error.hpp"

using namespace uavcover;
using namespace uavcover::planners;
using uavcover::testing::rect;

namespace {

constexpr double kPi = 3.14159265358979323846;

MultiPolygon mp(std::initializer_list<Polygon> polys) {
  MultiPolygon m;
  for (const auto& p : polys) m.push_back(p);
  return m;
}

Problem problem(const MultiPolygon& area, const MultiPolygon& nfz, std::vector<Point> starts,
                std::vector<double> shares, Mode mode = Mode::Strict, double spacing = 40.0) {
  Problem p;
  p.area = geometry::unite(area);
  p.no_fly = geometry::unite(nfz);
  p.free = geometry::free_space(p.area, p.no_fly);
  p.starts = std::move(starts);
  p.shares = std::move(shares);
  p.uavs.resize(p.starts.size());
  p.spacing_m = spacing;
  p.footprint_m = 1.5 * spacing;
  p.mode = mode;
  return p;
}

Problem one_uav(const MultiPolygon& area, const MultiPolygon& nfz = {}, Mode mode = Mode::Strict) {
  return problem(area, nfz, {Point{-50, -50}}, {1.0}, mode);
}

const PlannerInfo& info() {
  const PlannerInfo* i = find("boustrophedon");
  if (!i) throw std::runtime_error("boustrophedon planner not registered");
  return *i;
}

Assignment run(const Problem& p, const nlohmann::json& params = nullptr, const Context& ctx = Context{}) {
  return info().create()->plan(p, validate_params(info(), params), ctx);
}

using Seg = std::pair<Point, Point>;

std::vector<Seg> segments(const UavAssignment& u) {
  std::vector<Seg> out;
  for (const auto& part : u.coverage)
    for (std::size_t i = 1; i < part.size(); ++i) out.emplace_back(part[i - 1], part[i]);
  return out;
}

/// The legs of a lawnmower without extra boundary vertices: segments 0-1, 2-3, ...
std::vector<Seg> legs(const std::vector<Point>& part) {
  std::vector<Seg> out;
  for (std::size_t i = 0; i + 1 < part.size(); i += 2) out.emplace_back(part[i], part[i + 1]);
  return out;
}

double bearing(const Seg& s) {
  double b = std::atan2(s.second.x() - s.first.x(), s.second.y() - s.first.y()) * 180.0 / kPi;
  b = std::fmod(b + 360.0, 180.0);
  return b > 179.999 ? 0.0 : b;
}

Problem roi(const std::string& file, Mode mode) {
  const Mission m = parse_mission(uavcover::testing::roi_text(file));
  const auto lm = engine::to_local(m);
  Problem p;
  p.area = lm.area;
  p.no_fly = lm.no_fly;
  p.free = lm.free;
  Point c;
  bg::centroid(lm.free, c);
  p.starts = {c};
  p.shares = {1.0};
  p.uavs = m.uavs;
  p.spacing_m = m.spacing_m;
  p.footprint_m = 1.5 * m.spacing_m;
  p.mode = mode;
  return p;
}

void expect_strict_inside(const Problem& p, const Assignment& a) {
  for (const auto& u : a.uavs)
    for (const auto& [s, e] : segments(u))
      EXPECT_TRUE(geometry::segment_within(p.free, s, e, 1e-6))
          << bg::wkt(s) << " " << bg::wkt(e) << " leaves the free area";
}

void expect_no_fly_avoided(const Problem& p, const Assignment& a) {
  for (const auto& u : a.uavs)
    for (const auto& [s, e] : segments(u))
      EXPECT_FALSE(geometry::segment_enters(p.no_fly, s, e, 1e-6)) << bg::wkt(s) << " " << bg::wkt(e);
}

void expect_no_crossings(const Assignment& a) {
  for (std::size_t i = 0; i < a.uavs.size(); ++i)
    for (std::size_t j = i + 1; j < a.uavs.size(); ++j) {
      const auto si = segments(a.uavs[i]);
      const auto sj = segments(a.uavs[j]);
      for (const auto& x : si)
        for (const auto& y : sj)
          ASSERT_FALSE(bg::intersects(bg::model::segment<Point>{x.first, x.second},
                                      bg::model::segment<Point>{y.first, y.second}))
              << "uav " << i << " " << bg::wkt(x.first) << "-" << bg::wkt(x.second) << " crosses uav " << j
              << " " << bg::wkt(y.first) << "-" << bg::wkt(y.second);
    }
}

}  // namespace

TEST(Boustrophedon, Registered) {
  const auto& i = info();
  EXPECT_EQ(i.name, "boustrophedon");
  EXPECT_TRUE(i.supports.shares);
  EXPECT_TRUE(i.supports.no_fly_zones);
  EXPECT_TRUE(i.supports.strict_mode);
  EXPECT_TRUE(i.supports.coverage_mode);
  EXPECT_TRUE(i.supports.multiple_areas);
  const auto d = describe(i);
  EXPECT_EQ(d["params"][0]["name"], "angle_deg");
  EXPECT_TRUE(d["params"][0]["default"].is_null());
}

TEST(Boustrophedon, RectangleHasCeilWidthOverSpacingLegsAlongItsLength) {
  for (const double width : {400.0, 390.0, 410.0}) {
    SCOPED_TRACE(width);
    const int n = static_cast<int>(std::ceil(width / 40.0));
    // tall: legs run north-south
    const auto a = run(one_uav(mp({rect(0, 0, width, 1000)})));
    ASSERT_EQ(a.uavs.size(), 1u);
    ASSERT_EQ(a.uavs[0].coverage.size(), 1u);
    const auto& part = a.uavs[0].coverage[0];
    ASSERT_EQ(part.size(), static_cast<std::size_t>(2 * n));
    std::vector<double> xs;
    for (const auto& [s, e] : legs(part)) {
      EXPECT_NEAR(s.x(), e.x(), 1e-9);
      EXPECT_NEAR(std::abs(e.y() - s.y()), 1000.0, 1e-6);
      xs.push_back(s.x());
    }
    std::sort(xs.begin(), xs.end());
    EXPECT_NEAR(xs.front(), 20.0, 1e-6);  // half a spacing in from the edge
    EXPECT_NEAR(xs.back(), width - 20.0, 1e-6);
    for (std::size_t i = 1; i < xs.size(); ++i) EXPECT_LE(xs[i] - xs[i - 1], 40.0 + 1e-9);
    // wide: legs run east-west
    const auto b = run(one_uav(mp({rect(0, 0, 1000, width)})));
    ASSERT_EQ(b.uavs[0].coverage.size(), 1u);
    ASSERT_EQ(b.uavs[0].coverage[0].size(), static_cast<std::size_t>(2 * n));
    for (const auto& [s, e] : legs(b.uavs[0].coverage[0])) EXPECT_NEAR(s.y(), e.y(), 1e-9);
  }
}

TEST(Boustrophedon, LShapeGivesTwoCells) {
  const auto p = one_uav(mp({rect(0, 0, 1000, 200), rect(0, 0, 200, 1000)}));
  const auto a = run(p);
  ASSERT_EQ(a.uavs[0].coverage.size(), 2u);
  EXPECT_EQ(a.uavs[0].diagnostics["legs"], 10);  // 5 legs along each arm
  expect_strict_inside(p, a);
}

TEST(Boustrophedon, ClipAtAStepAlongTheLegsKeepsBothSides) {
  // an L lying on its side in the frame: the lower chain steps down along X = 100 (an edge parallel to
  // the legs, at the reflex vertex where the cell may be cut); the two sides of that cut are the whole
  boustro::Monotone cell;
  cell.lower = {Point{0, 0}, Point{100, 0}, Point{100, -200}, Point{300, -200}};
  cell.upper = {Point{0, 100}, Point{300, 100}};
  const double whole = boustro::area(cell);
  ASSERT_NEAR(whole, 100.0 * 100.0 + 200.0 * 300.0, 1e-6);
  const double left = boustro::area(boustro::clip(cell, 0, 100));
  const double right = boustro::area(boustro::clip(cell, 100, 300));
  EXPECT_NEAR(left, 100.0 * 100.0, 1e-6);
  EXPECT_NEAR(right, 300.0 * 200.0, 1e-6) << "the right side starts at the step's low end";
  EXPECT_NEAR(left + right, whole, 1e-6);
}

TEST(Boustrophedon, EveryPointOfAStarIsSwept) {
  // a five-pointed star (radii 300 / 120 m), 3 UAVs, 35 m: the cells of each UAV's sweeps are its
  // whole region (two points were left out when a cut fell on an edge parallel to the legs)
  Polygon star;
  for (int k = 0; k < 10; ++k) {
    const double r = k % 2 == 0 ? 300.0 : 120.0, t = kPi / 2 + k * kPi / 5;
    bg::append(star.outer(), Point{r * std::cos(t), r * std::sin(t)});
  }
  bg::append(star.outer(), star.outer().front());
  bg::correct(star);
  auto p = problem(mp({star}), {}, {Point{-320, -260}, Point{0, -320}, Point{320, -260}},
                   {1.0 / 3, 1.0 / 3, 1.0 / 3}, Mode::Strict, 35.0);
  const auto a = run(p);
  for (std::size_t k = 0; k < a.uavs.size(); ++k) {
    ASSERT_TRUE(a.uavs[k].diagnostics.contains("cells")) << "uav " << k << " has no region";
    double cells = 0.0;
    for (const auto& c : a.uavs[k].diagnostics.at("cells")) cells += c["area_m2"].get<double>();
    EXPECT_NEAR(cells, bg::area(a.uavs[k].region), 0.01 * bg::area(a.uavs[k].region)) << "uav " << k;
  }
  expect_strict_inside(p, a);
}

TEST(Boustrophedon, HoleGivesCellsOnBothSides) {
  const auto p = one_uav(mp({rect(0, 0, 1000, 600)}), mp({rect(400, 200, 600, 400)}));
  const auto a = run(p);
  EXPECT_GE(a.uavs[0].coverage.size(), 3u);
  bool above = false, below = false;
  for (const auto& [s, e] : segments(a.uavs[0])) {
    const Point mid{(s.x() + e.x()) / 2, (s.y() + e.y()) / 2};
    if (mid.x() > 400 && mid.x() < 600 && mid.y() > 400) above = true;
    if (mid.x() > 400 && mid.x() < 600 && mid.y() < 200) below = true;
  }
  EXPECT_TRUE(above);
  EXPECT_TRUE(below);
  expect_no_fly_avoided(p, a);
  expect_strict_inside(p, a);
}

TEST(Boustrophedon, StrictPathsStayInsideTheFreeAreaAndOutOfNoFlyZones) {
  for (const char* f : {"roi10.json", "roi16.json", "roi17.json", "roi18.json"}) {
    SCOPED_TRACE(f);
    const auto p = roi(f, Mode::Strict);
    const auto a = run(p);
    EXPECT_FALSE(a.uavs[0].coverage.empty());
    expect_strict_inside(p, a);
    expect_no_fly_avoided(p, a);
  }
}

TEST(Boustrophedon, CoverageModeExtendsLegsByHalfAFootprint) {
  const auto p = one_uav(mp({rect(0, 0, 400, 1000)}), {}, Mode::Coverage);
  const auto a = run(p);
  ASSERT_EQ(a.uavs[0].coverage.size(), 1u);
  for (const auto& [s, e] : legs(a.uavs[0].coverage[0])) {
    EXPECT_NEAR(std::min(s.y(), e.y()), -30.0, 1e-6);
    EXPECT_NEAR(std::max(s.y(), e.y()), 1030.0, 1e-6);
  }
}

TEST(Boustrophedon, CoverageModeNeverEntersNoFlyZones) {
  // a no-fly zone across the bottom edge and one inside
  const auto p = one_uav(mp({rect(0, 0, 400, 1000)}),
                         mp({rect(110, -100, 290, 100), rect(150, 500, 250, 600)}), Mode::Coverage);
  const auto a = run(p);
  expect_no_fly_avoided(p, a);
  bool extended_beside = false;
  for (const auto& [s, e] : segments(a.uavs[0]))
    if (s.x() < 100 && std::abs(s.x() - e.x()) < 1e-9 && std::min(s.y(), e.y()) < -29.9)
      extended_beside = true;
  EXPECT_TRUE(extended_beside);
  for (const char* f : {"roi11.json", "roi16.json", "roi17.json"}) {
    SCOPED_TRACE(f);
    const auto q = roi(f, Mode::Coverage);
    expect_no_fly_avoided(q, run(q));
  }
}

TEST(Boustrophedon, SharesGiveExclusiveConnectedRegions) {
  const std::vector<double> shares{0.2, 0.3, 0.5};
  const std::vector<std::pair<MultiPolygon, MultiPolygon>> shapes = {
      {mp({rect(0, 0, 1000, 600)}), {}},
      {mp({rect(0, 0, 1000, 600)}), mp({rect(400, 200, 600, 400)})},
      {mp({rect(0, 0, 1000, 200), rect(0, 0, 200, 1000)}), {}},
  };
  for (Mode mode : {Mode::Strict, Mode::Coverage})
    for (std::size_t s = 0; s < shapes.size(); ++s)
      for (std::size_t n : {2u, 3u}) {
        SCOPED_TRACE(::testing::Message()
                     << "shape " << s << " uavs " << n << " mode " << static_cast<int>(mode));
        std::vector<double> sh(shares.end() - static_cast<std::ptrdiff_t>(n), shares.end());
        double sum = 0;
        for (double x : sh) sum += x;
        for (double& x : sh) x /= sum;
        std::vector<Point> starts{{-100, -100}, {1100, 700}, {500, -100}};
        starts.resize(n);
        const auto p = problem(shapes[s].first, shapes[s].second, starts, sh, mode);
        const auto a = run(p);
        ASSERT_EQ(a.uavs.size(), n);
        const double total = bg::area(p.free);
        // the regions share the free area less a 0.5 m clearance band along the no-fly zones
        double band = 0;
        for (const auto& z : p.no_fly) band += 0.5 * bg::perimeter(z) * 1.05;
        double regions_total = 0;
        for (const auto& u : a.uavs) regions_total += bg::area(u.region);
        double sum_area = 0;
        for (std::size_t k = 0; k < n; ++k) {
          const auto& r = a.uavs[k].region;
          EXPECT_EQ(r.size(), 1u) << "region " << k << " is not connected";
          const double ak = bg::area(r);
          sum_area += ak;
          EXPECT_NEAR(ak / total, sh[k], 0.02) << "uav " << k;
          ASSERT_TRUE(a.uavs[k].share_actual);
          EXPECT_NEAR(*a.uavs[k].share_actual, ak / regions_total, 1e-6);
          MultiPolygon outside;
          bg::difference(r, p.free, outside);
          EXPECT_LT(bg::area(outside), 1e-6 * total);
          for (std::size_t j = k + 1; j < n; ++j) {
            MultiPolygon both;
            bg::intersection(r, a.uavs[j].region, both);
            EXPECT_LT(bg::area(both), 1e-6 * total) << "regions " << k << " and " << j << " overlap";
          }
          EXPECT_FALSE(a.uavs[k].coverage.empty());
        }
        EXPECT_LE(sum_area, total * (1 + 1e-6));
        EXPECT_GE(sum_area, total - band - 1e-6 * total);
        if (mode == Mode::Strict) expect_strict_inside(p, a);
        expect_no_fly_avoided(p, a);
        expect_no_crossings(a);
      }
}

TEST(Boustrophedon, PathsOfDifferentUavsDoNotCrossOnARegion) {
  for (Mode mode : {Mode::Strict, Mode::Coverage}) {
    auto p = roi("roi16.json", mode);
    p.starts = {Point{-2000, 0}, Point{2000, 0}, Point{0, 2000}};
    p.shares = {0.25, 0.35, 0.4};
    p.uavs.resize(3);
    const auto a = run(p);
    expect_no_crossings(a);
    expect_no_fly_avoided(p, a);
    if (mode == Mode::Strict) expect_strict_inside(p, a);
    for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(*a.uavs[k].share_actual, p.shares[k], 0.02);
  }
}

TEST(Boustrophedon, SameInputSameOutput) {
  auto p = roi("roi17.json", Mode::Coverage);
  p.starts = {Point{-500, 0}, Point{500, 0}};
  p.shares = {0.4, 0.6};
  p.uavs.resize(2);
  const auto a = run(p), b = run(p);
  ASSERT_EQ(a.uavs.size(), b.uavs.size());
  for (std::size_t k = 0; k < a.uavs.size(); ++k) {
    ASSERT_EQ(a.uavs[k].coverage.size(), b.uavs[k].coverage.size());
    for (std::size_t i = 0; i < a.uavs[k].coverage.size(); ++i) {
      const auto& x = a.uavs[k].coverage[i];
      const auto& y = b.uavs[k].coverage[i];
      ASSERT_EQ(x.size(), y.size());
      for (std::size_t j = 0; j < x.size(); ++j) {
        EXPECT_EQ(x[j].x(), y[j].x());
        EXPECT_EQ(x[j].y(), y[j].y());
      }
    }
    std::ostringstream ra, rb;
    ra << bg::wkt(a.uavs[k].region);
    rb << bg::wkt(b.uavs[k].region);
    EXPECT_EQ(ra.str(), rb.str());
    EXPECT_EQ(a.uavs[k].diagnostics, b.uavs[k].diagnostics);
  }
}

TEST(Boustrophedon, FixedAngleIsHonoured) {
  // east-west legs would need 10; north-south ones (angle 0) need 25
  const auto p = one_uav(mp({rect(0, 0, 1000, 400)}));
  const auto a = run(p, {{"angle_deg", 0}});
  ASSERT_EQ(a.uavs[0].coverage.size(), 1u);
  EXPECT_EQ(a.uavs[0].coverage[0].size(), 50u);
  for (const auto& l : legs(a.uavs[0].coverage[0])) EXPECT_NEAR(bearing(l), 0.0, 1e-6);
  for (const double angle : {30.0, 120.0, -45.0}) {
    SCOPED_TRACE(angle);
    const auto b = run(p, {{"angle_deg", angle}});
    for (const auto& part : b.uavs[0].coverage)
      for (const auto& l : legs(part)) EXPECT_NEAR(bearing(l), std::fmod(angle + 360.0, 180.0), 1e-6);
    expect_strict_inside(p, b);
  }
}

TEST(Boustrophedon, BadParamsAreRefused) {
  auto message = [](const nlohmann::json& params) {
    try {
      (void)validate_params(info(), params);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message({{"angle_deg", "north"}}).rfind("planner_params.angle_deg: ", 0), 0u);
  EXPECT_EQ(message({{"angle_deg", 400}}).rfind("planner_params.angle_deg: must be <= 360", 0), 0u);
  EXPECT_EQ(message({{"angle_deg", true}}).rfind("planner_params.angle_deg: ", 0), 0u);
  EXPECT_EQ(message({{"angle", 10}}).rfind("planner_params.angle: unknown parameter", 0), 0u);
  EXPECT_EQ(message({{"angle_deg", 10}}), "accepted");
  EXPECT_EQ(message(nullptr), "accepted");
}

TEST(Boustrophedon, MultipleAreas) {
  const auto p = one_uav(mp({rect(0, 0, 400, 400), rect(1000, 0, 1400, 400)}));
  const auto a = run(p);
  ASSERT_EQ(a.uavs[0].coverage.size(), 2u);
  expect_strict_inside(p, a);
}

TEST(Boustrophedon, ReportsProgress) {
  double last = -1;
  bool monotone = true;
  const Context ctx([&](std::string_view stage, double f) {
    EXPECT_EQ(stage, "boustrophedon");
    if (f < last) monotone = false;
    last = f;
  });
  (void)run(roi("roi16.json", Mode::Strict), nullptr, ctx);
  EXPECT_TRUE(monotone);
  EXPECT_EQ(last, 1.0);
}

TEST(Boustrophedon, StopRequestedThrowsCancelled) {
  std::stop_source stop;
  stop.request_stop();
  const Context ctx(nullptr, stop.get_token());
  EXPECT_THROW((void)run(one_uav(mp({rect(0, 0, 400, 1000)})), nullptr, ctx), Cancelled);
}

TEST(Boustrophedon, StopLandsQuicklyOnAHugeProblem) {
  // 100 000 north-south legs of 2 km (spacing 1 m over 100 km), three UAVs; the stop is requested
  // from the progress callback once the first UAV is planned, and again from another thread
  const auto p =
      problem(mp({rect(0, 0, 100000, 2000)}), mp({rect(30000, 500, 31000, 1500)}),
              {Point{0, 0}, Point{50000, 0}, Point{100000, 0}}, {0.3, 0.3, 0.4}, Mode::Coverage, 1.0);
  const nlohmann::json params{{"angle_deg", 0}};
  {
    std::stop_source stop;
    std::chrono::steady_clock::time_point requested;
    const Context ctx(
        [&](std::string_view, double f) {
          if (f > 0.5 && !stop.stop_requested()) {
            requested = std::chrono::steady_clock::now();
            stop.request_stop();
          }
        },
        stop.get_token());
    EXPECT_THROW((void)run(p, params, ctx), Cancelled);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - requested).count(), 0.5);
  }
  {
    std::stop_source stop;
    const Context ctx(nullptr, stop.get_token());
    std::chrono::steady_clock::time_point requested;
    std::thread t([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      requested = std::chrono::steady_clock::now();
      stop.request_stop();
    });
    bool cancelled = false;
    try {
      (void)run(p, params, ctx);
    } catch (const Cancelled&) {
      cancelled = true;
    }
    const auto landed = std::chrono::steady_clock::now();
    t.join();
    if (cancelled) {
      EXPECT_LT(std::chrono::duration<double>(landed - requested).count(), 0.5);
    }
  }
}

TEST(Boustrophedon, AllPaperRegionsOneAndThreeUavs) {
  for (int r = 1; r <= 20; ++r) {
    char name[32];
    std::snprintf(name, sizeof name, "roi%02d.json", r);
    for (Mode mode : {Mode::Strict, Mode::Coverage}) {
      SCOPED_TRACE(::testing::Message() << name << " mode " << static_cast<int>(mode));
      auto p = roi(name, mode);
      const auto one = run(p);
      EXPECT_FALSE(one.uavs[0].coverage.empty());
      if (mode == Mode::Strict) expect_strict_inside(p, one);
      expect_no_fly_avoided(p, one);
      bg::model::box<Point> box;
      bg::envelope(p.free, box);
      p.starts = {box.min_corner(), box.max_corner(), Point{box.min_corner().x(), box.max_corner().y()}};
      p.shares = {0.2, 0.3, 0.5};
      p.uavs.resize(3);
      const auto three = run(p);
      const double total = bg::area(p.free);
      for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_NEAR(bg::area(three.uavs[k].region) / total, p.shares[k], 0.02) << "uav " << k;
        if (p.free.size() == 1) {
          EXPECT_EQ(three.uavs[k].region.size(), 1u) << "uav " << k;
        }
        EXPECT_FALSE(three.uavs[k].coverage.empty());
      }
      if (mode == Mode::Strict) expect_strict_inside(p, three);
      expect_no_fly_avoided(p, three);
      expect_no_crossings(three);
    }
  }
}

TEST(Boustrophedon, ThesisRectangleThreeUavsGetStripsAlongItsLength) {
  Mission m = parse_mission(uavcover::testing::slurp(std::filesystem::path(UAVCOVER_BENCH_DATA) /
                                                     "mondinelli2025" / "rectangle_3uav.json"));
  const auto lm = engine::to_local(m);
  Problem p;
  p.area = lm.area;
  p.no_fly = lm.no_fly;
  p.free = lm.free;
  std::mt19937_64 rng(m.seed);
  for (const auto& u : m.uavs) {
    p.starts.push_back(engine::random_free_point(lm.free, rng));
    p.shares.push_back(u.share);
  }
  p.uavs = m.uavs;
  p.spacing_m = m.spacing_m;
  p.footprint_m = 1.5 * m.spacing_m;
  p.mode = m.mode;
  const auto a = run(p);
  ASSERT_EQ(a.uavs.size(), 3u);
  const double total = bg::area(p.free);
  for (const auto& u : a.uavs) {
    EXPECT_NEAR(bg::area(u.region) / total, 1.0 / 3.0, 0.02);
    EXPECT_EQ(u.region.size(), 1u);
    ASSERT_EQ(u.coverage.size(), 1u);
    for (const auto& l : legs(u.coverage[0])) EXPECT_NEAR(bearing(l), 0.0, 0.5);  // north-south, along 200 m
  }
  expect_strict_inside(p, a);
  expect_no_crossings(a);
}

TEST(Boustrophedon, RefusesMoreNoFlyZonesThanItPlansInSeconds) {
  MultiPolygon zones;
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j)
      zones.push_back(rect(100 + 100 * i, 100 + 100 * j, 102 + 100 * i, 102 + 100 * j));
  MultiPolygon area;
  area.push_back(rect(0, 0, 1000, 1000));
  try {
    (void)run(one_uav(area, zones));
    FAIL() << "planned around 81 zones";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "no_fly_zones");
    EXPECT_NE(std::string(e.what()).find("darp"), std::string::npos) << e.what();
  }
}
