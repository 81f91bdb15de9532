// The MILP sweep planner (Hong et al. 2021) on hand-checkable shapes: brute-force optimality of the
// model, every line flown once end to end, contiguous bands on a hexagon, several areas, no-fly
// zones, the time limit and parameter errors.
#ifdef UAVCOVER_HAS_MILP
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <tuple>

#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "planners/milp/lines.hpp"
#include "planners/milp/model.hpp"
#include "planners/planner.hpp"
#include "support/hard_shapes.hpp"
#include "support/shapes.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"

using namespace uavcover;
using namespace uavcover::planners;
using uavcover::testing::rect;

namespace {

Polygon poly(std::initializer_list<Point> pts) {
  Polygon p;
  for (const auto& q : pts) bg::append(p.outer(), q);
  bg::append(p.outer(), *pts.begin());
  bg::correct(p);
  return p;
}

Problem problem(const MultiPolygon& area, const MultiPolygon& nfz, std::vector<Point> starts, double spacing,
                std::vector<double> shares = {}) {
  Problem p;
  p.area = geometry::unite(area);
  p.no_fly = geometry::unite(nfz);
  p.free = geometry::free_space(p.area, p.no_fly);
  p.starts = std::move(starts);
  if (shares.empty()) shares.assign(p.starts.size(), 1.0 / static_cast<double>(p.starts.size()));
  p.shares = std::move(shares);
  p.uavs.resize(p.starts.size());
  p.spacing_m = spacing;
  p.footprint_m = 1.5 * spacing;
  return p;
}

const PlannerInfo& info() {
  const PlannerInfo* i = find("milp");
  if (!i) throw std::runtime_error("milp planner not registered");
  return *i;
}

Assignment run(const Problem& p, const nlohmann::json& params = nullptr, const Context& ctx = Context{}) {
  return info().create()->plan(p, validate_params(info(), params), ctx);
}

milp::Lines lines_of(const Problem& p, const nlohmann::json& params = nullptr) {
  const auto v = validate_params(info(), params);
  std::optional<double> fixed;
  if (v["angle_deg"].is_number())
    fixed = std::numbers::pi / 2 - v["angle_deg"].get<double>() * std::numbers::pi / 180;
  return milp::build_lines(p.free, p.no_fly, p.spacing_m,
                           v["direction"] == "auto" ? milp::Direction::Auto : milp::Direction::LongestEdge,
                           fixed, Context{});
}

/// Per segment the UAV flying it end to end (-1: none; -2: several, each a piece of it, the pieces
/// of a segment cut between UAVs); fails the test when a leg is not on a segment, or the legs on a
/// segment overlap or leave a gap.
std::vector<int> flown_by(const Assignment& a, const milp::Lines& lines) {
  std::vector<int> who(lines.segments.size(), -1);
  std::vector<double> flown(lines.segments.size(), 0.0);
  std::vector<std::vector<std::pair<double, double>>> spans(lines.segments.size());
  for (std::size_t k = 0; k < a.uavs.size(); ++k)
    for (const auto& leg : a.uavs[k].coverage) {
      EXPECT_EQ(leg.size(), 2u) << "a leg is one straight segment";
      if (leg.size() != 2) continue;
      bool found = false;
      for (std::size_t s = 0; s < lines.segments.size() && !found; ++s) {
        const auto& seg = lines.segments[s];
        const bg::model::segment<Point> line{seg.a, seg.b};
        if (bg::distance(leg[0], line) > 1e-6 || bg::distance(leg[1], line) > 1e-6) continue;
        found = true;
        who[s] = who[s] == -1 || who[s] == static_cast<int>(k) ? static_cast<int>(k) : -2;
        flown[s] += boustro::dist(leg[0], leg[1]);
        const double t0 = boustro::dist(seg.a, leg[0]), t1 = boustro::dist(seg.a, leg[1]);
        spans[s].emplace_back(std::min(t0, t1), std::max(t0, t1));
      }
      EXPECT_TRUE(found) << "a leg that is not on a line segment";
    }
  for (std::size_t s = 0; s < lines.segments.size(); ++s) {
    if (who[s] == -1) continue;
    // the pieces of a cut segment: legs end to end but for the gap at each cut
    const double cuts = static_cast<double>(spans[s].size() - 1);
    EXPECT_NEAR(flown[s] + 2.0 * milp::kCutGapM * cuts, lines.segments[s].length(), 1e-6)
        << "segment " << s << ": a gap or an overlap";
    std::sort(spans[s].begin(), spans[s].end());
    for (std::size_t i = 1; i < spans[s].size(); ++i)
      EXPECT_NEAR(spans[s][i].first - spans[s][i - 1].second, 2.0 * milp::kCutGapM, 1e-6)
          << "segment " << s << ": overlap or gap at a cut";
  }
  return who;
}

// ---- the model against brute force ----

/// Every assignment of the pairs to the UAVs, every order and direction: the least objective (8).
double brute_force(const milp::Instance& in) {
  const int m = in.uavs, P = in.pairs;
  double best = 1e300;
  std::vector<int> who(static_cast<std::size_t>(P), 0);
  // best distance of UAV k over a set of pairs: all permutations and directions
  auto best_route = [&](int k, std::vector<int> mine) {
    if (mine.empty()) return 0.0;
    double b = 1e300;
    std::sort(mine.begin(), mine.end());
    do {
      for (int dirs = 0; dirs < (1 << mine.size()); ++dirs) {
        double d = 0.0;
        int here = k;
        for (std::size_t t = 0; t < mine.size(); ++t) {
          int a = m + 2 * mine[t], c = a + 1;
          if (dirs >> t & 1) std::swap(a, c);
          d += in.c(here, a) + in.c(a, c);
          here = c;
        }
        b = std::min(b, d + in.c(here, k));
      }
    } while (std::next_permutation(mine.begin(), mine.end()));
    return b;
  };
  const int combos = static_cast<int>(std::pow(m, P));
  for (int code = 0; code < combos; ++code) {
    int c = code;
    std::vector<std::vector<int>> sets(static_cast<std::size_t>(m));
    for (int p = 0; p < P; ++p, c /= m) sets[static_cast<std::size_t>(c % m)].push_back(p);
    if (std::any_of(sets.begin(), sets.end(), [](const auto& s) { return s.empty(); })) continue;  // (6)
    double s = 0.0, total = 0.0;
    for (int k = 0; k < m; ++k) {
      const double d = best_route(k, sets[static_cast<std::size_t>(k)]);
      s = std::max(s, d / in.weight[static_cast<std::size_t>(k)]);
      total += d;
    }
    best = std::min(best, s + total / m);
  }
  return best;
}

/// A random instance like the paper's: `pairs` parallel lines 20 m apart with ragged ends, depots
/// below them, the non-nearby penalty (x2) on waypoints numbered more than 2 apart.
milp::Instance random_instance(std::mt19937& rng, int uavs, int pairs, std::vector<double> weight) {
  std::uniform_real_distribution<double> u(0.0, 100.0);
  milp::Instance in;
  in.uavs = uavs;
  in.pairs = pairs;
  std::vector<Point> pos;
  for (int k = 0; k < uavs; ++k) pos.push_back({u(rng), -20.0});
  for (int p = 0; p < pairs; ++p) {
    const double x = 10.0 + 20.0 * p, y0 = u(rng) * 0.3, y1 = 50.0 + u(rng) * 0.5;
    pos.push_back({x, y0});
    pos.push_back({x, y1});
  }
  const int n = in.nodes();
  in.cost.resize(static_cast<std::size_t>(n * n));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double c = boustro::dist(pos[static_cast<std::size_t>(i)], pos[static_cast<std::size_t>(j)]);
      if (i >= uavs && j >= uavs && std::abs(i - j) > 2) c *= 2.0;
      in.cost[static_cast<std::size_t>(i * n + j)] = c;
    }
  in.weight = std::move(weight);
  return in;
}

