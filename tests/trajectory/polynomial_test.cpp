// Method::Polynomial (issue 33, Mondinelli 2025 §4.1): the four bounds on random 3D polylines and on
// the fixture's plans, continuity up to derivative P - 1 at the waypoints, through every waypoint, at
// rest at both ends, the mean speed per segment, and the refusals naming the field.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "export/fixture.hpp"
#include "trajectory/polylines.hpp"
#include "trajectory/trajectory.hpp"
#include "uavcover/error.hpp"

using namespace uavcover;
using namespace uavcover::trajectory;
using polylines::random_polyline;

namespace {

double norm(const Vec3& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

/// The d-th time derivative of axis `ax` of segment g at s in [0, 1] (its coefficients are in s; those
/// above the order are 0, so `order` may be kMaxOrder).
double derivative(const PolySegment& g, int order, int d, int ax, double s) {
  double r = 0;
  for (int j = order; j >= d; --j) {
    double f = 1;
    for (int q = 0; q < d; ++q) f *= j - q;
    r = r * s + g.c[static_cast<std::size_t>(ax)][static_cast<std::size_t>(j)] * f;
  }
  return r / std::pow(g.duration, d);
}

Options polynomial(int order = 5) {
  Options o;
  o.method = Method::Polynomial;
  o.order = order;
  return o;
}

/// Every bound on samples every `dt` (to 1e-9 relative), the report agreeing with them, rest at both
/// ends, through every waypoint, C^(P-1) at every waypoint.
void check_polynomial(const Trajectory& t, double dt) {
  const LimitReport& r = t.report();
  ASSERT_TRUE(r.hold);
  const double up = 1 + 1e-9;
  const auto samples = t.sample(dt);
  double v_lo = 0, v_hi = 0, a_lo = 0, a_hi = 0, speed = 0, accel = 0;
  for (const auto& s : samples) {
    for (int k = 0; k < 3; ++k) {
      v_lo = std::min(v_lo, s.v[k]);
      v_hi = std::max(v_hi, s.v[k]);
      a_lo = std::min(a_lo, s.a[k]);
      a_hi = std::max(a_hi, s.a[k]);
    }
    speed = std::max(speed, norm(s.v));
    accel = std::max(accel, norm(s.a));
  }
  EXPECT_LE(v_hi, r.v_max * up);
  EXPECT_GE(v_lo, r.v_min * up);
  EXPECT_LE(speed, r.v_max * up);
  EXPECT_LE(a_hi, r.a_max * up);
  EXPECT_GE(a_lo, r.a_min * up);
  EXPECT_LE(accel, r.a_max * up);
  // the report's extremes are the true ones: the samples never beyond them
  EXPECT_LE(v_hi, r.v_hi + 1e-9);
  EXPECT_GE(v_lo, r.v_lo - 1e-9);
  EXPECT_LE(speed, r.speed_max + 1e-9);
  EXPECT_LE(accel, r.accel_max + 1e-9);
  // at rest at both ends, at the first and last waypoints
  const Sample first = t.at(0), last = t.at(t.duration());
  EXPECT_LE(norm(first.v), 1e-9);
  EXPECT_LE(norm(last.v), 1e-9);
  const auto& w = t.waypoints();
  EXPECT_LE(norm({first.p[0] - w.front()[0], first.p[1] - w.front()[1], first.p[2] - w.front()[2]}), 1e-9);
  EXPECT_LE(norm({last.p[0] - w.back()[0], last.p[1] - w.back()[1], last.p[2] - w.back()[2]}), 1e-6);
  // through every waypoint, and continuous up to derivative P - 1 there
  const auto& g = t.polynomials();
  ASSERT_EQ(g.size() + 1, w.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    for (int ax = 0; ax < 3; ++ax) {
      EXPECT_NEAR(derivative(g[i], kMaxOrder, 0, ax, 0.0), w[i][static_cast<std::size_t>(ax)], 1e-6);
      EXPECT_NEAR(derivative(g[i], kMaxOrder, 0, ax, 1.0), w[i + 1][static_cast<std::size_t>(ax)], 1e-6);
    }
  }
}

/// Largest jump of derivative d over the interior waypoints, relative to the derivative's size there.
double worst_jump(const Trajectory& t, int d) {
  const auto& g = t.polynomials();
  double worst = 0;
  for (std::size_t i = 0; i + 1 < g.size(); ++i)
    for (int ax = 0; ax < 3; ++ax) {
      const double l = derivative(g[i], kMaxOrder, d, ax, 1.0),
                   r = derivative(g[i + 1], kMaxOrder, d, ax, 0.0);
      worst = std::max(worst, std::abs(l - r) / (1.0 + std::max(std::abs(l), std::abs(r))));
    }
  return worst;
}

}  // namespace

TEST(TrajectoryPolynomial, RandomPolylinesKeepTheFourLimits) {
  std::mt19937_64 rng(20261204);
  std::uniform_real_distribution<double> speed(1, 12), accel(0.5, 5), share(0.3, 1.0), mean(0.3, 1.0);
  for (int trial = 0; trial < 40; ++trial) {
    const auto w = random_polyline(rng, trial);
    Options o = polynomial(3 + 2 * (trial % 3));
    o.densify_m = trial % 2 == 0 ? 10.0 : 0.0;
    const Limits lim{speed(rng), accel(rng)};
    o.v_min = -share(rng) * lim.v_max;  // the lower bounds tighter than -v_max, -a_max: they bite
    o.a_min = -share(rng) * lim.a_max;
    o.v_mean = mean(rng) * lim.v_max;
    SCOPED_TRACE("trial " + std::to_string(trial) + " order " + std::to_string(o.order));
    const Trajectory t(w, lim, o);
    EXPECT_DOUBLE_EQ(t.report().v_min, o.v_min);
    EXPECT_DOUBLE_EQ(t.report().a_max, lim.a_max);
    check_polynomial(t, 0.01);
  }
}

TEST(TrajectoryPolynomial, ContinuousUpToDerivativeOrderMinusOneAtTheWaypoints) {
  std::mt19937_64 rng(7);
  for (const int order : {3, 5, 7}) {
    const auto w = random_polyline(rng, 8);
    const Trajectory t(w, {5, 2}, polynomial(order));
    SCOPED_TRACE("order " + std::to_string(order));
    for (int d = 0; d < order; ++d) EXPECT_LE(worst_jump(t, d), 1e-7) << "derivative " << d;
    // derivative P is not continuous: the polynomial has nothing left to match it with
    EXPECT_GT(worst_jump(t, order), 1e-3);
    // at rest: derivatives 1 .. (P - 1) / 2 are 0 at both ends
    const auto& g = t.polynomials();
    for (int d = 1; d <= (order - 1) / 2; ++d)
      for (int ax = 0; ax < 3; ++ax) {
        EXPECT_NEAR(derivative(g.front(), kMaxOrder, d, ax, 0.0), 0.0, 1e-9);
        EXPECT_NEAR(derivative(g.back(), kMaxOrder, d, ax, 1.0), 0.0, 1e-9);
      }
  }
}

TEST(TrajectoryPolynomial, EachSegmentKeepsItsMeanSpeedWhereNoLimitBites) {
  // the thesis's parameters: v_mean 3 m/s, v 5 m/s both ways, a 4 m/s^2 both ways, P 5; 1 km straight
  // densified every 10 m: every segment takes 10 m / 3 m/s (no bound bites)
  Options o = polynomial(5);
  o.v_mean = 3.0;
  const Trajectory t({{0, 0, 0}, {1000, 0, 0}}, {5, 4}, o);
  const auto& g = t.polynomials();
  ASSERT_EQ(g.size(), 100u);
  for (const auto& s : g) EXPECT_NEAR(s.duration, 10.0 / 3.0, 1e-12);
  EXPECT_NEAR(t.duration(), 1000.0 / 3.0, 1e-9);
  EXPECT_NEAR(t.at(g[50].t0 + 0.5).v[0], 3.0, 1e-6);
  EXPECT_EQ(t.report().stretched, 0u);
  check_polynomial(t, 0.01);
  // at v_mean = v_max the speeding up and slowing down ring past v_max (a ripple that halves from one
  // waypoint to the next): the segments towards the ends stretch, the middle ones keep 10 m / 5 m/s
  o.v_mean = 5.0;
  const Trajectory fast({{0, 0, 0}, {1000, 0, 0}}, {5, 4}, o);
  EXPECT_GT(fast.report().stretched, 0u);
  EXPECT_LT(fast.report().stretched, 60u);
  EXPECT_NEAR(fast.polynomials()[50].duration, 2.0, 1e-12);
  EXPECT_GT(fast.duration(), 200.0);
  EXPECT_LT(fast.duration(), 215.0);  // 209.3 s (fillet-lines: 201.25 s)
  check_polynomial(fast, 0.01);
}

TEST(TrajectoryPolynomial, FixturePlansKeepTheLimits) {
  const Plan plan = fixture::two_uav_plan();
  for (std::size_t u = 0; u < plan.uavs.size(); ++u)
    for (const int order : {3, 5, 7}) {
      SCOPED_TRACE("uav " + std::to_string(u) + " order " + std::to_string(order));
      const Trajectory t = uav_trajectory(plan, u, polynomial(order));
      EXPECT_DOUBLE_EQ(t.limits().v_max, plan.mission.uavs[u].speed_mps);
      EXPECT_DOUBLE_EQ(t.report().v_min, -plan.mission.uavs[u].speed_mps);
      EXPECT_DOUBLE_EQ(t.report().a_min, -plan.mission.uavs[u].max_accel_mps2);
      check_polynomial(t, 0.01);
      EXPECT_EQ(t.waypoints(), uav_trajectory(plan, u).waypoints());  // the same densified waypoints
      const Measured m = measure(t, 0.01);
      EXPECT_NEAR(m.duration_s, t.duration(), 1e-12);
      EXPECT_LE(m.speed_max, t.report().speed_max + 1e-9);
    }
}

TEST(TrajectoryPolynomial, SameInputSameTrajectory) {
  const Plan plan = fixture::two_uav_plan();
  const auto a = uav_trajectory(plan, 0, polynomial()).sample(0.1);
  const auto b = uav_trajectory(plan, 0, polynomial()).sample(0.1);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].p, b[k].p);
    EXPECT_EQ(a[k].v, b[k].v);
  }
}

