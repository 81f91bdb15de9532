#include "trajectory/trajectory.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string_view>

#include "geodesy/local_frame.hpp"
#include "terrain/terrain.hpp"
#include "trajectory/polynomial.hpp"
#include "trajectory/vec3.hpp"
#include "uavcover/error.hpp"

namespace uavcover::trajectory {

namespace {

using detail::add;
using detail::cross;
using detail::dot;
using detail::norm;
using detail::scale;
using detail::sub;
using detail::unit;

constexpr double kStraightAngle = 1e-6;  // radians: below this a vertex is passed straight through

}  // namespace

Trajectory::Trajectory(const std::vector<Vec3>& waypoints, const Limits& limits, const Options& options)
    : limits_(limits), options_(options) {
  if (waypoints.empty()) throw std::invalid_argument("trajectory: no waypoints");
  if (!(limits.v_max > 0) || !(limits.a_max > 0))
    throw std::invalid_argument("trajectory: v_max and a_max must be positive");
  const bool polynomial = options_.method == Method::Polynomial;
  if (polynomial) report_ = detail::polynomial_bounds(limits_, options_);  // refused even for one waypoint
  // 1. drop consecutive duplicates, densify long legs
  std::vector<Vec3> pts;
  for (const auto& w : waypoints)
    if (pts.empty() || norm(sub(w, pts.back())) > 1e-9) pts.push_back(w);
  waypoints_.push_back(pts.front());
  for (std::size_t i = 1; i < pts.size(); ++i) {
    const Vec3 d = sub(pts[i], pts[i - 1]);
    const double len = norm(d);
    if (options_.densify_m > 0 && len > options_.densify_m) {
      const int n = static_cast<int>(std::ceil(len / options_.densify_m));
      for (int k = 1; k < n; ++k) waypoints_.push_back(add(pts[i - 1], scale(d, static_cast<double>(k) / n)));
    }
    waypoints_.push_back(pts[i]);
  }
  const std::size_t n = waypoints_.size();
  radii_.assign(n, 0.0);
  if (n == 1) {
    report_.hold = true;
    return;
  }
  if (polynomial) {
    auto built = detail::polynomial(waypoints_, limits_, options_);
    poly_ = std::move(built.segments);
    report_ = built.report;
    duration_ = poly_.back().t0 + poly_.back().duration;
    return;
  }

  // 2. corners: tangent length, radius, speed cap per vertex
  std::vector<double> leg(n - 1);
  std::vector<Vec3> dir(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Vec3 d = sub(waypoints_[i + 1], waypoints_[i]);
    leg[i] = norm(d);
    dir[i] = scale(d, 1.0 / leg[i]);
  }
  std::vector<double> tangent(n, 0.0), cap(n, 0.0), angle(n, 0.0);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const Vec3& din = dir[i - 1];
    const Vec3& dout = dir[i];
    const double phi = std::atan2(norm(cross(din, dout)), dot(din, dout));
    angle[i] = phi;
    if (phi < kStraightAngle) {
      cap[i] = limits_.v_max;
      continue;
    }
    if (options_.corners == CornerMode::Stop) continue;
    const double th = std::tan(phi / 2.0);
    double r = options_.fillet_radius_m;
    const double avail = std::min(leg[i - 1], leg[i]) / 2.0;
    if (r * th > avail) r = avail / th;
    if (!(r >= options_.min_fillet_m) || !std::isfinite(r)) continue;  // stop at this corner
    radii_[i] = r;
    tangent[i] = r * th;
    cap[i] = std::min(limits_.v_max, std::sqrt(limits_.a_max * r));
  }

  // 3. line lengths between tangent points; forward/backward pass over node speeds
  std::vector<double> line(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) line[i] = std::max(0.0, leg[i] - tangent[i] - tangent[i + 1]);
  const double a = limits_.a_max;
  std::vector<double> u(n, 0.0);
  cap[0] = cap[n - 1] = 0.0;
  for (std::size_t i = 1; i < n; ++i)
    u[i] = std::min(cap[i], std::sqrt(u[i - 1] * u[i - 1] + 2 * a * line[i - 1]));
  u[n - 1] = 0.0;
  for (std::size_t i = n - 1; i-- > 0;)
    u[i] = std::min(u[i], std::sqrt(u[i + 1] * u[i + 1] + 2 * a * line[i]));