TEST(MilpModel, SmallInstancesAreSolvedToTheBruteForceOptimum) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 6; ++trial) {
    // 2 UAVs, 4 vertical segments (10 nodes), random depots and lengths
    const milp::Instance in = random_instance(
        rng, 2, 4, trial % 2 == 0 ? std::vector<double>{1.0, 1.0} : std::vector<double>{0.6, 1.4});
    // a poor but feasible start: everything but one pair to UAV 0
    milp::Routes start;
    start.seq = {{0, 2, 3, 4, 5, 6, 7}, {1, 8, 9}};
    const milp::Result r = milp::solve(in, start, milp::Limits{}, Context{});
    ASSERT_TRUE(r.optimal) << r.status;
    const double bf = brute_force(in);
    EXPECT_NEAR(r.objective, bf, 1e-6 * bf) << "trial " << trial;
    EXPECT_NEAR(milp::objective(in, r.routes), r.objective, 1e-9 * bf);
    EXPECT_LE(r.gap, 1e-6);
    EXPECT_EQ(r.binaries, 2 * 9 * 8 + 2 * 4);  // per UAV its depot and 8 waypoints; y per pair and UAV
  }
}

/// Pairs 0..P-1 dealt round-robin to the UAVs, each flown low end first: feasible, poor.
milp::Routes round_robin(const milp::Instance& in) {
  milp::Routes r;
  for (int k = 0; k < in.uavs; ++k) r.seq.push_back({k});
  for (int p = 0; p < in.pairs; ++p) {
    auto& q = r.seq[static_cast<std::size_t>(p % in.uavs)];
    q.push_back(in.uavs + 2 * p);
    q.push_back(in.uavs + 2 * p + 1);
  }
  return r;
}

TEST(MilpModel, TheContractedModelHasTheExactModelsOptimum) {
  std::mt19937 rng(11);
  milp::Limits exact, contracted;
  exact.model = milp::Formulation::Exact;
  contracted.model = milp::Formulation::Contracted;
  int pruned = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const int pairs = 3 + trial % 3;  // 3 to 5 lines, 8 to 12 nodes
    const milp::Instance in = random_instance(
        rng, 2, pairs, trial % 2 == 0 ? std::vector<double>{1.0, 1.0} : std::vector{0.7, 1.3});
    const milp::Routes start = round_robin(in);
    const milp::Result e = milp::solve(in, start, exact, Context{});
    const milp::Result c = milp::solve(in, start, contracted, Context{});
    ASSERT_TRUE(e.optimal) << e.status;
    ASSERT_TRUE(c.optimal) << c.status;
    EXPECT_EQ(c.model, "contracted");
    EXPECT_NEAR(c.objective, e.objective, 1e-6 * e.objective) << "trial " << trial;
    const double bf = brute_force(in);
    EXPECT_NEAR(c.objective, bf, 1e-6 * bf) << "trial " << trial;
    // the contracted routes fly whole pairs and cost what CBC says
    EXPECT_TRUE(milp::back_and_forth(in, c.routes));
    EXPECT_TRUE(milp::back_and_forth(in, e.routes));
    EXPECT_NEAR(milp::objective(in, c.routes), c.objective, 1e-9 * bf);
    // one node per pair and orientation: no pair-internal arcs, no constraint (7), MTZ over pairs;
    // arcs that cannot beat the start are left out
    const int m = 2, P = pairs;
    EXPECT_EQ(c.binaries + c.pruned_arcs, m * (2 * P + 2 * P + 2 * P * (2 * P - 2)) + m * P);
    EXPECT_EQ(e.pruned_arcs, 0);
    EXPECT_EQ(c.rows, P * (1 + m) + m * (1 + 2 * P) + m + P * (P - 1) + m);
    EXPECT_LT(c.rows, e.rows);
    EXPECT_LT(c.binaries, e.binaries);
    // from a good start (contiguous halves) more arcs are left out, and the optimum stays
    milp::Routes halves{{{0}, {1}}};
    for (int p = 0; p < P; ++p) {
      auto& q = halves.seq[p < P / 2 ? 0u : 1u];
      q.push_back(m + 2 * p);
      q.push_back(m + 2 * p + 1);
    }
    const milp::Result h = milp::solve(in, halves, contracted, Context{});
    ASSERT_TRUE(h.optimal) << h.status;
    EXPECT_NEAR(h.objective, bf, 1e-6 * bf) << "trial " << trial;
    EXPECT_TRUE(milp::back_and_forth(in, h.routes));
    if (milp::objective(in, halves) < milp::objective(in, start)) {
      EXPECT_GE(h.pruned_arcs, c.pruned_arcs);
    }
    pruned += h.pruned_arcs;
  }
  EXPECT_GT(pruned, 0) << "the pruning was exercised";
}

