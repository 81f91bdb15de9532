// Every sample of every trajectory is checked: speed and acceleration limits, strictly increasing
// time, rest at both ends, waypoints reached, deviation within the fillet bound, and p/v/a
// consistent by finite differences.
#include "trajectory/trajectory.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "export/fixture.hpp"
#include "trajectory/polylines.hpp"
#include "uavcover/error.hpp"

using namespace uavcover;
using namespace uavcover::trajectory;

namespace {

double norm(const Vec3& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }
Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dist(const Vec3& a, const Vec3& b) { return norm(sub(a, b)); }

double dist_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = sub(b, a), ap = sub(p, a);
  const double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
  double t = l2 > 0 ? (ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / l2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return dist(p, {a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]});
}

/// Interior angle half-width alpha at waypoint i: pi/2 - turning angle / 2.
double half_interior(const std::vector<Vec3>& w, std::size_t i) {
  const Vec3 a = sub(w[i], w[i - 1]), b = sub(w[i + 1], w[i]);
  const double c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (norm(a) * norm(b));
  const double phi = std::acos(std::clamp(c, -1.0, 1.0));
  return (std::numbers::pi - phi) / 2.0;
}

/// Checks every property the issue lists on the samples of `traj` (sampled at dt).
void check_all(const Trajectory& traj, double dt, double nominal_radius) {
  const auto s = traj.sample(dt);
  const auto& w = traj.waypoints();
  const double vmax = traj.limits().v_max, amax = traj.limits().a_max;
  ASSERT_GE(s.size(), 2u);
  const auto& radii = traj.corner_radii();
  ASSERT_EQ(radii.size(), w.size());
  double dev_bound = 1e-6;
  for (std::size_t i = 1; i + 1 < w.size(); ++i) {
    EXPECT_LE(radii[i], nominal_radius + 1e-12);
    if (radii[i] > 0)
      dev_bound = std::max(dev_bound, radii[i] * (1.0 - std::sin(half_interior(w, i))) + 1e-6);
  }
  // rest at both ends, at the first and last waypoints
  EXPECT_DOUBLE_EQ(s.front().t, 0.0);
  EXPECT_LE(norm(s.front().v), 1e-12);
  EXPECT_LE(norm(s.back().v), 1e-12);
  EXPECT_NEAR(s.back().t, traj.duration(), 1e-12);
  EXPECT_LE(norm(traj.at(traj.duration()).v), 1e-9);
  EXPECT_LE(dist(s.front().p, w.front()), 1e-9);
  EXPECT_LE(dist(s.back().p, w.back()), 1e-6);
  for (std::size_t k = 0; k < s.size(); ++k) {
    EXPECT_LE(norm(s[k].v), vmax * (1 + 1e-9)) << "t=" << s[k].t;
    EXPECT_LE(norm(s[k].a), amax * (1 + 1e-9)) << "t=" << s[k].t;
    // deviation from the polyline
    double d = 1e300;
    for (std::size_t i = 0; i + 1 < w.size(); ++i) d = std::min(d, dist_to_segment(s[k].p, w[i], w[i + 1]));
    EXPECT_LE(d, dev_bound) << "t=" << s[k].t;
    if (k == 0) continue;
    const double h = s[k].t - s[k - 1].t;
    ASSERT_GT(h, 0.0) << "t not strictly increasing at sample " << k;
    // mean-value bounds between samples: no jumps in position or velocity
    EXPECT_LE(dist(s[k].p, s[k - 1].p) / h, vmax * (1 + 1e-9) + 1e-9);
    EXPECT_LE(dist(s[k].v, s[k - 1].v) / h, amax * (1 + 1e-9) + 1e-9);
    // within one piece with constant acceleration, the trapezoid rule is exact for p
    if (s[k].piece == s[k - 1].piece && s[k].piece % 4 != 3) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR((s[k].p[c] - s[k - 1].p[c]) / h, (s[k].v[c] + s[k - 1].v[c]) / 2, 1e-7);
        EXPECT_NEAR((s[k].v[c] - s[k - 1].v[c]) / h, s[k].a[c], 1e-7);
      }
    }
  }
  // central differences at every sample (step 1e-5 s), where both sides are in the same piece
  const double e = 1e-5;
  for (const auto& x : s) {
    if (x.t - e < 0 || x.t + e > traj.duration()) continue;
    const Sample lo = traj.at(x.t - e), hi = traj.at(x.t + e);
    if (lo.piece != x.piece || hi.piece != x.piece) continue;
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR((hi.p[c] - lo.p[c]) / (2 * e), x.v[c], 1e-6) << "t=" << x.t;
      EXPECT_NEAR((hi.v[c] - lo.v[c]) / (2 * e), x.a[c], 1e-5) << "t=" << x.t;
    }
  }
  // every waypoint reached: within the corner offset of its fillet plus half a sampling step
  for (std::size_t i = 0; i < w.size(); ++i) {
    double tol = vmax * dt / 2 + 1e-6;
    if (i > 0 && i + 1 < w.size() && radii[i] > 0)
      tol += radii[i] * (1.0 / std::sin(half_interior(w, i)) - 1.0);
    double best = 1e300;
    for (const auto& x : s) best = std::min(best, dist(x.p, w[i]));
    EXPECT_LE(best, tol) << "waypoint " << i;
  }
  // arcs respect sqrt(a_max r); the duration is at least length / v_max
  double length = 0;
  for (const auto& pc : traj.pieces()) {
    length += pc.length;
    if (pc.arc) {
      EXPECT_LE(pc.speed, std::sqrt(amax * pc.radius) * (1 + 1e-12));
    }
  }
  EXPECT_GE(traj.duration(), length / vmax * (1 - 1e-12));
}

