// Shares the division can meet (issue 26, section 2): starts the engine chooses, DARP's warning for a
// grid too coarse for the shares, and free areas in several parts (every UAV's share over the parts).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <numeric>

#include "codec/plan_codec.hpp"
#include "engine/local_mission.hpp"
#include "engine/shares.hpp"
#include "geometry/geometry.hpp"
#include "io/plan_io.hpp"
#include "planners/darp/darp_planner.hpp"
#include "planners/planner.hpp"
#include "support/shapes.hpp"
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

json uavs(int n) {
  json u = json::array();
  for (int i = 0; i < n; ++i) u.push_back({{"id", "u" + std::to_string(i + 1)}});
  return u;
}

/// 4 km x 150 m, 6 UAVs without starts, spacing 70 m: DARP's strict grid is one row of 28 cells.
json strip() {
  return {{"area", geo_rect(0, 0, 4000, 150)}, {"spacing_m", 70}, {"uavs", uavs(6)}, {"seed", 7}};
}

/// Five islands of different sizes in a row, 6 UAVs without starts.
json islands() {
  json area = {{"type", "MultiPolygon"}, {"coordinates", json::array()}};
  const double w[] = {400, 300, 500, 200, 600}, h[] = {400, 300, 300, 200, 400};
  double x = 0;
  for (int k = 0; k < 5; ++k) {
    area["coordinates"].push_back(geo_rect(x, 0, x + w[k], h[k])["coordinates"]);
    x += w[k] + 150;
  }
  return {{"area", area}, {"spacing_m", 20}, {"uavs", uavs(6)}, {"seed", 11}};
}

/// 1 km x 600 m, a no-fly band across it at x 300-360 m, 4 UAVs all starting west of the band.
json banded() {
  json u = uavs(4);
  for (int i = 0; i < 4; ++i) {
    const LonLat s = zone_lattice_point(-20, 100 + 130 * i);
    u[i]["start"] = {s.lon, s.lat};
  }
  return {{"area", geo_rect(0, 0, 1000, 600)},
          {"no_fly_zones", {geo_rect(300, -20, 360, 620)}},
          {"spacing_m", 20},
          {"uavs", u},
          {"seed", 3}};
}

Mission with_planner(json j, const std::string& planner) {
  j["planner"] = planner;
  return parse_mission(j.dump());
}

/// Every UAV's share of the area: its region's area over all regions'.
std::vector<double> region_shares(const Plan& p) {
  double total = 0;
  for (const auto& u : p.uavs) total += bg::area(u.region_local);
  std::vector<double> out;
  for (const auto& u : p.uavs) out.push_back(total > 0 ? bg::area(u.region_local) / total : 0.0);
  return out;
}

double worst_deviation(const Plan& p) {
  const auto s = region_shares(p);
  double worst = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    worst = std::max(worst, std::fabs(s[i] - p.uavs[i].share_requested));
  return worst;
}

/// Regions exclusive, coverage inside the free area (strict mode), nothing in a no-fly zone.
void check_geometry(const Mission& m, const Plan& p) {
  const auto lm = engine::to_local(m);
  for (std::size_t i = 0; i < p.uavs.size(); ++i)
    for (std::size_t j = i + 1; j < p.uavs.size(); ++j) {
      MultiPolygon both;
      bg::intersection(p.uavs[i].region_local, p.uavs[j].region_local, both);
      EXPECT_LT(bg::area(both), 1.0) << p.uavs[i].id << " and " << p.uavs[j].id << " overlap";
    }
  for (const auto& u : p.uavs)
    for (const auto& part : u.parts)
      for (std::size_t k = 1; k < part.local.size(); ++k) {
        const Point a = part.local[k - 1], b = part.local[k];
        EXPECT_FALSE(geometry::segment_enters(lm.no_fly, a, b, 0.05)) << u.id << " enters a no-fly zone";
        if (part.kind == PartKind::Coverage) {
          EXPECT_TRUE(geometry::segment_within(lm.free, a, b, 0.05)) << u.id << " leaves the area";
        }
      }
}

std::vector<std::string> share_planners() {
  std::vector<std::string> out;
  for (const auto& p : planners::registry())
    if (p.supports.shares) out.push_back(p.name);
  return out;
}

}  // namespace