TEST(MilpModel, TheContractedModelSolvesThreeUavsToTheBruteForceOptimum) {
  std::mt19937 rng(3);
  milp::Limits contracted;
  contracted.model = milp::Formulation::Contracted;
  for (int trial = 0; trial < 3; ++trial) {
    const milp::Instance in = random_instance(rng, 3, 6, {1.0, 1.0, 1.0});
    const milp::Result c = milp::solve(in, round_robin(in), contracted, Context{});
    ASSERT_TRUE(c.optimal) << c.status;
    const double bf = brute_force(in);
    EXPECT_NEAR(c.objective, bf, 1e-6 * bf) << "trial " << trial;
    EXPECT_TRUE(milp::back_and_forth(in, c.routes));
    for (const auto& q : c.routes.seq) EXPECT_GE(q.size(), 3u) << "constraint (6): every UAV flies";
  }
}

TEST(MilpModel, BackAndForthRejectsSplitPairs) {
  std::mt19937 rng(5);
  const milp::Instance in = random_instance(rng, 2, 2, {1.0, 1.0});
  EXPECT_TRUE(milp::back_and_forth(in, {{{0, 2, 3}, {1, 5, 4}}}));
  EXPECT_FALSE(milp::back_and_forth(in, {{{0, 2, 4}, {1, 3, 5}}})) << "pair 0 split between the UAVs";
  EXPECT_FALSE(milp::back_and_forth(in, {{{0, 2, 3, 4}, {1, 5}}})) << "pair 1 entered and left apart";
  EXPECT_FALSE(milp::back_and_forth(in, {{{0, 2, 3, 1}, {1, 4, 5}}})) << "a depot as a waypoint";
}

// ---- the planner ----

TEST(MilpPlanner, EveryLineIsFlownEndToEndByExactlyOneUav) {
  const Problem p = problem({rect(0, 0, 300, 200)}, {}, {{-20, -20}, {320, -20}, {150, 230}}, 25.0);
  const Assignment a = run(p, {{"max_uavs_per_milp", 3}});
  const milp::Lines lines = lines_of(p);
  ASSERT_EQ(lines.segments.size(), 8u) << "legs along the 300 m side, 25 m apart across 200 m";
  const auto who = flown_by(a, lines);
  for (std::size_t s = 0; s < who.size(); ++s) EXPECT_NE(who[s], -1) << "segment " << s << " not flown";
  for (const auto& u : a.uavs) {
    EXPECT_FALSE(u.coverage.empty()) << "constraint (6): every UAV flies";
    EXPECT_FALSE(u.region.empty());
  }
  EXPECT_TRUE(a.complete) << "the node limit is a deterministic budget, not a time limit";
  const auto& c = a.diagnostics.at("clusters")[0];
  EXPECT_LE(c.at("bound").get<double>(), c.at("objective").get<double>() + 1e-9);
  // the legs run along the longest edge (east-west)
  for (const auto& u : a.uavs)
    for (const auto& leg : u.coverage) EXPECT_NEAR(leg[0].y(), leg[1].y(), 1e-6);
}

TEST(MilpPlanner, AConvexHexagonIsCutLikeACakeAmongFiveUavs) {
  MultiPolygon hex;
  hex.push_back(poly({{0, 0}, {60, -10}, {110, 20}, {115, 80}, {50, 110}, {-5, 70}}));
  std::vector<Point> starts;
  for (double y : {0.0, 5.0, -5.0, 10.0, -10.0}) starts.push_back({-20.0, 50.0 + y});
  const Problem p = problem(hex, {}, starts, 9.0);
  const Assignment a = run(p, {{"max_uavs_per_milp", 5}});
  const milp::Lines lines = lines_of(p);
  ASSERT_LE(lines.segments.size(), 14u) << "one MILP";
  ASSERT_GE(lines.segments.size(), 10u);
  const auto who = flown_by(a, lines);
  // each UAV's lines are one contiguous band
  for (int k = 0; k < 5; ++k) {
    std::vector<int> mine;
    for (std::size_t s = 0; s < who.size(); ++s)
      if (who[s] == k) mine.push_back(lines.segments[s].line);
    ASSERT_FALSE(mine.empty()) << "UAV " << k;
    std::sort(mine.begin(), mine.end());
    EXPECT_EQ(mine.back() - mine.front() + 1, static_cast<int>(mine.size()))
        << "UAV " << k << "'s band has a gap";
    EXPECT_EQ(a.uavs[static_cast<std::size_t>(k)].region.size(), 1u)
        << "UAV " << k << "'s region is connected";
  }
  for (int i = 0; i < 5; ++i)
    for (int j = i + 1; j < 5; ++j) {
      MultiPolygon both;
      bg::intersection(a.uavs[static_cast<std::size_t>(i)].region, a.uavs[static_cast<std::size_t>(j)].region,
                       both);
      EXPECT_LT(bg::area(both), 1e-6) << "regions " << i << " and " << j << " overlap";
    }
}