const std::vector<Vec3> kSquare{{0, 0, 0}, {50, 0, 0}, {50, 50, 0}, {0, 50, 0}, {0, 0, 0}};

}  // namespace

TEST(Trajectory, FilletedSquare) {
  Options opt;
  opt.fillet_radius_m = 4.0;
  const Trajectory t(kSquare, {5.0, 2.0}, opt);
  check_all(t, 0.1, 4.0);
  // fillets: 3 corners of the 4 (the last vertex is the end), all with the full radius
  int arcs = 0;
  for (const auto& p : t.pieces()) arcs += p.arc ? 1 : 0;
  EXPECT_EQ(arcs, 3);
  // faster than stopping at every corner
  Options stop = opt;
  stop.corners = CornerMode::Stop;
  const Trajectory ts(kSquare, {5.0, 2.0}, stop);
  check_all(ts, 0.1, 0.0);
  EXPECT_LT(t.duration(), ts.duration());
}

TEST(Trajectory, StopAtCornersTimeIsAnalytic) {
  // one 100 m leg, v 5, a 2: accelerate 2.5 s (6.25 m), cruise 87.5 m (17.5 s), decelerate 2.5 s
  Options opt;
  opt.corners = CornerMode::Stop;
  opt.densify_m = 0;
  const Trajectory t({{0, 0, 0}, {100, 0, 0}}, {5.0, 2.0}, opt);
  EXPECT_NEAR(t.duration(), 22.5, 1e-12);
  check_all(t, 0.05, 0.0);
  // a leg too short to reach v_max: triangular profile, 2 * sqrt(L / a)
  const Trajectory tri({{0, 0, 0}, {4, 0, 0}}, {5.0, 2.0}, opt);
  EXPECT_NEAR(tri.duration(), 2 * std::sqrt(4.0 / 2.0), 1e-12);
  check_all(tri, 0.05, 0.0);
}

TEST(Trajectory, DensifiesLongLegs) {
  Options opt;
  opt.densify_m = 10;
  const Trajectory t({{0, 0, 0}, {95, 0, 0}, {95, 30, 10}}, {5.0, 2.0}, opt);
  // 95 m -> 10 pieces, 31.6 m -> 4 pieces
  EXPECT_EQ(t.waypoints().size(), 1u + 10u + 4u);
  for (std::size_t i = 1; i < t.waypoints().size(); ++i)
    EXPECT_LE(dist(t.waypoints()[i], t.waypoints()[i - 1]), 10.0 + 1e-9);
  check_all(t, 0.1, opt.fillet_radius_m);
  // densification does not slow the flight down on a straight line
  Options no = opt;
  no.densify_m = 0;
  const Trajectory line({{0, 0, 0}, {95, 0, 0}}, {5.0, 2.0}, no);
  const Trajectory dense({{0, 0, 0}, {95, 0, 0}}, {5.0, 2.0}, opt);
  EXPECT_NEAR(line.duration(), dense.duration(), 1e-9);
}