TEST(SpreadStarts, OnePerShareInsideTheFreeAreaInShareOrderAndSeeded) {
  const MultiPolygon free{uavcover::testing::rect(0, 0, 4000, 150)};
  std::mt19937_64 a(1), b(1), c(2);
  const std::vector<double> shares{0.1, 0.4, 0.2, 0.3};
  const auto s = engine::spread_starts(free, shares, a);
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s.size(), engine::spread_starts(free, shares, b).size());
  // within the middle half of each UAV's slab of the strip: 0-400, 400-2000, 2000-2800, 2800-4000
  const double lo[] = {100, 800, 2200, 3100}, hi[] = {300, 1600, 2600, 3700};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_TRUE(bg::within(s[i], free));
    EXPECT_GE(s[i].x(), lo[i] - 1) << i;
    EXPECT_LE(s[i].x(), hi[i] + 1) << i;
  }
  std::mt19937_64 a2(1);
  EXPECT_TRUE(bg::equals(engine::spread_starts(free, shares, a2)[1], s[1]));
  EXPECT_FALSE(bg::equals(engine::spread_starts(free, shares, c)[1], s[1]));
}

TEST(SpreadStarts, PrincipalAxisOfATiltedStrip) {
  Polygon p;
  for (Point q : {Point{0, 0}, Point{1000, 1000}, Point{1010, 990}, Point{10, -10}, Point{0, 0}})
    bg::append(p.outer(), q);
  bg::correct(p);
  EXPECT_NEAR(engine::principal_axis(MultiPolygon{p}), M_PI / 4, 1e-6);
}

/// DARP's cells per UAV on the strip, and the best division of that many cells among 6 equal shares.
struct StripCells {
  std::vector<int> cells, best;
  int free = 0;
  double best_deviation = 0;  // cells
};

StripCells strip_cells(const Plan& p) {
  StripCells out;
  for (const auto& u : p.uavs) out.cells.push_back(u.diagnostics.at("cells").get<int>());
  out.free = std::accumulate(out.cells.begin(), out.cells.end(), 0);
  const int U = static_cast<int>(out.cells.size()), lo = out.free / U, more = out.free % U;
  for (int i = 0; i < U; ++i) out.best.push_back(i < U - more ? lo : lo + 1);
  const double t = static_cast<double>(out.free) / U;
  out.best_deviation = more == 0 ? 0.0 : std::max(t - lo, lo + 1 - t);
  std::sort(out.cells.begin(), out.cells.end());
  return out;
}

TEST(StripShares, DarpReachesTheBestDivisionOfItsGrid) {
  const Plan p = plan(with_planner(strip(), "darp"));
  const StripCells c = strip_cells(p);
  // one row of 4 km / 140 m mega-cells (the placement decides 28 or 29)
  EXPECT_GE(c.free, 27);
  EXPECT_LE(c.free, 29);
  EXPECT_EQ(c.cells, c.best) << "the best division of " << c.free << " cells";
}

TEST(StripShares, EverySharePlannerMeetsTheSharesWithDrawnStarts) {
  for (const auto& name : share_planners()) {
    const Mission m = with_planner(strip(), name);
    const Plan p = plan(m);
    if (name == "darp") {
      // a cell is 1/28 of the area: the shares within the best division of the grid (its own measure),
      // the region areas (clipped mega-cells) within one cell
      const StripCells c = strip_cells(p);
      for (const auto& u : p.uavs)
        EXPECT_LE(std::fabs(u.share_actual - u.share_requested), c.best_deviation / c.free + 1e-9) << u.id;
      EXPECT_LE(worst_deviation(p), 1.0 / c.free) << name;
    } else {
      // smt's lattice on a 150 m strip is coarse too (measured 2.2 points); milp cuts its 3 lines of 4 km
      // by line length, and its edge lines' strips are wider than the middle one's (measured 3.4 points;
      // before, 3 UAVs got no line: 20 points); the others divide continuously
      const double tolerance = name == "smt" ? 0.03 : name == "milp" ? 0.04 : 0.01;
      EXPECT_LE(worst_deviation(p), tolerance) << name;
      for (const auto& u : p.uavs)
        EXPECT_GT(bg::area(u.region_local), 0.0) << name << " " << u.id << " has a region";
    }
    check_geometry(m, p);
  }
}