TEST(MilpPlanner, ThreeAreasWithTwoUavs) {
  MultiPolygon areas;
  areas.push_back(rect(0, 0, 40, 30));
  areas.push_back(rect(60, 0, 100, 25));
  areas.push_back(poly({{20, 50}, {70, 50}, {45, 80}}));
  const Problem p = problem(areas, {}, {{50, -10}, {55, -10}}, 6.0);
  ASSERT_EQ(p.free.size(), 3u);
  const Assignment a = run(p, {{"max_uavs_per_milp", 2}, {"max_segments", 16}});
  const milp::Lines lines = lines_of(p);
  ASSERT_EQ(lines.parts.size(), 3u);
  const auto who = flown_by(a, lines);
  for (std::size_t s = 0; s < who.size(); ++s) EXPECT_NE(who[s], -1) << "segment " << s << " not flown";
  double total = 0.0;
  for (const auto& u : a.uavs) {
    EXPECT_FALSE(u.coverage.empty());
    MultiPolygon outside;
    bg::difference(u.region, p.free, outside);
    EXPECT_LT(bg::area(outside), 1e-6);
    total += bg::area(u.region);
  }
  EXPECT_GT(total, 0.9 * bg::area(p.free)) << "the strips cover the areas";
  // the longest edge of each part sets its direction: the triangle's base (east-west) too
  for (const auto& part : a.diagnostics.at("parts"))
    EXPECT_NEAR(part.at("angle_deg").get<double>(), 90.0, 1e-6);
}

TEST(MilpPlanner, NoLegEntersTheNoFlyZoneOfANonConvexArea) {
  // an L with a no-fly zone in its long arm: lines are cut into several segments
  MultiPolygon area;
  area.push_back(poly({{0, 0}, {200, 0}, {200, 60}, {60, 60}, {60, 160}, {0, 160}}));
  MultiPolygon nfz;
  nfz.push_back(rect(100, 15, 130, 45));
  const Problem p = problem(area, nfz, {{-10, -10}, {210, -10}}, 10.0);
  const Assignment a = run(p);
  const milp::Lines lines = lines_of(p);
  const auto who = flown_by(a, lines);
  for (std::size_t s = 0; s < who.size(); ++s) EXPECT_NE(who[s], -1) << "segment " << s << " not flown";
  std::map<std::pair<int, int>, int> per_line;
  for (const auto& s : lines.segments) ++per_line[{s.part, s.line}];
  EXPECT_TRUE(std::any_of(per_line.begin(), per_line.end(), [](const auto& e) { return e.second > 1; }))
      << "some line is cut by the zone";
  for (const auto& u : a.uavs)
    for (const auto& leg : u.coverage) {
      EXPECT_FALSE(geometry::segment_enters(p.no_fly, leg[0], leg[1], 0.0));
      EXPECT_TRUE(geometry::segment_within(p.free, leg[0], leg[1], 1e-6));
      EXPECT_GE(geometry::distance(p.no_fly, leg[0]), 0.49);
    }
}

/// The pieces (connected parts in the segment adjacency graph) of each UAV's segments.
std::vector<int> pieces_per_uav(const std::vector<int>& who, const milp::Lines& lines, std::size_t uavs) {
  const auto adj = milp::adjacency(lines);
  std::vector<int> pieces(uavs, 0);
  std::vector<char> seen(who.size(), 0);
  for (std::size_t s = 0; s < who.size(); ++s) {
    if (seen[s] || who[s] < 0) continue;
    ++pieces[static_cast<std::size_t>(who[s])];
    std::vector<std::size_t> stack{s};
    seen[s] = 1;
    while (!stack.empty()) {
      const std::size_t u = stack.back();
      stack.pop_back();
      for (int v : adj[u])
        if (!seen[static_cast<std::size_t>(v)] && who[static_cast<std::size_t>(v)] == who[s])
          seen[static_cast<std::size_t>(v)] = 1, stack.push_back(static_cast<std::size_t>(v));
    }
  }
  return pieces;
}