TEST(TrajectoryPolynomial, UnmeetableLimitsAreRefusedNamingTheField) {
  const std::vector<Vec3> w{{0, 0, 0}, {10, 0, 0}, {10, 10, 5}};
  auto field = [&](Options o, Limits lim = {5, 2}) {
    try {
      const Trajectory t(w, lim, o);
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string("(accepted)");
  };
  Options o = polynomial();
  o.v_min = 6;  // above v_max 5
  EXPECT_EQ(field(o), "v_min");
  o.v_min = 0;  // the flight could never come back along an axis
  EXPECT_EQ(field(o), "v_min");
  o = polynomial();
  o.a_min = 3;  // above a_max 2
  EXPECT_EQ(field(o), "a_min");
  o.a_min = 0;
  EXPECT_EQ(field(o), "a_min");
  o = polynomial();
  o.v_mean = 7;
  EXPECT_EQ(field(o), "v_mean");
  for (const int order : {1, 2, 4, 6, 9}) EXPECT_EQ(field(polynomial(order)), "order") << order;
  EXPECT_EQ(field(polynomial()), "(accepted)");
  // refused for a single waypoint too, and the fillet-lines method ignores the polynomial's options
  EXPECT_THROW(Trajectory({{1, 2, 3}}, {5, 2}, polynomial(4)), InputError);
  o.method = Method::FilletLines;
  EXPECT_EQ(field(o), "(accepted)");
  EXPECT_EQ(parse_method("polynomial"), Method::Polynomial);
  EXPECT_EQ(parse_method("fillet-lines"), Method::FilletLines);
  try {
    (void)parse_method("spline", "trajectory_method");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "trajectory_method");
  }
}

TEST(TrajectoryPolynomial, HasNoSegmentForm) {
  const Trajectory t({{0, 0, 0}, {10, 0, 0}}, {5, 2}, polynomial());
  EXPECT_THROW((void)t.segments(), std::logic_error);
  EXPECT_TRUE(t.pieces().empty());
  EXPECT_EQ(t.method(), Method::Polynomial);
}
