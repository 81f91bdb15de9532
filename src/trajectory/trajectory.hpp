// Time-parameterised flight trajectories (Mondinelli 2025 §4), by one of two methods (Method):
//
// Fillet-lines (the default): densify long legs, round corners with fillets (or stop at them), limit
// speed to v_max and to sqrt(a_max * r) on arcs, forward/backward speed pass. The path is a chain of
// straight lines and circular arcs in local ENU metres (x east, y north, z up). Tangential acceleration
// happens only on lines and centripetal acceleration only on arcs (constant speed there), so
// ||a|| <= a_max holds exactly; ||v|| <= v_max everywhere; start and end are at rest.
//
// Polynomial (the thesis's §4.1): through the densified waypoints, one polynomial of order P per axis
// and segment, continuous up to derivative P-1 at the waypoints, at rest at both ends, each segment's
// duration its length over a mean speed, stretched where a limit is broken (polynomial.cpp).
//
// Either is sampled (t, position, velocity, acceleration) at a fixed step.
#pragma once

#include <array>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "uavcover/plan.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::trajectory {

using Vec3 = std::array<double, 3>;

enum class CornerMode { Stop, Fillet };

/// How the waypoints become a trajectory (docs/trajectory.md).
enum class Method { FilletLines, Polynomial };

/// "fillet-lines", "polynomial".
const char* method_name(Method method);
/// The method of that name; InputError naming `field` otherwise.
Method parse_method(const std::string& name, const std::string& field = "method");

/// The polynomial orders (degrees) Method::Polynomial accepts: odd, so that the ends have as many
/// conditions as the waypoints' continuity leaves (3 cubic, 5 quintic, 7 septic).
inline constexpr int kMinOrder = 3, kMaxOrder = 7;

struct Options {
  double dt = 0.1;          ///< sampling step, seconds
  double densify_m = 10.0;  ///< legs longer than this get intermediate waypoints (0 = off)
  CornerMode corners = CornerMode::Fillet;
  double fillet_radius_m = 2.0;  ///< corner radius; shrunk where legs are too short
  double min_fillet_m = 0.05;    ///< below this radius the UAV stops at the corner instead
  Method method = Method::FilletLines;
  // Method::Polynomial only (the thesis's inputs P, v_mean, v_min, a_min; v_max and a_max are the UAV's):
  int order = 5;      ///< P, the degree of each segment's polynomial: 3, 5 or 7
  double v_mean = 0;  ///< m/s, each segment's mean speed before stretching; 0 = v_max
  /// m/s and m/s^2: the lower bounds of every velocity and acceleration component (the thesis's v_min,
  /// a_min); NaN = -v_max, -a_max. Negative: the flight returns home, so it flies every axis both ways.
  double v_min = std::numeric_limits<double>::quiet_NaN();
  double a_min = std::numeric_limits<double>::quiet_NaN();
};

struct Limits {
  double v_max = 5.0;  ///< m/s
  double a_max = 2.0;  ///< m/s^2
};

/// Throws InputError naming "order", "v_mean", "v_min" or "a_min" when Method::Polynomial's options
/// cannot be kept under `limits` (nothing for the fillet-lines method).
void check_options(const Options& options, const Limits& limits);

/// Method::Polynomial: one segment between consecutive (densified) waypoints, per axis k
/// p_k(t0 + s T) = sum_j c[k][j] s^j for s in [0, 1], T = duration.
struct PolySegment {
  double t0 = 0, duration = 0, length = 0;  ///< length: of the chord between its waypoints
  std::array<std::array<double, kMaxOrder + 1>, 3> c{};
};

/// Method::Polynomial: the bounds the trajectory keeps and its extremes (found per segment by sampling
/// and golden-section refinement), so whether the limits hold.
struct LimitReport {
  double v_min = 0, v_max = 0, a_min = 0, a_max = 0;  ///< bounds of each component (and |v|, |a| <= max)
  double v_lo = 0, v_hi = 0, a_lo = 0, a_hi = 0;      ///< smallest and largest component over x, y, z
  double speed_max = 0, accel_max = 0, jerk_max = 0;  ///< largest |v|, |a|, |da/dt|
  int iterations = 0;                                 ///< solves of the spline until the limits held
  std::size_t stretched = 0;                          ///< segments whose duration grew beyond length / v_mean
  bool hold = false;                                  ///< every bound holds (to 1e-9 relative)
};

struct Sample {
  double t = 0;
  Vec3 p{}, v{}, a{};
  int piece = 0;  ///< index of the path piece (line/arc) and phase; a changes only between pieces
};

/// One piece of the path: a straight line (with accelerate/cruise/decelerate phases) or an arc.
struct Piece {
  bool arc = false;
  double t0 = 0, duration = 0, length = 0;
  // line
  Vec3 start{}, dir{};
  double v_in = 0, v_peak = 0, v_out = 0, t_acc = 0, t_cruise = 0, t_dec = 0;
  // arc: p(th) = center - r*u*cos(th) + r*d1*sin(th), th in [0, angle]
  Vec3 center{}, u{}, d1{};
  double radius = 0, angle = 0, speed = 0;
};

/// The motion law of one segment of the segment form (docs/trajectory.md).
enum class SegmentKind { Accelerate, Cruise, Decelerate, Arc, End };