/// The legs of `a` as segments on the lines of `lines` (found by their position across the lines),
/// sorted part by part, line by line, low to high, with the gaps at cuts closed: each UAV's legs, cut
/// segments included. Fails the test for a leg off every line.
std::pair<milp::Lines, std::vector<int>> legs_as_segments(const Assignment& a, const milp::Lines& lines) {
  milp::Lines out;
  out.parts = lines.parts;
  std::vector<std::pair<milp::Segment, int>> legs;
  for (std::size_t k = 0; k < a.uavs.size(); ++k)
    for (const auto& leg : a.uavs[k].coverage) {
      bool found = false;
      for (std::size_t c = 0; c < lines.parts.size() && !found; ++c) {
        const auto& f = lines.parts[c].frame;
        const Point p = f.to(leg[0]), q = f.to(leg[1]);
        if (std::abs(p.x() - q.x()) > 1e-6) continue;
        for (std::size_t l = 0; l < lines.parts[c].xs.size() && !found; ++l)
          if (std::abs(p.x() - lines.parts[c].xs[l]) < 1e-6) {
            milp::Segment s;
            s.a = p.y() < q.y() ? leg[0] : leg[1];
            s.b = p.y() < q.y() ? leg[1] : leg[0];
            s.part = static_cast<int>(c);
            s.line = static_cast<int>(l);
            legs.emplace_back(s, static_cast<int>(k));
            found = true;
          }
      }
      EXPECT_TRUE(found) << "a leg off the sweep lines";
    }
  auto lo = [&](const milp::Segment& s) {
    return out.parts[static_cast<std::size_t>(s.part)].frame.to(s.a).y();
  };
  std::sort(legs.begin(), legs.end(), [&](const auto& x, const auto& y) {
    return std::tuple(x.first.part, x.first.line, lo(x.first)) <
           std::tuple(y.first.part, y.first.line, lo(y.first));
  });
  std::vector<int> who;
  for (const auto& [s, k] : legs) {
    // a cut: the legs on both sides of it end milp::kCutGapM short of it; closed here
    if (!out.segments.empty() && out.segments.back().part == s.part && out.segments.back().line == s.line &&
        std::abs(boustro::dist(out.segments.back().b, s.a) - 2.0 * milp::kCutGapM) < 1e-6) {
      const Point mid{0.5 * (s.a.x() + out.segments.back().b.x()),
                      0.5 * (s.a.y() + out.segments.back().b.y())};
      out.segments.back().b = mid;
      out.segments.push_back(s);
      out.segments.back().a = mid;
    } else {
      out.segments.push_back(s);
    }
    who.push_back(k);
  }
  return {out, who};
}

TEST(MilpPlanner, EachUavOfANonConvexAreaGetsOneConnectedPiece) {
  // a wide U (lines along its 300 m base cross both arms) with a no-fly zone in the base: the lines in
  // the arms have two segments each, so a split of the sweep order gives a UAV the tops of both arms
  MultiPolygon u;
  u.push_back(poly({{0, 0}, {300, 0}, {300, 200}, {200, 200}, {200, 60}, {100, 60}, {100, 200}, {0, 200}}));
  MultiPolygon nfz;
  nfz.push_back(rect(140, 20, 160, 40));
  for (const std::vector<Point>& starts :
       {std::vector<Point>{{-10, -10}, {310, -10}}, std::vector<Point>{{-10, -10}, {150, -10}, {310, -10}}}) {
    SCOPED_TRACE(starts.size());
    const Problem p = problem(u, nfz, starts, 10.0);
    const Assignment a = run(p);
    const milp::Lines lines = lines_of(p);
    std::map<int, int> per_line;
    for (const auto& s : lines.segments) ++per_line[s.line];
    EXPECT_GE(std::count_if(per_line.begin(), per_line.end(), [](const auto& e) { return e.second == 2; }),
              14)
        << "the arms' lines and the lines through the zone have two segments";
    const auto who = flown_by(a, lines);
    for (std::size_t s = 0; s < who.size(); ++s) EXPECT_NE(who[s], -1) << "segment " << s << " not flown";
    const auto [legs, leg_uav] = legs_as_segments(a, lines);
    const auto pieces = pieces_per_uav(leg_uav, legs, starts.size());
    for (std::size_t k = 0; k < starts.size(); ++k) {
      EXPECT_EQ(pieces[k], 1) << "UAV " << k << "'s legs are not one connected piece";
      EXPECT_EQ(a.uavs[k].region.size(), 1u) << "UAV " << k << "'s region is not one polygon";
      for (const auto& leg : a.uavs[k].coverage)
        EXPECT_FALSE(geometry::segment_enters(p.no_fly, leg[0], leg[1], 0.0));
    }
  }
}