TEST(Trajectory, ShortLegsShrinkTheFilletAndUTurnsStop) {
  Options opt;
  opt.fillet_radius_m = 5.0;
  // zig-zag with 2 m legs (fillets must shrink), then a 180 degree reversal (must stop)
  const std::vector<Vec3> w{{0, 0, 0}, {20, 0, 0}, {20, 2, 0}, {0, 2, 0},
                            {0, 4, 0}, {20, 4, 0}, {5, 4, 0},  {5, 4, 3}};
  const Trajectory t(w, {6.0, 2.5}, opt);
  check_all(t, 0.05, 5.0);
  const auto& r = t.corner_radii();
  const auto& wp = t.waypoints();
  std::size_t c = 0;
  while (dist(wp[c], {20, 0, 0}) > 1e-9) ++c;
  EXPECT_GT(r[c], 0.0);
  EXPECT_LT(r[c], 1.0 + 1e-12);  // shrunk: the tangent length fits half of the 2 m leg
  // the reversal at (20,4) -> (5,4): no fillet, the UAV stops there
  for (std::size_t i = 0; i < wp.size(); ++i)
    if (dist(wp[i], {20, 4, 0}) < 1e-9) {
      EXPECT_EQ(r[i], 0.0);
    }
  double best = 1e300;
  for (double tt = 0; tt <= t.duration(); tt += 0.001) {
    const auto s = t.at(tt);
    if (dist(s.p, {20, 4, 0}) < 1e-6) best = std::min(best, norm(s.v));
  }
  EXPECT_LT(best, 1e-2);
}

TEST(Trajectory, DegenerateInputs) {
  const Trajectory one({{1, 2, 3}}, {5, 2});
  EXPECT_EQ(one.duration(), 0.0);
  const auto s = one.sample(0.1);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].p[2], 3.0);
  const Trajectory dup({{0, 0, 0}, {0, 0, 0}, {10, 0, 0}, {10, 0, 0}}, {5, 2});
  EXPECT_EQ(dup.waypoints().size(), 2u);
  check_all(dup, 0.1, 2.0);
  EXPECT_THROW(Trajectory({}, {5, 2}), std::invalid_argument);
  EXPECT_THROW(Trajectory({{0, 0, 0}, {1, 0, 0}}, {0, 2}), std::invalid_argument);
  EXPECT_THROW((void)dup.sample(0), std::invalid_argument);
}

TEST(Trajectory, PlanTrajectoriesWithTransitionAltitudes) {
  const Plan plan = fixture::two_uav_plan();
  for (std::size_t u = 0; u < 2; ++u) {
    const Trajectory t = uav_trajectory(plan, u);
    EXPECT_DOUBLE_EQ(t.limits().v_max, plan.mission.uavs[u].speed_mps);
    EXPECT_DOUBLE_EQ(t.limits().a_max, plan.mission.uavs[u].max_accel_mps2);
    check_all(t, 0.1, Options{}.fillet_radius_m);
    // starts and ends on the ground at home, climbs to the transition altitude, covers at 40 m
    const auto w = flight_waypoints(plan, u);
    EXPECT_EQ(w.front()[2], 0.0);
    EXPECT_EQ(w.back()[2], 0.0);
    double zmax = 0;
    for (const auto& p : w) zmax = std::max(zmax, p[2]);
    EXPECT_DOUBLE_EQ(zmax, waypoints::transition_altitude({}, u, plan.mission.altitude_m));
    EXPECT_DOUBLE_EQ(flight_time_s(plan, u), t.duration());
    // the flight takes longer than flying the 3D waypoint polyline at v_max
    double len = 0;
    for (std::size_t i = 1; i < w.size(); ++i) len += dist(w[i], w[i - 1]);
    EXPECT_GT(t.duration(), len / plan.mission.uavs[u].speed_mps);
  }
}

TEST(Trajectory, CsvHasTheExactHeaderAndOneRowPerSample) {
  const Plan plan = fixture::two_uav_plan();
  const Trajectory t = uav_trajectory(plan, 0);
  const auto samples = t.sample(0.5);
  const std::string csv = trajectory_csv(plan, samples);
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "t,x,y,z,lat,lon,vx,vy,vz,ax,ay,az");
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), samples.size() + 1);
  // the first row is home on the ground, at rest
  const std::string row1 =
      csv.substr(csv.find('\n') + 1, csv.find('\n', csv.find('\n') + 1) - csv.find('\n') - 1);
  std::vector<double> f;
  std::size_t pos = 0;
  while (pos <= row1.size()) {
    const std::size_t c = std::min(row1.find(',', pos), row1.size());
    f.push_back(std::stod(row1.substr(pos, c - pos)));
    pos = c + 1;
  }
  ASSERT_EQ(f.size(), 12u);
  EXPECT_NEAR(f[4], plan.mission.uavs[0].start_resolved.lat, 1e-8);
  EXPECT_NEAR(f[5], plan.mission.uavs[0].start_resolved.lon, 1e-8);
  EXPECT_EQ(f[3], 0.0);
  EXPECT_EQ(f[6], 0.0);
}