/// The strip as a user writes it: the spacing from a camera block (ds = (2 - 0.75) 56 m tan 45 deg
/// = 70 m), a count of UAVs and no starts.
json camera_strip(int seed) {
  json j = strip();
  j.erase("spacing_m");
  j["camera"] = {{"altitude_m", 56}, {"hfov_deg", 90}, {"overlap", 0.75}};
  j["uavs"] = 6;
  j["seed"] = seed;
  return j;
}

TEST(StripShares, DarpBestDivisionForEverySeed) {
  // uniform starts missed by 7.9 to 28.3 points on seeds 1-9 (e.g. seed 4: cells 3,13,3,3,5,2); the spread
  // starts give the best division of the grid on every seed
  for (int seed = 1; seed <= 9; ++seed) {
    const Plan p = plan(with_planner(camera_strip(seed), "darp"));
    ASSERT_NEAR(p.mission.spacing_m, 70.0, 1e-9);
    const StripCells c = strip_cells(p);
    EXPECT_GE(c.free, 27) << "seed " << seed;
    EXPECT_LE(c.free, 29) << "seed " << seed;
    EXPECT_EQ(c.cells, c.best) << "seed " << seed << ": the best division of " << c.free << " cells";
    for (const auto& u : p.uavs)
      EXPECT_LE(std::fabs(u.share_actual - u.share_requested) * c.free, 1.0 + 1e-9)
          << "seed " << seed << " " << u.id << ": within one cell of the share";
  }
}

TEST(DrawnStarts, DeterministicFromTheSeedInsideTheFreeAreaOnePerSlab) {
  const Mission m = parse_mission(camera_strip(5).dump());
  const auto lm = engine::to_local(m);
  auto starts = [&](std::optional<std::uint64_t> seed) {
    PlanOptions o;
    o.seed = seed;
    std::vector<Point> out;
    for (const auto& u : plan(m, o).mission.uavs) out.push_back(lm.frame.to_local(u.start_resolved));
    return out;
  };
  const auto a = starts(std::nullopt), b = starts(std::nullopt), c = starts(6);
  ASSERT_EQ(a.size(), 6u);
  bool moved = false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_DOUBLE_EQ(a[i].x(), b[i].x()) << i;
    EXPECT_DOUBLE_EQ(a[i].y(), b[i].y()) << i;
    EXPECT_LT(bg::distance(a[i], lm.free), 1e-6) << i << " lies in the free area";
    EXPECT_LT(bg::distance(c[i], lm.free), 1e-6) << i << " lies in the free area";
    moved |= !bg::equals(a[i], c[i]);
  }
  EXPECT_TRUE(moved) << "another seed draws other starts";
  // spread along the strip: one start in each sixth (equal shares), in UAV order along the axis
  bg::model::box<Point> env;
  bg::envelope(lm.free, env);
  const double x0 = env.min_corner().x(), w = env.max_corner().x() - x0;
  for (const auto& s : {a, c})
    for (std::size_t i = 0; i < s.size(); ++i) {
      const double along = (s[i].x() - x0) / w * 6;
      const bool forward = s.back().x() > s.front().x();
      const double slab = forward ? static_cast<double>(i) : static_cast<double>(5 - i);
      EXPECT_GE(along, slab - 1e-6) << i;
      EXPECT_LE(along, slab + 1 + 1e-6) << i;
    }
}

TEST(DrawnStarts, GivenStartsAreKeptAndOnlyMissingOnesAreDrawn) {
  json j = camera_strip(3);
  j["uavs"] = uavs(6);
  const LonLat given = zone_lattice_point(-50, 75);
  j["uavs"][2]["start"] = {given.lon, given.lat};
  const Plan p = plan(with_planner(j, "darp"));
  EXPECT_EQ(p.mission.uavs[2].start_resolved.lon, given.lon);
  EXPECT_EQ(p.mission.uavs[2].start_resolved.lat, given.lat);
  const auto lm = engine::to_local(p.mission);
  for (std::size_t i = 0; i < 6; ++i)
    if (i != 2) {
      EXPECT_LT(bg::distance(lm.frame.to_local(p.mission.uavs[i].start_resolved), lm.free), 1e-6) << i;
    }
}