TEST(MilpPlanner, CutSegmentsGiveEachUavOfABranchingAreaItsShareInOneConnectedPiece) {
  // the U of EachUavOfANonConvexAreaGetsOneConnectedPiece: whole segments miss the shares by up to an
  // arm; cutting the boundary segments of each piece where its share is met lands within 3 %
  MultiPolygon u;
  u.push_back(poly({{0, 0}, {300, 0}, {300, 200}, {200, 200}, {200, 60}, {100, 60}, {100, 200}, {0, 200}}));
  MultiPolygon nfz;
  nfz.push_back(rect(140, 20, 160, 40));
  const double spacing = 10.0;
  struct Case {
    std::vector<Point> starts;
    std::vector<double> shares;
  };
  const std::vector<Case> cases{{{{-10, -10}, {310, -10}}, {}},
                                {{{-10, -10}, {150, -10}, {310, -10}}, {}},
                                {{{-10, -10}, {150, -10}, {310, -10}}, {0.2, 0.3, 0.5}},
                                {{{-10, -10}, {150, -10}, {310, -10}}, {0.5, 0.3, 0.2}}};
  for (const auto& cs : cases) {
    const Problem p = problem(u, nfz, cs.starts, spacing, cs.shares);
    SCOPED_TRACE(::testing::Message() << p.starts.size() << " UAVs, first share " << p.shares[0]);
    const Assignment a = run(p);
    const milp::Lines lines = lines_of(p);
    const auto [legs, who] = legs_as_segments(a, lines);
    // every line covered exactly once: the legs on a line lie in its free segments, do not overlap and
    // add up to its free length
    std::map<int, double> free_len, flown_len;
    for (const auto& s : lines.segments) free_len[s.line] += s.length();
    for (std::size_t i = 0; i < legs.segments.size(); ++i) {
      const auto& s = legs.segments[i];
      flown_len[s.line] += s.length();
      EXPECT_GE(s.length(), spacing - 1e-6) << "a sliver on line " << s.line;
      EXPECT_TRUE(std::any_of(lines.segments.begin(), lines.segments.end(),
                              [&](const milp::Segment& f) {
                                return f.line == s.line &&
                                       bg::distance(s.a, bg::model::segment<Point>{f.a, f.b}) < 1e-6 &&
                                       bg::distance(s.b, bg::model::segment<Point>{f.a, f.b}) < 1e-6;
                              }))
          << "a leg outside the free segments of line " << s.line;
      if (i > 0 && legs.segments[i - 1].line == s.line) {
        const auto& f = legs.parts[static_cast<std::size_t>(s.part)].frame;
        EXPECT_LE(f.to(legs.segments[i - 1].b).y(), f.to(s.a).y() + 1e-6) << "overlap on line " << s.line;
      }
    }
    for (const auto& [l, len] : free_len) EXPECT_NEAR(flown_len[l], len, 1e-6) << "line " << l;
    EXPECT_EQ(flown_len.size(), free_len.size());
    // shares of the scanned length (the swath area), each UAV one connected piece in its own region
    double total = 0.0;
    std::vector<double> mine(p.starts.size(), 0.0);
    for (std::size_t i = 0; i < legs.segments.size(); ++i)
      total += legs.segments[i].length(), mine[static_cast<std::size_t>(who[i])] += legs.segments[i].length();
    const auto pieces = pieces_per_uav(who, legs, p.starts.size());
    std::string got;
    for (std::size_t k = 0; k < p.starts.size(); ++k)
      got += (k ? " / " : "") + std::to_string(mine[k] / total);
    ::testing::Test::RecordProperty(
        "shares_" + std::to_string(p.starts.size()) + "_uavs_first_" + std::to_string(p.shares[0]),
        got + " (" + std::to_string(legs.segments.size()) + " legs, " +
            std::to_string(legs.segments.size() - lines.segments.size()) + " cuts)");
    for (std::size_t k = 0; k < p.starts.size(); ++k) {
      EXPECT_NEAR(mine[k] / total, p.shares[k], 0.03) << "UAV " << k;
      EXPECT_EQ(pieces[k], 1) << "UAV " << k << "'s legs are not one connected piece";
      EXPECT_EQ(a.uavs[k].region.size(), 1u) << "UAV " << k << "'s region is not one polygon";
      for (const auto& leg : a.uavs[k].coverage)
        EXPECT_TRUE(geometry::segment_within(a.uavs[k].region, leg[0], leg[1], 1e-6)) << "UAV " << k;
      for (std::size_t j = k + 1; j < p.starts.size(); ++j) {
        MultiPolygon both;
        bg::intersection(a.uavs[k].region, a.uavs[j].region, both);
        EXPECT_LT(bg::area(both), 1e-3) << "regions " << k << " and " << j << " overlap";
      }
    }
  }
}

TEST(MilpPlanner, CoverageModeExtendsLegsPastTheBoundaryButNotIntoZones) {
  // a 200 m x 100 m field, lines east-west; a zone inside it (legs stop 0.5 m short of it) and one just
  // outside its east side (the legs there cannot be extended without entering it)
  Problem p = problem({rect(0, 0, 200, 100)}, {rect(80, 40, 120, 60), rect(203, 0, 230, 30)},
                      {{-10, -10}, {210, 110}}, 10.0);
  p.mode = Mode::Coverage;
  const double half = 0.5 * p.footprint_m;
  const Assignment a = run(p);
  const milp::Lines lines = lines_of(p);
  std::size_t legs = 0, extended = 0;
  for (const auto& uav : a.uavs)
    for (const auto& leg : uav.coverage) {
      ++legs;
      ASSERT_EQ(leg.size(), 2u);
      EXPECT_FALSE(geometry::segment_enters(p.no_fly, leg[0], leg[1], 0.0));
      for (const Point& e : leg) {
        EXPECT_GE(geometry::distance(p.no_fly, e), 0.49);
        const double out = bg::distance(e, p.area);
        if (out > 1e-6) {
          ++extended;
          EXPECT_NEAR(out, half, 1e-6) << "an end beyond the boundary is half a footprint out";
        }
      }
      // the leg covers a whole segment: it contains one of the lines' segments
      EXPECT_TRUE(std::any_of(lines.segments.begin(), lines.segments.end(), [&](const milp::Segment& s) {
        return bg::distance(s.a, bg::model::segment<Point>{leg[0], leg[1]}) < 1e-6 &&
               bg::distance(s.b, bg::model::segment<Point>{leg[0], leg[1]}) < 1e-6;
      }));
    }
  EXPECT_EQ(legs, lines.segments.size());
  // 10 lines, two ends each on the boundary, the 3 lines next to the outer zone end short on the east
  EXPECT_EQ(extended, 2 * 10 - 3u);
  // strict mode keeps every end inside
  p.mode = Mode::Strict;
  for (const auto& uav : run(p).uavs)
    for (const auto& leg : uav.coverage)
      for (const Point& e : leg) EXPECT_LT(bg::distance(e, p.area), 1e-6);
}