  // 4. pieces
  double t = 0;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    Piece ln;
    ln.arc = false;
    ln.t0 = t;
    ln.start = add(waypoints_[i], scale(dir[i], tangent[i]));
    ln.dir = dir[i];
    ln.length = line[i];
    ln.v_in = u[i];
    ln.v_out = u[i + 1];
    if (ln.length > 0) {
      double vp = std::sqrt((ln.v_in * ln.v_in + ln.v_out * ln.v_out + 2 * a * ln.length) / 2.0);
      vp = std::max({std::min(vp, limits_.v_max), ln.v_in, ln.v_out});
      ln.v_peak = vp;
      const double d_acc = (vp * vp - ln.v_in * ln.v_in) / (2 * a);
      const double d_dec = (vp * vp - ln.v_out * ln.v_out) / (2 * a);
      const double d_cruise = std::max(0.0, ln.length - d_acc - d_dec);
      ln.t_acc = (vp - ln.v_in) / a;
      ln.t_dec = (vp - ln.v_out) / a;
      ln.t_cruise = vp > 0 ? d_cruise / vp : 0.0;
      ln.duration = ln.t_acc + ln.t_cruise + ln.t_dec;
      t += ln.duration;
      pieces_.push_back(ln);
    }
    const std::size_t c = i + 1;
    if (c + 1 < n && radii_[c] > 0) {
      Piece arc;
      arc.arc = true;
      arc.t0 = t;
      arc.radius = radii_[c];
      arc.angle = angle[c];
      arc.d1 = dir[i];
      arc.u = unit(sub(dir[c], scale(dir[i], dot(dir[c], dir[i]))));
      const Vec3 t1 = sub(waypoints_[c], scale(dir[i], tangent[c]));
      arc.center = add(t1, scale(arc.u, arc.radius));
      arc.speed = u[c];
      arc.length = arc.radius * arc.angle;
      if (!(arc.speed > 0)) throw std::logic_error("trajectory: zero speed on a fillet");
      arc.duration = arc.length / arc.speed;
      t += arc.duration;
      pieces_.push_back(arc);
    }
  }
  duration_ = t;
}

Sample Trajectory::at(double t) const {
  if (!poly_.empty()) return detail::polynomial_at(poly_, options_.order, t);
  Sample s;
  if (pieces_.empty()) {
    s.t = 0;
    s.p = waypoints_.front();
    return s;
  }
  t = std::clamp(t, 0.0, duration_);
  s.t = t;
  auto it =
      std::upper_bound(pieces_.begin(), pieces_.end(), t, [](double x, const Piece& p) { return x < p.t0; });
  const std::size_t k = it == pieces_.begin() ? 0 : static_cast<std::size_t>(it - pieces_.begin()) - 1;
  const Piece& pc = pieces_[k];
  const double tau = std::clamp(t - pc.t0, 0.0, pc.duration);
  const double a = limits_.a_max;
  if (pc.arc) {
    const double th = pc.speed * tau / pc.radius;
    const double c = std::cos(th), sn = std::sin(th);
    s.p = add(pc.center, add(scale(pc.u, -pc.radius * c), scale(pc.d1, pc.radius * sn)));
    s.v = add(scale(pc.u, pc.speed * sn), scale(pc.d1, pc.speed * c));
    const double ac = pc.speed * pc.speed / pc.radius;
    s.a = add(scale(pc.u, ac * c), scale(pc.d1, -ac * sn));
    s.piece = static_cast<int>(4 * k + 3);
    return s;
  }
  double dist = 0, v = 0, acc = 0;
  int phase = 0;
  const double d_acc = pc.v_in * pc.t_acc + 0.5 * a * pc.t_acc * pc.t_acc;
  if (tau < pc.t_acc) {
    dist = pc.v_in * tau + 0.5 * a * tau * tau;
    v = pc.v_in + a * tau;
    acc = a;
  } else if (tau < pc.t_acc + pc.t_cruise) {
    dist = d_acc + pc.v_peak * (tau - pc.t_acc);
    v = pc.v_peak;
    phase = 1;
  } else {
    const double t3 = std::min(tau - pc.t_acc - pc.t_cruise, pc.t_dec);
    dist = d_acc + pc.v_peak * pc.t_cruise + pc.v_peak * t3 - 0.5 * a * t3 * t3;
    v = std::max(0.0, pc.v_peak - a * t3);
    acc = pc.t_dec > 0 ? -a : 0.0;
    phase = 2;
  }
  s.p = add(pc.start, scale(pc.dir, dist));
  s.v = scale(pc.dir, v);
  s.a = scale(pc.dir, acc);
  s.piece = static_cast<int>(4 * k) + phase;
  return s;
}

