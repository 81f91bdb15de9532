// DARP's division at scale (issue 16): the waves and the border rebalance keep every region connected
// and holding its start whatever the shares; equal and unequal shares (1..P) converge within 2 % of
// each participant's own share, starts on the edge or scattered; deterministic.
#include <gtest/gtest.h>

#include <random>

#include "planners/darp/darp_props.hpp"

namespace uavcover::test {
namespace {

/// The free cells of a 2 400 x 2 000 m field with a no-fly block, at ds 10 m (120 x 100 mega-cells),
/// with `P` distinct start cells drawn from `seed` (on the field's outer edge, or anywhere when
/// `scattered`) and shares 1..P.
struct Field {
  grid::Grid g;
  darp::DivisionInput in;
};

Field field(int P, std::uint64_t seed, double scale = 1.0, bool scattered = false) {
  const MultiPolygon area{rect(0, 0, 2400 * scale, 2000 * scale)};
  const MultiPolygon nfz{rect(700 * scale, 600 * scale, 1100 * scale, 1300 * scale)};
  const darp::Input din = make_input(area, nfz, {}, {}, 10, Mode::Strict, 1);
  const grid::Prepared prep = grid::prepare(din.free, din.no_fly, 10, Mode::Strict);
  Field f{grid::rasterize(prep, 0, 0, 0), {}};
  std::vector<int> label;
  EXPECT_EQ(grid::components(f.g, label), 1);
  for (int k = 0; k < f.g.rows * f.g.cols; ++k)
    if (f.g.free[k]) f.in.cells.push_back(k);
  // starts on the field's outer edge (take-off beside the field), drawn from the seed
  std::vector<int> edge;
  for (int k : f.in.cells) {
    const int r = k / f.g.cols, c = k % f.g.cols;
    if (scattered || r == f.g.fr0 || r == f.g.fr1 || c == f.g.fc0 || c == f.g.fc1) edge.push_back(k);
  }
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, edge.size() - 1);
  std::vector<char> used(f.g.rows * f.g.cols, 0);
  while (static_cast<int>(f.in.starts.size()) < P) {
    const int k = edge[pick(rng)];
    if (!used[k]) used[k] = 1, f.in.starts.push_back(k);
  }
  const double total = P * (P + 1) / 2.0;
  for (int i = 0; i < P; ++i)
    f.in.targets.push_back((i + 1) / total * static_cast<double>(f.in.cells.size()));
  f.in.seed = seed;
  return f;
}

/// Regions of `r` over the grid's links: each connected and holding its start.
void expect_connected(const Field& f, const darp::DivisionResult& r) {
  const int N = f.g.rows * f.g.cols;
  std::vector<int> owner(N, -1);
  for (std::size_t x = 0; x < f.in.cells.size(); ++x) owner[f.in.cells[x]] = r.owner[x];
  std::array<int, 4> nb{};
  for (std::size_t i = 0; i < f.in.starts.size(); ++i) {
    ASSERT_EQ(owner[f.in.starts[i]], static_cast<int>(i)) << "start of " << i;
    std::vector<char> seen(N, 0);
    std::vector<int> stack{f.in.starts[i]};
    seen[f.in.starts[i]] = 1;
    int reached = 0;
    while (!stack.empty()) {
      const int u = stack.back();
      stack.pop_back();
      ++reached;
      const int m = f.g.neighbours(u, nb);
      for (int j = 0; j < m; ++j)
        if (!seen[nb[j]] && owner[nb[j]] == static_cast<int>(i)) seen[nb[j]] = 1, stack.push_back(nb[j]);
    }
    EXPECT_EQ(reached, r.counts[i]) << "region " << i << " is in pieces";
  }
}

/// Every participant within its own tolerance (2 % of its target), the flag saying so, every region
/// connected and holding its start, every cell assigned.
void expect_balanced(const Field& f, const darp::DivisionResult& r) {
  int total = 0;
  for (int c : r.counts) total += c;
  EXPECT_EQ(total, static_cast<int>(f.in.cells.size()));
  for (std::size_t i = 0; i < f.in.targets.size(); ++i)
    EXPECT_LE(std::fabs(r.counts[i] - f.in.targets[i]), darp::tolerance(f.in.targets[i]))
        << "participant " << i << ": " << r.counts[i] << " cells for " << f.in.targets[i];
  EXPECT_TRUE(r.converged);
  expect_connected(f, r);
}

TEST(DarpDivision, UnequalSharesOneToTwentyConvergeWithStartsOnTheEdge) {
  for (std::uint64_t seed : {1, 2}) {
    SCOPED_TRACE(seed);
    const Field f = field(20, seed, 2.5);  // 75k cells x 20 participants: the waves' side
    expect_balanced(f, darp::divide(f.g, f.in));
  }
}

TEST(DarpDivision, UnequalSharesOneToFortyConvergeWithScatteredStarts) {
  for (std::uint64_t seed : {3, 7}) {
    SCOPED_TRACE(seed);
    const Field f = field(40, seed, 2.0, true);  // 48k cells x 40 participants, shares 1..40
    expect_balanced(f, darp::divide(f.g, f.in));
  }
}

TEST(DarpDivision, FiftyEqualSharesConverge) {
  Field f = field(50, 4, 2.5);
  std::fill(f.in.targets.begin(), f.in.targets.end(), static_cast<double>(f.in.cells.size()) / 50);
  const darp::DivisionResult r = darp::divide(f.g, f.in);
  EXPECT_TRUE(r.converged);
  for (int i = 0; i < 50; ++i)
    EXPECT_LE(std::fabs(r.counts[i] - f.in.targets[i]), darp::tolerance(f.in.targets[i]));
  expect_connected(f, r);
}

TEST(DarpDivision, SameInputSameDivision) {
  Field f = field(20, 5);
  f.in.max_iterations = 60;
  const darp::DivisionResult a = darp::divide(f.g, f.in), b = darp::divide(f.g, f.in);
  EXPECT_EQ(a.owner, b.owner);
  EXPECT_EQ(a.iterations, b.iterations);
}

TEST(DarpDivision, ToleranceIsTwoPercentOfTheOwnTargetAtLeastOneCell) {
  EXPECT_DOUBLE_EQ(darp::tolerance(5000), 100);
  EXPECT_DOUBLE_EQ(darp::tolerance(476), 9.52);
  EXPECT_DOUBLE_EQ(darp::tolerance(20), 1);
}

TEST(DarpDivision, UnequalSharesThroughThePlannerKeepEveryProperty) {
  // the whole planner (placement, components, division) on a mid-size field: shares 1..20
  const Field f = field(20, 6);
  std::vector<Point> starts;
  std::vector<double> shares;
  for (int i = 0; i < 20; ++i) {
    starts.push_back(f.g.cell_centre(f.in.starts[i] / f.g.cols, f.in.starts[i] % f.g.cols));
    shares.push_back(i + 1.0);
  }
  const darp::Input in =
      make_input({rect(0, 0, 2400, 2000)}, {rect(700, 600, 1100, 1300)}, starts, shares, 10, Mode::Strict, 3);
  darp::Options opt;
  opt.placement_evaluations = 40;  // the division is under test, not the placement
  const darp::Output out = darp::run(in, opt, Context{});
  check_plan(in, out, true);  // exclusive, connected, starts held, loops inside, shares within 2 %
}

}  // namespace
}  // namespace uavcover::test