TEST(MilpRegions, ThousandsOfStripsKeepEveryBand) {
  // a 2 km square at 2 m (1 000 lines) in 10 bands of uneven width: each region is its band, in one
  // piece (uniting the strips one by one lost most of a band to the overlay in a plan of this size)
  const std::vector<int> edges{0, 98, 199, 302, 400, 507, 600, 709, 800, 908, 1000};
  // the third: the square as a mission gives it, 2 km on a side in WGS84 around (24.40 E, 40.93 N)
  const double mx = 111320.0 * std::cos(40.93 * std::numbers::pi / 180.0), my = 110540.0;
  GeoRing ring;
  for (const auto& [x, y] :
       std::vector<std::pair<double, double>>{{0, 0}, {2000, 0}, {2000, 2000}, {0, 2000}, {0, 0}})
    ring.push_back({24.40 + x / mx, 40.93 + y / my});
  const std::vector<GeoPolygon> geo{{ring}};
  const MultiPolygon wgs = geometry::to_local(geo, geodesy::LocalFrame(geodesy::centroid(geo)));
  for (const Polygon& square : {rect(0, 0, 2000, 2000), rect(-1000, -1000, 1000, 1000), wgs.front()})
    for (const nlohmann::json& params :
         {nlohmann::json(nullptr), nlohmann::json{{"angle_deg", 0}}, nlohmann::json{{"angle_deg", 90}}}) {
      SCOPED_TRACE(params.dump() + " " + std::to_string(square.outer()[0].x()));
      const Problem p = problem({square}, {}, {{0, 0}}, 2.0);
      const milp::Lines lines = lines_of(p, params);
      const std::size_t n = lines.segments.size();
      ASSERT_NEAR(static_cast<double>(n), 1000.0, 10.0);
      std::vector<int> owner(n);
      std::vector<int> count(10, 0);
      for (std::size_t k = 0; k + 1 < edges.size(); ++k)
        for (std::size_t s = static_cast<std::size_t>(edges[k]) * n / 1000;
             s < static_cast<std::size_t>(edges[k + 1]) * n / 1000; ++s)
          owner[s] = static_cast<int>(k), ++count[k];
      const auto regs = milp::regions(lines, p.free, owner, 10, Context{});
      for (std::size_t k = 0; k < 10; ++k) {
        EXPECT_EQ(regs[k].size(), 1u) << "band " << k;
        const double want = static_cast<double>(count[k]) / static_cast<double>(n) * bg::area(p.free);
        EXPECT_NEAR(bg::area(regs[k]), want, 2e-3 * bg::area(p.free)) << "band " << k;
      }
    }
}

TEST(MilpPlanner, OnEveryHardShapeTheRegionsFillTheFreeAreaAndMeetTheShares) {
  // issue 26's shapes: milp divides the lines continuously (cut segments), so its regions are the whole
  // free area and each within a few points of its share. Two failures this guards: on the 4 km x 150 m
  // strip (4 lines, 6 UAVs) one UAV got nothing (16.7 points off: a group stopped rather than cut a
  // segment when taking one whole left too few for the groups after it); on the arctic field with a hole
  // beside a no-fly zone a UAV's region lost 16 % of the free area (Boost.Geometry's union of its cells,
  // whose sides differed by 0.2 mm from line to line, came out empty).
  for (const auto& shape : uavcover::testing::hard_shapes()) {
    SCOPED_TRACE(shape.name);
    nlohmann::json j = shape.mission;
    j["planner"] = "milp";
    const Plan p = plan(parse_mission(j.dump()));
    EXPECT_GE(uavcover::testing::regions_over_free_area(p), 0.995);
    EXPECT_LE(uavcover::testing::worst_share_deviation(p), 0.025);
    for (const auto& u : p.uavs) EXPECT_GT(bg::area(u.region_local), 0.0) << u.id << " has no region";
    for (std::size_t a = 0; a < p.uavs.size(); ++a)
      for (std::size_t b = a + 1; b < p.uavs.size(); ++b) {
        MultiPolygon both;
        bg::intersection(p.uavs[a].region_local, p.uavs[b].region_local, both);
        EXPECT_LT(bg::area(both), 1e-3 * p.free_area_m2)
            << p.uavs[a].id << " and " << p.uavs[b].id << " overlap";
      }
  }
}

TEST(MilpPlanner, TheTimeLimitReturnsTheBestAssignmentWithItsGap) {
  // 40 segments and 3 UAVs in one MILP: far from proven in a tenth of a second
  const Problem p = problem({rect(0, 0, 400, 200)}, {}, {{-20, 0}, {-20, 100}, {-20, 200}}, 5.0);
  const Assignment a = run(p, {{"max_segments", 60}, {"max_uavs_per_milp", 3}, {"time_limit_s", 0.1}});
  EXPECT_FALSE(a.complete);
  ASSERT_EQ(a.diagnostics.at("clusters").size(), 1u);
  const auto& c = a.diagnostics.at("clusters")[0];
  EXPECT_EQ(c.at("pairs").get<int>(), 40);
  EXPECT_FALSE(c.at("optimal").get<bool>());
  EXPECT_GT(c.at("gap").get<double>(), 0.0);
  EXPECT_LE(c.at("bound").get<double>(), c.at("objective").get<double>());
  EXPECT_FALSE(a.warnings.empty());
  // the incumbent is a whole plan
  const auto who = flown_by(a, lines_of(p));
  for (int w : who) EXPECT_NE(w, -1);
  // the same through the context's budget
  const Context ctx = Context{}.with_time_limit(std::chrono::milliseconds(100));
  const Assignment b = run(p, {{"max_segments", 60}, {"max_uavs_per_milp", 3}}, ctx);
  EXPECT_FALSE(b.complete);
  for (int w : flown_by(b, lines_of(p))) EXPECT_NE(w, -1);
}