const char* segment_kind_name(SegmentKind kind) {
  switch (kind) {
    case SegmentKind::Accelerate:
      return "accelerate";
    case SegmentKind::Cruise:
      return "cruise";
    case SegmentKind::Decelerate:
      return "decelerate";
    case SegmentKind::Arc:
      return "arc";
    case SegmentKind::End:
      return "end";
  }
  return "?";
}

std::vector<Segment> Trajectory::segments() const {
  if (options_.method != Method::FilletLines)
    throw std::logic_error("trajectory: the segment form is the fillet-lines method's; sample a polynomial");
  std::vector<Segment> out;
  // a phase that continues the law of the segment before it (the same kind and acceleration, and that
  // law's state at its start) is not a new breakpoint: densified legs and long cruises stay one row
  // (a 5 km cruise predicted from its first 10 m piece is off by about 1e-10 m: rounding of the directions)
  constexpr double kSameP = 5e-10, kSameV = 1e-12;
  auto continues = [&](const Segment& c) {
    if (out.empty()) return false;
    const Segment& r = out.back();
    if (r.kind != c.kind || c.kind == SegmentKind::Arc || norm(sub(r.a, c.a)) > kSameV) return false;
    const double s = c.t - r.t;
    const Vec3 p = add(add(r.p, scale(r.v, s)), scale(r.a, 0.5 * s * s));
    const Vec3 v = add(r.v, scale(r.a, s));
    return norm(sub(p, c.p)) <= kSameP && norm(sub(v, c.v)) <= kSameV;
  };
  auto push = [&](Segment c) {
    // a phase too short to move the clock has no instant of its own: the next one starts then
    while (!out.empty() && out.back().t >= c.t) out.pop_back();
    if (!continues(c)) out.push_back(c);
  };
  const double a = limits_.a_max;
  for (const Piece& pc : pieces_) {
    if (pc.arc) {
      const double ac = pc.speed * pc.speed / pc.radius;
      push({pc.t0, SegmentKind::Arc, sub(pc.center, scale(pc.u, pc.radius)), scale(pc.d1, pc.speed),
            scale(pc.u, ac)});
      continue;
    }
    // the same phase starts as at(): accelerate, cruise, decelerate (phases of no duration have none)
    const double d_acc = pc.v_in * pc.t_acc + 0.5 * a * pc.t_acc * pc.t_acc;
    if (pc.t_acc > 0)
      push({pc.t0, SegmentKind::Accelerate, pc.start, scale(pc.dir, pc.v_in), scale(pc.dir, a)});
    if (pc.t_cruise > 0)
      push({pc.t0 + pc.t_acc, SegmentKind::Cruise, add(pc.start, scale(pc.dir, d_acc)),
            scale(pc.dir, pc.v_peak), Vec3{0, 0, 0}});
    if (pc.t_dec > 0)
      push({pc.t0 + pc.t_acc + pc.t_cruise, SegmentKind::Decelerate,
            add(pc.start, scale(pc.dir, d_acc + pc.v_peak * pc.t_cruise)), scale(pc.dir, pc.v_peak),
            scale(pc.dir, -a)});
  }
  const Segment end{duration_, SegmentKind::End, at(duration_).p, Vec3{0, 0, 0}, Vec3{0, 0, 0}};
  while (out.size() > 0 && out.back().t >= end.t && duration_ > 0) out.pop_back();
  out.push_back(end);
  return out;
}

Sample segment_at(const std::vector<Segment>& segments, double t) {
  if (segments.empty()) throw std::invalid_argument("trajectory: no segments");
  t = std::clamp(t, segments.front().t, segments.back().t);
  auto it = std::upper_bound(segments.begin(), segments.end(), t,
                             [](double x, const Segment& s) { return x < s.t; });
  const std::size_t k = it == segments.begin() ? 0 : static_cast<std::size_t>(it - segments.begin()) - 1;
  const Segment& g = segments[k];
  Sample s;
  s.t = t;
  s.piece = static_cast<int>(k);
  const double tau = t - g.t;
  const double speed = norm(g.v), ac = norm(g.a);
  if (g.kind == SegmentKind::End) {
    s.p = g.p;
  } else if (g.kind == SegmentKind::Arc && speed > 0 && ac > 0) {
    const double r = speed * speed / ac;
    const Vec3 u = scale(g.a, 1.0 / ac), d1 = scale(g.v, 1.0 / speed);
    const Vec3 center = add(g.p, scale(u, r));
    const double th = speed * tau / r, c = std::cos(th), sn = std::sin(th);
    s.p = add(center, add(scale(u, -r * c), scale(d1, r * sn)));
    s.v = add(scale(u, speed * sn), scale(d1, speed * c));
    s.a = add(scale(u, ac * c), scale(d1, -ac * sn));
  } else {
    s.p = add(add(g.p, scale(g.v, tau)), scale(g.a, 0.5 * tau * tau));
    s.v = add(g.v, scale(g.a, tau));
    s.a = g.a;
  }
  return s;
}