/// One breakpoint of the segment form: from `t` until the next breakpoint's time the UAV moves by the
/// law `kind` from the state (p, v, a) it has at `t`: on a line p(t + s) = p + v s + a s^2 / 2 (a is
/// +a_max, 0 or -a_max along the line); on an arc uniform circular motion, the centre at p + a |v|^2 /
/// |a|^2 (radius |v|^2 / |a|). The last breakpoint (End) is the end of the flight, at rest.
struct Segment {
  double t = 0;
  SegmentKind kind = SegmentKind::Cruise;
  Vec3 p{}, v{}, a{};
};

/// "accelerate", "cruise", "decelerate", "arc", "end".
const char* segment_kind_name(SegmentKind kind);

/// The state at time t (clamped to [segments.front().t, segments.back().t]) by the law of the
/// segment that holds t. Sample::piece is the segment's index.
Sample segment_at(const std::vector<Segment>& segments, double t);

/// Most samples one trajectory may have (about 55 hours at dt 0.1 s): sample() refuses more.
inline constexpr double kMaxSamples = 2'000'000;

class Trajectory {
 public:
  /// `waypoints` are visited in order (consecutive duplicates are dropped). Needs >= 1 waypoint.
  Trajectory(const std::vector<Vec3>& waypoints, const Limits& limits, const Options& options = {});

  [[nodiscard]] double duration() const { return duration_; }
  [[nodiscard]] Sample at(double t) const;
  /// Samples at 0, dt, 2dt, ... and at the end time (t strictly increasing). Throws InputError
  /// ("trajectory") when that would be more than kMaxSamples.
  [[nodiscard]] std::vector<Sample> sample(double dt) const;
  [[nodiscard]] std::vector<Sample> sample() const { return sample(options_.dt); }
  /// The waypoints after densification (the ones the trajectory passes by).
  [[nodiscard]] const std::vector<Vec3>& waypoints() const { return waypoints_; }
  /// Per waypoint: the radius actually used at that corner (0 = straight through or stop).
  [[nodiscard]] const std::vector<double>& corner_radii() const { return radii_; }
  [[nodiscard]] const std::vector<Piece>& pieces() const { return pieces_; }
  [[nodiscard]] const Limits& limits() const { return limits_; }
  [[nodiscard]] Method method() const { return options_.method; }
  /// Method::Polynomial: the segments (empty otherwise).
  [[nodiscard]] const std::vector<PolySegment>& polynomials() const { return poly_; }
  /// Method::Polynomial: the limits and whether they hold (default otherwise).
  [[nodiscard]] const LimitReport& report() const { return report_; }
  /// The segment form (Method::FilletLines only: a polynomial has no breakpoint form here; std::logic_error
  /// otherwise): one breakpoint wherever the motion law changes (the start of every
  /// acceleration, cruise and deceleration phase and of every fillet arc) and one at the end. Phases
  /// that continue one law across a straight-through (densified) waypoint are one segment, so the
  /// count follows the turns, not the length or a sampling step. segment_at() gives at() again, to
  /// within 1e-9 m and 1e-9 m/s.
  [[nodiscard]] std::vector<Segment> segments() const;

 private:
  Limits limits_;
  Options options_;
  std::vector<Vec3> waypoints_;
  std::vector<double> radii_;
  std::vector<Piece> pieces_;
  std::vector<PolySegment> poly_;
  LimitReport report_;
  double duration_ = 0;
};

/// Extremes of a trajectory measured on its samples every `dt` (any method; the comparison of the
/// methods in docs/trajectory.md): jerk by finite differences of the acceleration, so a jump of the
/// acceleration (the fillet-lines' phase changes) shows as jump / dt.
struct Measured {
  double duration_s = 0, length_m = 0, speed_max = 0, accel_max = 0, jerk_max = 0;
};
Measured measure(const Trajectory& trajectory, double dt = 0.01);

/// 3D flight waypoints of UAV `index` in local metres: home on the ground, then every positioned
/// mission item (take-off, transition, transit, coverage) in order, then home and the ground again.
std::vector<Vec3> flight_waypoints(const Plan& plan, std::size_t index,
                                   const waypoints::AltitudeOptions& altitudes = {});

/// The trajectory of UAV `index` under its own speed_mps and max_accel_mps2.
Trajectory uav_trajectory(const Plan& plan, std::size_t index, const Options& options = {},
                          const waypoints::AltitudeOptions& altitudes = {});

/// Flight time (s) of UAV `index` along its trajectory: an alternative to the eq. 15 time model.
double flight_time_s(const Plan& plan, std::size_t index, const Options& options = {},
                     const waypoints::AltitudeOptions& altitudes = {});

/// CSV with header `t,x,y,z,lat,lon,vx,vy,vz,ax,ay,az`, positions in the plan's local frame.
std::string trajectory_csv(const Plan& plan, const std::vector<Sample>& samples);

/// The header of segments_csv().
inline constexpr const char* kSegmentsHeader = "t,kind,x,y,z,lat,lon,vx,vy,vz,ax,ay,az,v_max,a_max";

/// The segment form as CSV (docs/trajectory.md): header kSegmentsHeader, one row per breakpoint,
/// positions in the plan's local frame (ENU metres from plan.origin), every number but lat/lon in its
/// shortest exact decimal form (it reads back to the same double), v_max and a_max the UAV's limits.
std::string segments_csv(const Plan& plan, const Trajectory& trajectory);

/// Reads segments_csv() back (lat, lon and the limits are not needed to recover the motion). Throws
/// InputError naming "trajectory" on a malformed text.
std::vector<Segment> parse_segments_csv(const std::string& csv);

}  // namespace uavcover::trajectory