TEST(Trajectory, RandomPolylinesKeepEveryProperty) {
  // seeded random 3D polylines: short and long legs, acute turns, reversals, both corner modes
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> speed(1, 12), accel(0.5, 5), radius(0, 6);
  for (int trial = 0; trial < 40; ++trial) {
    const auto w = polylines::random_polyline(rng, trial);
    Options opt;
    opt.corners = trial % 4 == 3 ? CornerMode::Stop : CornerMode::Fillet;
    opt.fillet_radius_m = radius(rng);
    opt.densify_m = trial % 2 == 0 ? 10.0 : 0.0;
    const Trajectory t(w, {speed(rng), accel(rng)}, opt);
    SCOPED_TRACE("trial " + std::to_string(trial));
    check_all(t, 0.05, opt.corners == CornerMode::Stop ? 0.0 : opt.fillet_radius_m);
  }
}

TEST(Trajectory, SampleCountIsBounded) {
  // 2000 km at 1 m/s: 2e6 s, 2e7 samples at 0.1 s; refused before anything is allocated
  const Trajectory t({{0, 0, 0}, {2e6, 0, 0}}, Limits{1.0, 2.0});
  EXPECT_THROW((void)t.sample(0.1), uavcover::InputError);
  EXPECT_NO_THROW((void)t.sample(2000.0));
}

namespace {

/// The segment form gives at() again at many instants: in every piece, at its ends and between.
double worst_recovery(const Trajectory& t, const std::vector<Segment>& g, double* worst_v = nullptr) {
  std::vector<double> times;
  for (const auto& pc : t.pieces())
    for (int k = 0; k <= 16; ++k) times.push_back(pc.t0 + pc.duration * k / 16.0);
  for (int k = 0; k <= 5000; ++k) times.push_back(t.duration() * k / 5000.0);
  double wp = 0, wv = 0;
  for (const double x : times) {
    const Sample a = t.at(x), b = segment_at(g, x);
    wp = std::max(wp, dist(a.p, b.p));
    wv = std::max(wv, dist(a.v, b.v));
    // the acceleration is the same law's (it jumps only at breakpoints, where either side is right;
    // the end breakpoint is at rest)
    if (x < t.duration() && dist(a.a, b.a) > 1e-6) {
      const Sample lo = t.at(x - 1e-7), hi = t.at(x + 1e-7);
      EXPECT_TRUE(dist(lo.a, b.a) < 1e-6 || dist(hi.a, b.a) < 1e-6) << "t=" << x;
    }
  }
  if (worst_v) *worst_v = wv;
  return wp;
}

}  // namespace

TEST(TrajectorySegments, RecoverTheTrajectoryAtEveryInstant) {
  std::mt19937_64 rng(20261201);
  std::uniform_real_distribution<double> coord(-30, 30), len(0.05, 1.0), speed(1, 12), accel(0.5, 5),
      radius(0, 6);
  for (int trial = 0; trial < 60; ++trial) {
    std::vector<Vec3> w{{0, 0, 0}};
    const int n = 2 + trial % 9;
    for (int i = 0; i < n; ++i) {
      const double f = trial % 3 == 0 ? len(rng) : trial % 5 == 0 ? 40.0 : 1.0;
      w.push_back({w.back()[0] + f * coord(rng), w.back()[1] + f * coord(rng),
                   std::max(0.0, w.back()[2] + f * coord(rng) / 3)});
    }
    Options opt;
    opt.corners = trial % 4 == 3 ? CornerMode::Stop : CornerMode::Fillet;
    opt.fillet_radius_m = radius(rng);
    opt.densify_m = trial % 2 == 0 ? 10.0 : 0.0;
    const Trajectory t(w, {speed(rng), accel(rng)}, opt);
    SCOPED_TRACE("trial " + std::to_string(trial));
    const auto g = t.segments();
    ASSERT_GE(g.size(), 1u);
    EXPECT_EQ(g.back().kind, SegmentKind::End);
    EXPECT_EQ(g.front().t, 0.0);
    EXPECT_EQ(g.back().t, t.duration());
    for (std::size_t k = 1; k < g.size(); ++k) EXPECT_GT(g[k].t, g[k - 1].t);
    double wv = 0;
    EXPECT_LE(worst_recovery(t, g, &wv), 1e-9);
    EXPECT_LE(wv, 1e-9);
    // never more breakpoints than phases: at most three per line piece and one per arc, plus the end
    std::size_t phases = 1;
    for (const auto& pc : t.pieces()) phases += pc.arc ? 1 : 3;
    EXPECT_LE(g.size(), phases);
  }
}