std::vector<Sample> Trajectory::sample(double dt) const {
  if (!(dt > 0)) throw std::invalid_argument("trajectory: dt must be positive");
  const double need = std::floor(duration_ / dt) + 2;
  if (!(need <= kMaxSamples))
    throw InputError("trajectory",
                     fmt::format("the flight of {:.0f} s would need {:.0f} samples at {} s, more "
                                 "than the limit of {:.0f} per UAV (see docs/limits.md)",
                                 duration_, need, dt, kMaxSamples));
  std::vector<Sample> out;
  const auto steps = static_cast<std::size_t>(std::floor(duration_ / dt));
  out.reserve(steps + 2);
  for (std::size_t k = 0; k <= steps; ++k) out.push_back(at(static_cast<double>(k) * dt));
  if (duration_ - out.back().t < 1e-3 * dt) {
    if (out.size() > 1) out.pop_back();
    if (duration_ > 0 || out.empty()) out.push_back(at(duration_));
  } else {
    out.push_back(at(duration_));
  }
  // the end is exactly at rest (the last piece decelerates to 0)
  out.back().v = {0, 0, 0};
  return out;
}

const char* method_name(Method method) {
  return method == Method::Polynomial ? "polynomial" : "fillet-lines";
}

Method parse_method(const std::string& name, const std::string& field) {
  for (const Method m : {Method::FilletLines, Method::Polynomial})
    if (name == method_name(m)) return m;
  throw InputError(field, fmt::format("unknown trajectory method \"{}\"; expected fillet-lines or polynomial",
                                      name.substr(0, 40)));
}

void check_options(const Options& options, const Limits& limits) {
  if (options.method == Method::Polynomial) (void)detail::polynomial_bounds(limits, options);
}

Measured measure(const Trajectory& trajectory, double dt) {
  Measured m;
  m.duration_s = trajectory.duration();
  const auto s = trajectory.sample(dt);
  for (std::size_t k = 0; k < s.size(); ++k) {
    m.speed_max = std::max(m.speed_max, norm(s[k].v));
    m.accel_max = std::max(m.accel_max, norm(s[k].a));
    if (k == 0) continue;
    m.length_m += norm(sub(s[k].p, s[k - 1].p));
    m.jerk_max = std::max(m.jerk_max, norm(sub(s[k].a, s[k - 1].a)) / (s[k].t - s[k - 1].t));
  }
  return m;
}

std::vector<Vec3> flight_waypoints(const Plan& plan, std::size_t index,
                                   const waypoints::AltitudeOptions& altitudes) {
  const auto items = waypoints::mission_items(plan, index, altitudes);
  const geodesy::LocalFrame frame(plan.origin);
  const Point home = frame.to_local(plan.mission.uavs.at(index).start_resolved);
  // heights above take-off: with a DEM the items are above mean sea level, less the ground at take-off
  const double home_ground = terrain::home_ground(plan.mission, index);
  std::vector<Vec3> pts{{home.x(), home.y(), 0.0}};
  for (const auto& it : items) {
    if (it.command == waypoints::kNavWaypoint || it.command == waypoints::kNavTakeoff ||
        it.command == waypoints::kNavLand) {
      const Point p = frame.to_local({it.lon, it.lat});
      const double z =
          static_cast<double>(it.alt) - (it.frame == waypoints::kFrameGlobal ? home_ground : 0.0);
      pts.push_back({p.x(), p.y(), z});
    }
  }
  // return to launch: back above home at the current altitude, then down to the ground
  const Vec3 last = pts.back();
  pts.push_back({home.x(), home.y(), last[2]});
  pts.push_back({home.x(), home.y(), 0.0});
  return pts;
}