TEST(CoarseGrid, TheWarningGivesTheNumbersAndWhatToChange) {
  const Plan p = plan(with_planner(strip(), "darp"));
  const StripCells c = strip_cells(p);
  const auto w = std::find_if(p.warnings.begin(), p.warnings.end(),
                              [](const std::string& s) { return s.find("too coarse") != std::string::npos; });
  ASSERT_NE(w, p.warnings.end());
  for (const std::string& part :
       {fmt::format("{} free cells for 6 UAVs", c.free), fmt::format("{:.1f} per UAV", c.free / 6.0),
        std::string("smallest share, 0.167"), fmt::format("off by up to {:.2f} cells", c.best_deviation),
        fmt::format("{:.1f} points of the area", 100 * c.best_deviation / c.free),
        std::string("finer spacing"), std::string("boustrophedon"), std::string("spiral")})
    EXPECT_NE(w->find(part), std::string::npos) << part << " in: " << *w;
  // 25 cells for a sixth: 150 cells: at least sqrt(150 / cells) finer than 70 m
  const auto at = w->find("about ");
  ASSERT_NE(at, std::string::npos);
  const double finer = std::stod(w->substr(at + 6));
  EXPECT_LE(finer, 70 / std::sqrt(150.0 / c.free));
  EXPECT_GT(finer, 10);
}

TEST(CoarseGrid, NoWarningWhenWholeCellsMeetTheShares) {
  EXPECT_FALSE(darp::coarse_grid_warning({50, 50}, 25, 1e6));
  EXPECT_FALSE(darp::coarse_grid_warning({3.5}, 25, 1e6)) << "one UAV";
  EXPECT_TRUE(darp::coarse_grid_warning({10.5, 10.5}, 25, 1e6));
}

TEST(PartsShares, IslandsEveryPlannerWithinTwoPoints) {
  for (const auto& name : share_planners()) {
    const Mission m = with_planner(islands(), name);
    const Plan p = plan(m);
    EXPECT_LE(worst_deviation(p), 0.02) << name;
    check_geometry(m, p);
  }
}

TEST(PartsShares, BandedFieldEveryPlannerWithinTwoPointsAndTransitAroundTheBand) {
  for (const auto& name : share_planners()) {
    const Mission m = with_planner(banded(), name);
    const Plan p = plan(m);
    EXPECT_LE(worst_deviation(p), 0.02) << name;
    check_geometry(m, p);
    // some UAV starting west covers east of the band
    bool crosses = false;
    for (const auto& u : p.uavs)
      for (const auto& part : u.parts)
        if (part.kind == PartKind::Coverage)
          for (const auto& q : part.local) crosses |= q.x() > 360;
    EXPECT_TRUE(crosses) << name;
  }
}

TEST(PartsShares, SameSeedSamePlan) {
  for (json j : {islands(), banded()}) {
    const Mission m = with_planner(j, "darp");
    EXPECT_EQ(codec::paths_geojson(plan(m)).dump(), codec::paths_geojson(plan(m)).dump());
  }
}

TEST(PartsShares, AllocationPrefersFewPartsAndMeetsTheShares) {
  using uavcover::testing::rect;
  // parts of 100, 300 and 600 area units (10 x 10, 10 x 30, 10 x 60), 4 equal shares of 250
  const MultiPolygon free{rect(0, 0, 10, 10), rect(20, 0, 30, 30), rect(40, 0, 50, 60)};
  const std::vector<Point> starts{{5, 5}, {25, 5}, {45, 5}, {45, 50}};
  const auto alloc = engine::allocate_parts(free, starts, {0.25, 0.25, 0.25, 0.25});
  std::size_t pieces = 0;
  for (const auto& a : alloc) {
    double sum = 0;
    for (const auto& p : a) sum += p.area_m2;
    EXPECT_NEAR(sum, 250, 1e-6);
    pieces += a.size();
  }
  EXPECT_LE(pieces, 4u + 3u - 1u);  // at most one split per cut
  // the UAV starting on the first part takes it
  ASSERT_FALSE(alloc[0].empty());
  EXPECT_EQ(alloc[0][0].part, 0u);
}