TEST(TrajectorySegments, ADensifiedLegIsOneAccelerationCruiseAndDeceleration) {
  // 2 km straight at 5 m/s, 2 m/s^2, densified every 10 m: 200 pieces, four breakpoints
  const Trajectory t({{0, 0, 0}, {2000, 0, 0}}, Limits{5.0, 2.0});
  EXPECT_EQ(t.pieces().size(), 200u);
  const auto g = t.segments();
  ASSERT_EQ(g.size(), 4u);
  EXPECT_EQ(g[0].kind, SegmentKind::Accelerate);
  EXPECT_EQ(g[1].kind, SegmentKind::Cruise);
  EXPECT_EQ(g[2].kind, SegmentKind::Decelerate);
  EXPECT_EQ(g[3].kind, SegmentKind::End);
  EXPECT_NEAR(g[1].t, 2.5, 1e-12);  // v_max / a_max
  EXPECT_NEAR(g[1].p[0], 6.25, 1e-9);
  EXPECT_NEAR(g[3].t, 2000.0 / 5.0 + 2.5, 1e-9);
  EXPECT_LE(worst_recovery(t, g), 1e-9);
}

TEST(TrajectorySegments, CsvReadsBackToTheSameDoubles) {
  const Plan plan = fixture::two_uav_plan();
  for (std::size_t u = 0; u < 2; ++u) {
    const Trajectory t = uav_trajectory(plan, u);
    const std::string csv = segments_csv(plan, t);
    EXPECT_EQ(csv.substr(0, csv.find('\n')), kSegmentsHeader);
    const auto g = t.segments();
    const auto back = parse_segments_csv(csv);
    ASSERT_EQ(back.size(), g.size());
    for (std::size_t k = 0; k < g.size(); ++k) {
      EXPECT_EQ(back[k].t, g[k].t);
      EXPECT_EQ(back[k].kind, g[k].kind);
      EXPECT_EQ(back[k].p, g[k].p);
      EXPECT_EQ(back[k].v, g[k].v);
      EXPECT_EQ(back[k].a, g[k].a);
    }
    // an arc for each filleted corner, and the flight recovered from the file alone
    EXPECT_GT(std::count_if(g.begin(), g.end(), [](const Segment& s) { return s.kind == SegmentKind::Arc; }),
              0);
    EXPECT_LE(worst_recovery(t, back), 1e-9);
    // the limits are the UAV's
    const std::string row =
        csv.substr(csv.find('\n') + 1, csv.find('\n', csv.find('\n') + 1) - csv.find('\n') - 1);
    EXPECT_TRUE(row.ends_with(
        fmt::format(",{},{}", plan.mission.uavs[u].speed_mps, plan.mission.uavs[u].max_accel_mps2)))
        << row;
  }
}

TEST(TrajectorySegments, MalformedCsvIsRefusedNamingTheLine) {
  const Plan plan = fixture::two_uav_plan();
  const std::string csv = segments_csv(plan, uav_trajectory(plan, 0));
  auto refused = [](const std::string& text, const std::string& what) {
    try {
      (void)parse_segments_csv(text);
      ADD_FAILURE() << "accepted: " << what;
    } catch (const uavcover::InputError& e) {
      EXPECT_EQ(e.field(), "trajectory");
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  refused("t,x\n", "line 1");
  refused(std::string(kSegmentsHeader) + "\n", "no segments");
  refused(std::string(kSegmentsHeader) + "\n0,cruise,1,2\n", "line 2: expected 15 fields");
  refused(std::string(kSegmentsHeader) + "\n0,hover,0,0,0,0,0,0,0,0,0,0,0,5,2\n", "unknown kind");
  refused(std::string(kSegmentsHeader) + "\n0,cruise,x,0,0,0,0,0,0,0,0,0,0,5,2\n", "field 3");
  refused(std::string(kSegmentsHeader) +
              "\n1,cruise,0,0,0,0,0,0,0,0,0,0,0,5,2\n0,end,0,0,0,0,0,0,0,0,0,0,0,5,2\n",
          "line 3: times must not decrease");
  EXPECT_NO_THROW((void)parse_segments_csv(csv));
}