Trajectory uav_trajectory(const Plan& plan, std::size_t index, const Options& options,
                          const waypoints::AltitudeOptions& altitudes) {
  const Uav& u = plan.mission.uavs.at(index);
  return Trajectory(flight_waypoints(plan, index, altitudes), Limits{u.speed_mps, u.max_accel_mps2}, options);
}

double flight_time_s(const Plan& plan, std::size_t index, const Options& options,
                     const waypoints::AltitudeOptions& altitudes) {
  return uav_trajectory(plan, index, options, altitudes).duration();
}

std::string trajectory_csv(const Plan& plan, const std::vector<Sample>& samples) {
  const geodesy::LocalFrame frame(plan.origin);
  std::string out = "t,x,y,z,lat,lon,vx,vy,vz,ax,ay,az\n";
  out.reserve(samples.size() * 120);
  for (const auto& s : samples) {
    const LonLat ll = frame.to_wgs84({s.p[0], s.p[1]});
    out += fmt::format(
        "{:.6f},{:.6f},{:.6f},{:.6f},{:.9f},{:.9f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}\n", s.t, s.p[0],
        s.p[1], s.p[2], ll.lat, ll.lon, s.v[0], s.v[1], s.v[2], s.a[0], s.a[1], s.a[2]);
  }
  return out;
}

std::string segments_csv(const Plan& plan, const Trajectory& trajectory) {
  const geodesy::LocalFrame frame(plan.origin);
  const auto segments = trajectory.segments();
  const Limits& lim = trajectory.limits();
  std::string out = std::string(kSegmentsHeader) + "\n";
  out.reserve(segments.size() * 260);
  for (const auto& g : segments) {
    const LonLat ll = frame.to_wgs84({g.p[0], g.p[1]});
    // "{}" is the shortest text that reads back to the same double
    out += fmt::format("{},{},{},{},{},{:.9f},{:.9f},{},{},{},{},{},{},{},{}\n", g.t,
                       segment_kind_name(g.kind), g.p[0], g.p[1], g.p[2], ll.lat, ll.lon, g.v[0], g.v[1],
                       g.v[2], g.a[0], g.a[1], g.a[2], lim.v_max, lim.a_max);
  }
  return out;
}

std::vector<Segment> parse_segments_csv(const std::string& csv) {
  std::vector<Segment> out;
  std::string_view text(csv);
  std::size_t line_no = 0;
  auto fail = [&](const std::string& why) {
    throw InputError("trajectory", fmt::format("line {}: {}", line_no, why));
  };
  while (!text.empty()) {
    const std::size_t nl = text.find('\n');
    std::string_view line = text.substr(0, nl);
    text = nl == std::string_view::npos ? std::string_view{} : text.substr(nl + 1);
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line_no == 1) {
      if (line != kSegmentsHeader) fail(fmt::format("expected the header \"{}\"", kSegmentsHeader));
      continue;
    }
    if (line.empty()) continue;
    std::vector<std::string_view> f;
    for (std::size_t pos = 0;;) {
      const std::size_t c = line.find(',', pos);
      f.push_back(line.substr(pos, c == std::string_view::npos ? std::string_view::npos : c - pos));
      if (c == std::string_view::npos) break;
      pos = c + 1;
    }
    if (f.size() != 15) fail(fmt::format("expected 15 fields, got {}", f.size()));
    auto num = [&](std::size_t i) {
      double x = 0;
      const auto r = std::from_chars(f[i].data(), f[i].data() + f[i].size(), x);
      if (r.ec != std::errc() || r.ptr != f[i].data() + f[i].size() || !std::isfinite(x))
        fail(fmt::format("field {} is not a number: \"{}\"", i + 1, f[i]));
      return x;
    };
    Segment g;
    g.t = num(0);
    bool known = false;
    for (const auto k : {SegmentKind::Accelerate, SegmentKind::Cruise, SegmentKind::Decelerate,
                         SegmentKind::Arc, SegmentKind::End})
      if (f[1] == segment_kind_name(k)) {
        g.kind = k;
        known = true;
      }
    if (!known) fail(fmt::format("unknown kind \"{}\"", f[1]));
    g.p = {num(2), num(3), num(4)};
    g.v = {num(7), num(8), num(9)};
    g.a = {num(10), num(11), num(12)};
    if (!out.empty() && !(g.t >= out.back().t)) fail("times must not decrease");
    out.push_back(g);
  }
  if (out.empty()) throw InputError("trajectory", "no segments");
  return out;
}

}  // namespace uavcover::trajectory