TEST(MilpPlanner, AStopDuringTheSearchEndsCbcWithCancelled) {
  const Problem p = problem({rect(0, 0, 300, 150)}, {}, {{-20, 0}, {-20, 75}, {-20, 150}}, 10.0);
  std::stop_source stop;
  bool searching = false;
  std::chrono::steady_clock::time_point asked;
  const Context ctx(
      [&](std::string_view stage, double) {
        // the event handler's reports carry the incumbent: CBC is searching
        if (stage.find("incumbent") != std::string_view::npos && !searching) {
          searching = true;
          asked = std::chrono::steady_clock::now();
          stop.request_stop();
        }
      },
      stop.get_token());
  EXPECT_THROW((void)run(p, {{"max_segments", 60}, {"max_uavs_per_milp", 3}, {"node_limit", 10000000}}, ctx),
               Cancelled);
  EXPECT_TRUE(searching) << "CBC never reported from its search";
  // measured, not asserted (wall time depends on the machine)
  RecordProperty(
      "stop_latency_s",
      std::to_string(std::chrono::duration<double>(std::chrono::steady_clock::now() - asked).count()));
}

TEST(MilpPlanner, LargeInstancesAreClusteredByShare) {
  // 200 segments, 5 UAVs with unequal shares
  const Problem p =
      problem({rect(0, 0, 400, 1000)}, {}, {{-20, 0}, {-20, 250}, {-20, 500}, {-20, 750}, {-20, 1000}}, 2.0,
              {0.1, 0.15, 0.2, 0.25, 0.3});
  const Assignment a = run(p);
  const milp::Lines lines = lines_of(p);
  ASSERT_EQ(lines.segments.size(), 200u);
  const auto who = flown_by(a, lines);
  for (int w : who) EXPECT_NE(w, -1);
  EXPECT_EQ(a.diagnostics.at("clusters").size(), 5u);
  double total = 0.0;
  for (const auto& u : a.uavs) total += bg::area(u.region);
  for (std::size_t k = 0; k < 5; ++k) EXPECT_NEAR(bg::area(a.uavs[k].region) / total, p.shares[k], 0.03) << k;
}

TEST(MilpPlanner, AutoChoosesTheModelBySizeAndBothGiveTheSameOptimum) {
  // 3 lines and 2 UAVs: auto takes the exact model; 7 lines: the contracted one
  const Problem small = problem({rect(0, 0, 120, 30)}, {}, {{-10, 0}, {-10, 30}}, 10.0);
  const Problem larger = problem({rect(0, 0, 120, 70)}, {}, {{-10, 0}, {-10, 70}}, 10.0);
  const nlohmann::json joint = {{"max_uavs_per_milp", 2}, {"node_limit", 1000000}};
  auto cluster = [](const Assignment& a) { return a.diagnostics.at("clusters")[0]; };
  EXPECT_EQ(cluster(run(small, joint)).at("model"), "exact");
  const Assignment auto_large = run(larger, joint);
  EXPECT_EQ(cluster(auto_large).at("model"), "contracted");
  nlohmann::json exact = joint, contracted = joint;
  exact["model"] = "exact";
  contracted["model"] = "contracted";
  for (const Problem* p : {&small, &larger}) {
    const Assignment e = run(*p, exact), c = run(*p, contracted);
    ASSERT_TRUE(cluster(e).at("optimal").get<bool>());
    ASSERT_TRUE(cluster(c).at("optimal").get<bool>());
    EXPECT_EQ(cluster(e).at("model"), "exact");
    EXPECT_EQ(cluster(c).at("model"), "contracted");
    const double oe = cluster(e).at("objective").get<double>(), oc = cluster(c).at("objective").get<double>();
    EXPECT_NEAR(oc, oe, 1e-6 * oe);
    if (p == &larger) {
      EXPECT_GT(cluster(c).at("pruned_arcs").get<int>(), 0) << "the non-nearby penalty prunes";
    }
    // every line flown end to end by one UAV, every UAV flying
    const milp::Lines lines = lines_of(*p);
    for (int w : flown_by(c, lines)) EXPECT_NE(w, -1);
    for (const auto& u : c.uavs) EXPECT_FALSE(u.coverage.empty());
  }
}

TEST(MilpPlanner, BadParametersAreNamed) {
  auto field_of = [](const nlohmann::json& params) {
    try {
      (void)validate_params(info(), params);
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string("accepted");
  };
  EXPECT_EQ(field_of({{"max_segments", 1}}), "planner_params.max_segments");
  EXPECT_EQ(field_of({{"max_segments", 7.5}}), "planner_params.max_segments");
  EXPECT_EQ(field_of({{"direction", "sideways"}}), "planner_params.direction");
  EXPECT_EQ(field_of({{"node_limit", -1}}), "planner_params.node_limit");
  EXPECT_EQ(field_of({{"time_limit_s", 0}}), "planner_params.time_limit_s");
  EXPECT_EQ(field_of({{"nearby_penalty", 0.5}}), "planner_params.nearby_penalty");
  EXPECT_EQ(field_of({{"angle_deg", "north"}}), "planner_params.angle_deg");
  EXPECT_EQ(field_of({{"gurobi", true}}), "planner_params.gurobi");
  EXPECT_EQ(field_of({{"model", "gurobi"}}), "planner_params.model");
  EXPECT_EQ(field_of({{"model", 1}}), "planner_params.model");
  EXPECT_EQ(field_of({{"direction", "auto"}, {"angle_deg", 30}}), "accepted");
  // a spacing that would give too many lines is refused by field, before any allocation
  Problem p = problem({rect(0, 0, 1000, 1000)}, {}, {{0, 0}}, 0.01);
  try {
    (void)run(p);
    FAIL() << "planned 100000 lines";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "spacing_m");
  }
}

}  // namespace
#endif
