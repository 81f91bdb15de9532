#include "planners/structure/structure.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "evaluation/cost.hpp"
#include "evaluation/facade.hpp"
#include "uavcover/error.hpp"

namespace uavcover::planners::structure {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();
/// The most layers a structure may need (a 1000 m wall at 2 m per layer).
constexpr std::size_t kMaxLayers = 500;

double dist(Point a, Point b) { return std::hypot(a.x() - b.x(), a.y() - b.y()); }
Point lerp(Point a, Point b, double t) { return {a.x() + t * (b.x() - a.x()), a.y() + t * (b.y() - a.y())}; }

/// The nearest points of the footprint's outline to p: `foot` (their mean where several walls are
/// equally near: a mitre at a concave corner) and `inner` (the corner itself there).
struct Nearest {
  Point foot, inner;
  double d = kInf;
};

Nearest nearest(const Polygon& fp, Point p) {
  const auto& r = fp.outer();
  struct Cand {
    Point q;
    std::size_t edge;
    double d;
  };
  std::vector<Cand> cands;
  double best = kInf;
  for (std::size_t i = 1; i < r.size(); ++i) {
    const Point a = r[i - 1], b = r[i];
    const double dx = b.x() - a.x(), dy = b.y() - a.y();
    const double l2 = dx * dx + dy * dy;
    const double t = l2 > 0 ? std::clamp(((p.x() - a.x()) * dx + (p.y() - a.y()) * dy) / l2, 0.0, 1.0) : 0.0;
    const Point q = lerp(a, b, t);
    const double d = dist(p, q);
    cands.push_back({q, i, d});
    best = std::min(best, d);
  }
  Nearest out;
  out.d = best;
  std::vector<const Cand*> near;
  for (const auto& c : cands) {
    if (c.d > best + 1e-6 + 1e-9 * best) continue;
    bool seen = false;
    for (const Cand* n : near) seen = seen || dist(n->q, c.q) < 1e-6;
    if (!seen) near.push_back(&c);
  }
  if (near.size() <= 1) {
    out.foot = out.inner = near.empty() ? p : near.front()->q;
    return out;
  }
  double x = 0, y = 0;
  for (const Cand* n : near) x += n->q.x(), y += n->q.y();
  out.foot = Point(x / static_cast<double>(near.size()), y / static_cast<double>(near.size()));
  // the corner between the equally near walls: of their edges' ends, the one nearest the mean foot
  double bd = kInf;
  for (const Cand* n : near)
    for (const Point& v : {r[n->edge - 1], r[n->edge]})
      if (dist(v, out.foot) < bd) bd = dist(v, out.foot), out.inner = v;
  return out;
}

double bearing(Point from, Point to) {
  double b = std::atan2(to.x() - from.x(), to.y() - from.y()) * 180.0 / kPi;
  if (b < 0) b += 360.0;
  if (b >= 360.0) b -= 360.0;
  return b;
}

/// A closed polyline parameterised by arc length.
struct Ring {
  std::vector<Point> pts;  // closed: last == first
  std::vector<double> s;   // cumulative length at each vertex
  double length = 0.0;
  explicit Ring(std::vector<Point> p) : pts(std::move(p)) {
    s.push_back(0);
    for (std::size_t i = 1; i < pts.size(); ++i) s.push_back(s.back() + dist(pts[i - 1], pts[i]));
    length = s.back();
  }
  [[nodiscard]] double wrap(double t) const {
    t = std::fmod(t, length);
    return t < 0 ? t + length : t;
  }
  [[nodiscard]] Point at(double t) const {
    t = wrap(t);
    const auto it = std::upper_bound(s.begin(), s.end(), t);
    const std::size_t i =
        std::clamp<std::size_t>(static_cast<std::size_t>(it - s.begin()), 1, pts.size() - 1);
    const double seg = s[i] - s[i - 1];
    return seg > 0 ? lerp(pts[i - 1], pts[i], (t - s[i - 1]) / seg) : pts[i];
  }
  /// Arc length of the ring point nearest to p.
  [[nodiscard]] double project(Point p) const {
    double best = kInf, bt = 0;
    for (std::size_t i = 1; i < pts.size(); ++i) {
      const Point a = pts[i - 1], b = pts[i];
      const double dx = b.x() - a.x(), dy = b.y() - a.y();
      const double l2 = dx * dx + dy * dy;
      const double t =
          l2 > 0 ? std::clamp(((p.x() - a.x()) * dx + (p.y() - a.y()) * dy) / l2, 0.0, 1.0) : 0.0;
      const double d = dist(p, lerp(a, b, t));
      if (d < best - 1e-9) best = d, bt = s[i - 1] + t * (s[i] - s[i - 1]);
    }
    return bt;
  }
  /// The ring from arc length t0 forward to t1 (t0 <= t1 <= t0 + length): end points interpolated.
  [[nodiscard]] std::vector<Point> arc(double t0, double t1) const {
    std::vector<Point> out{at(t0)};
    const double base = t0 - wrap(t0);  // arc lengths along the unrolled ring
    for (int lap = 0; lap < 3; ++lap)
      for (std::size_t i = 1; i < pts.size(); ++i) {
        const double v = base + lap * length + s[i];
        if (v > t0 + 1e-6 && v < t1 - 1e-6) out.push_back(pts[i]);
      }
    out.push_back(at(t1));
    return out;
  }
};

std::vector<double> headings_of(const Polygon& fp, const std::vector<Point>& pts) {
  std::vector<double> h;
  h.reserve(pts.size());
  for (const Point& p : pts) h.push_back(facing_bearing(fp, p));
  return h;
}

/// The band between the wall and the orbit along `pts` (quads from each orbit segment to the wall).
MultiPolygon band(const Polygon& fp, const std::vector<Point>& pts) {
  MultiPolygon out;
  std::vector<Point> inner;
  for (const Point& p : pts) inner.push_back(nearest(fp, p).inner);
  for (std::size_t i = 1; i < pts.size(); ++i) {
    Polygon q;
    for (const Point& v : {pts[i - 1], pts[i], inner[i], inner[i - 1], pts[i - 1]}) bg::append(q.outer(), v);
    bg::correct(q);
    if (std::abs(bg::area(q)) < 1e-9) continue;
    MultiPolygon u;
    bg::union_(out, q, u);
    out = std::move(u);
  }
  return out;
}

/// Largest-remainder split of `n` items by `shares`.
std::vector<std::size_t> split(std::size_t n, const std::vector<double>& shares) {
  std::vector<std::size_t> c(shares.size(), 0);
  std::vector<std::pair<double, std::size_t>> rem;
  std::size_t given = 0;
  for (std::size_t i = 0; i < shares.size(); ++i) {
    const double x = static_cast<double>(n) * shares[i];
    c[i] = static_cast<std::size_t>(std::floor(x + 1e-9));
    given += c[i];
    rem.emplace_back(-(x - static_cast<double>(c[i])), i);
  }
  std::sort(rem.begin(), rem.end());
  for (std::size_t k = 0; given < n && k < rem.size(); ++k, ++given) ++c[rem[k].second];
  return c;
}

struct Option {
  std::vector<UavAssignment> uavs;
  std::vector<double> finish_min;  // estimated per UAV (eq. 15 over the 3D length)
  double makespan = 0.0, total_m = 0.0;
};

void add_part(UavAssignment& a, std::vector<Point> pts, const Polygon& fp, double z, double trigger) {
  Attitude att;
  att.altitude_m = z;
  att.heading_deg = headings_of(fp, pts);
  att.gimbal_pitch_deg = 0.0;
  att.trigger_distance_m = trigger;
  a.coverage.push_back(std::move(pts));
  a.camera_off.emplace_back();
  a.attitude.push_back(std::move(att));
}

}  // namespace

Layout layout(const Structure& st, const Camera& camera) {
  const evaluation::FacadeCamera fc = evaluation::facade_camera(camera);
  Layout l;
  l.photo_width_m = fc.width_at(st.standoff_m);
  l.photo_height_m = fc.height_at(st.standoff_m);
  l.layer_spacing_m = l.photo_height_m * (1.0 - fc.side_overlap);
  l.trigger_m = l.photo_width_m * (1.0 - fc.front_overlap);
  if (!(l.layer_spacing_m > 0) || !std::isfinite(l.layer_spacing_m))
    throw InputError("camera", "gives no layer spacing on the wall (side overlap too high)");
  if (!(l.trigger_m > 0) || !std::isfinite(l.trigger_m))
    throw InputError("camera.front_overlap", "gives no photo spacing along the orbit");
  const double sp = l.layer_spacing_m;
  const double z0 = std::max(st.safe_height_m, sp / 2);
  std::size_t n = 1;
  if (z0 + sp / 2 < st.height_m)
    n = static_cast<std::size_t>(std::ceil((st.height_m - z0 - sp / 2) / sp - 1e-9)) + 1;
  if (n > kMaxLayers)
    throw InputError("camera", fmt::format("gives {} orbit layers at {:.2f} m on a {} m wall, more than {}: "
                                           "lower the side overlap or raise structure.standoff_m",
                                           n, sp, st.height_m, kMaxLayers));
  for (std::size_t k = 0; k < n; ++k) l.heights_m.push_back(z0 + static_cast<double>(k) * sp);
  l.roof_altitude_m = st.height_m + camera.altitude_m;
  return l;
}

MultiPolygon keep_out(const Polygon& footprint, const Structure& st, const MultiPolygon& no_fly) {
  bg::strategy::buffer::distance_symmetric<double> distance(st.standoff_m / 2);
  bg::strategy::buffer::side_straight side;
  bg::strategy::buffer::join_round join(72);
  bg::strategy::buffer::end_flat end;
  bg::strategy::buffer::point_circle point(72);
  MultiPolygon grown;
  bg::buffer(MultiPolygon{footprint}, grown, distance, side, join, end, point);
  MultiPolygon out = no_fly;
  for (auto& p : grown) out.push_back(std::move(p));
  return out;
}

std::vector<Point> orbit(const Polygon& footprint, double standoff_m) {
  bg::strategy::buffer::distance_symmetric<double> distance(standoff_m);
  bg::strategy::buffer::side_straight side;
  bg::strategy::buffer::join_round join(72);  // 5 degree steps, as the mission's area
  bg::strategy::buffer::end_flat end;
  bg::strategy::buffer::point_circle point(72);
  MultiPolygon buf;
  bg::buffer(MultiPolygon{footprint}, buf, distance, side, join, end, point);
  if (buf.empty()) throw InputError("structure.footprint", "has no buffer by standoff_m");
  std::vector<Point> ring(buf.front().outer().begin(), buf.front().outer().end());
  std::reverse(ring.begin(), ring.end());  // Boost's outer rings are clockwise
  std::vector<Point> out;
  for (const Point& p : ring)
    if (out.empty() || dist(out.back(), p) > 1e-6) out.push_back(p);
  if (out.size() >= 2 && dist(out.front(), out.back()) > 1e-6) out.push_back(out.front());
  if (out.size() >= 2) out.back() = out.front();
  return out;
}

double facing_bearing(const Polygon& footprint, Point p) { return bearing(p, nearest(footprint, p).foot); }

Assignment plan(const Problem& problem, const Context& ctx) {
  if (!problem.structure) throw OperationError("structure::plan called without a structure");
  if (!problem.camera)
    throw InputError("camera", "a structure scan needs a camera block (its field of view and overlaps)");
  const Structure& st = *problem.structure;
  if (problem.pattern) {  // the area patterns' options have no lanes to work on around a wall
    const Pattern& pt = *problem.pattern;
    const char* asked = pt.crosshatch              ? "crosshatch"
                        : pt.turnaround_m > 0      ? "turnaround_m"
                        : pt.entry != "auto"       ? "entry"
                        : pt.alternate_transects   ? "alternate_transects"
                        : pt.capture_in_turnaround ? "capture_in_turnaround"
                        : pt.oblique               ? "oblique"
                                                   : nullptr;
    if (asked != nullptr)
      throw InputError(std::string("pattern.") + asked, "does not apply to a structure (facade) scan");
  }
  Polygon fp = problem.structure_footprint;
  bg::correct(fp);
  const std::size_t n = problem.starts.size();
  if (n == 0) throw InputError("uavs", "at least one UAV is needed");
  for (std::size_t i = 0; i < n; ++i)
    if (bg::distance(problem.starts[i], fp) < st.standoff_m / 2 - 1e-6)
      throw InputError(
          "uavs[" + std::to_string(i) + "].start",
          fmt::format("lies on the structure or within half the standoff ({:.1f} m) of its walls",
                      st.standoff_m / 2));
  ctx.check();
  const Layout lay = layout(st, *problem.camera);
  const Ring ring(orbit(fp, st.standoff_m));
  const std::size_t nl = lay.heights_m.size();
  const double climb_total = lay.heights_m.back() - lay.heights_m.front();

  // (a) the layers shared: contiguous blocks by share, each a closed loop from the vertex nearest the start
  Option layers;
  layers.uavs.resize(n);
  {
    const auto counts = split(nl, problem.shares);
    std::size_t next = 0;
    for (std::size_t i = 0; i < n; ++i) {
      auto& a = layers.uavs[i];
      const Point s = problem.starts[i];
      std::size_t j0 = 0;
      for (std::size_t j = 0; j + 1 < ring.pts.size(); ++j)
        if (dist(ring.pts[j], s) < dist(ring.pts[j0], s)) j0 = j;
      std::vector<Point> loop;
      for (std::size_t k = 0; k + 1 < ring.pts.size(); ++k)
        loop.push_back(ring.pts[(j0 + k) % (ring.pts.size() - 1)]);
      loop.push_back(loop.front());
      double len = 0;
      for (std::size_t k = 0; k < counts[i]; ++k)
        add_part(a, loop, fp, lay.heights_m[next + k], lay.trigger_m);
      if (counts[i] > 0) {
        len = static_cast<double>(counts[i]) * ring.length +
              (lay.heights_m[next + counts[i] - 1] - lay.heights_m[next]) + 2 * dist(s, loop.front());
        a.diagnostics["layers_m"] =
            std::vector<double>(lay.heights_m.begin() + static_cast<long>(next),
                                lay.heights_m.begin() + static_cast<long>(next + counts[i]));
      }
      next += counts[i];
      const int turns = static_cast<int>(counts[i] * loop.size());
      layers.finish_min.push_back(len > 0 ? evaluation::flight_duration_min(len, turns, problem.uavs[i])
                                          : 0.0);
      layers.total_m += len;
    }
  }
  ctx.check();

  // (b) angular sectors by share, every layer in each, flown up and down; the seam that brings the sector
  // ends nearest the starts
  Option sectors;
  sectors.uavs.resize(n);
  {
    std::vector<double> proj(n);
    for (std::size_t i = 0; i < n; ++i) proj[i] = ring.project(problem.starts[i]);
    std::vector<double> seams;
    for (int k = 0; k < 72; ++k) seams.push_back(ring.length * k / 72.0);
    for (double p : proj) seams.push_back(p);
    struct Sector {
      double a, b;
      bool forward;  // enters at a
    };
    double best = kInf;
    std::vector<Sector> chosen;
    std::vector<std::size_t> chosen_order;
    for (double seam : seams) {
      std::vector<std::size_t> order(n);
      std::iota(order.begin(), order.end(), 0);
      std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
        return ring.wrap(proj[x] - seam) < ring.wrap(proj[y] - seam);
      });
      double t = seam, cost = 0;
      std::vector<Sector> secs(n);
      for (std::size_t i : order) {
        const double l = ring.length * problem.shares[i];
        Sector sc{t, t + l, true};
        const Point pa = ring.at(sc.a), pb = ring.at(sc.b), s = problem.starts[i];
        // an odd number of layers ends at the other end
        const double fwd = dist(s, pa) + dist(nl % 2 ? pb : pa, s);
        const double bwd = dist(s, pb) + dist(nl % 2 ? pa : pb, s);
        sc.forward = fwd <= bwd;
        cost += std::min(fwd, bwd);
        secs[i] = sc;
        t += l;
      }
      if (cost < best - 1e-9) best = cost, chosen = secs, chosen_order = order;
    }
    for (std::size_t i = 0; i < n; ++i) {
      auto& a = sectors.uavs[i];
      const Sector& sc = chosen[i];
      if (problem.shares[i] <= 0 || sc.b - sc.a < 1e-6) {
        sectors.finish_min.push_back(0.0);
        continue;
      }
      std::vector<Point> fwd = ring.arc(sc.a, sc.b);
      std::vector<Point> bwd(fwd.rbegin(), fwd.rend());
      for (std::size_t k = 0; k < nl; ++k)
        add_part(a, ((k % 2 == 0) == sc.forward) ? fwd : bwd, fp, lay.heights_m[k], lay.trigger_m);
      const Point s = problem.starts[i];
      const double len = static_cast<double>(nl) * (sc.b - sc.a) + climb_total +
                         dist(s, a.coverage.front().front()) + dist(a.coverage.back().back(), s);
      sectors.finish_min.push_back(
          evaluation::flight_duration_min(len, static_cast<int>(nl * fwd.size()), problem.uavs[i]));
      sectors.total_m += len;
      a.region = band(fp, fwd);
      a.diagnostics["sector_m"] = {ring.wrap(sc.a), ring.wrap(sc.b)};
      a.diagnostics["layers_m"] = lay.heights_m;
    }
  }
  layers.makespan = *std::max_element(layers.finish_min.begin(), layers.finish_min.end());
  sectors.makespan = *std::max_element(sectors.finish_min.begin(), sectors.finish_min.end());
  const bool use_layers =
      n == 1 || layers.makespan < sectors.makespan - 1e-9 ||
      (std::fabs(layers.makespan - sectors.makespan) <= 1e-9 && layers.total_m <= sectors.total_m);
  Option& pick = use_layers ? layers : sectors;
  ctx.check();

  // the roof (top): a nadir lawnmower at height_m + the camera's altitude, by the UAV finishing first,
  // entered from where its last layer ends and left to the nearest orbit point
  std::size_t roof_uav = n;
  if (st.top) {
    for (std::size_t i = 0; i < n; ++i)
      if (!pick.uavs[i].coverage.empty() && (roof_uav == n || pick.finish_min[i] < pick.finish_min[roof_uav]))
        roof_uav = i;
    // lanes along the footprint's longest edge, at the mission's spacing, half a spacing in from its sides
    const auto& r = fp.outer();
    double ang = 0, longest = 0;
    for (std::size_t i = 1; i < r.size(); ++i)
      if (dist(r[i - 1], r[i]) > longest)
        longest = dist(r[i - 1], r[i]), ang = std::atan2(r[i].y() - r[i - 1].y(), r[i].x() - r[i - 1].x());
    const double c = std::cos(ang), s = std::sin(ang);
    auto to_uv = [&](Point p) { return Point(p.x() * c + p.y() * s, -p.x() * s + p.y() * c); };
    auto from_uv = [&](double u, double v) { return Point(u * c - v * s, u * s + v * c); };
    double vmin = kInf, vmax = -kInf;
    for (const Point& p : r) vmin = std::min(vmin, to_uv(p).y()), vmax = std::max(vmax, to_uv(p).y());
    const double sp = problem.spacing_m;
    const std::size_t lanes =
        std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil((vmax - vmin) / sp - 1e-9)));
    std::vector<std::pair<Point, Point>> lane_pts;
    for (std::size_t k = 0; k < lanes; ++k) {
      const double v = vmin + (static_cast<double>(k) + 0.5) * (vmax - vmin) / static_cast<double>(lanes);
      double umin = kInf, umax = -kInf;
      for (std::size_t i = 1; i < r.size(); ++i) {
        const Point a = to_uv(r[i - 1]), b = to_uv(r[i]);
        if ((a.y() - v) * (b.y() - v) > 0 || a.y() == b.y()) continue;
        const double u = a.x() + (v - a.y()) / (b.y() - a.y()) * (b.x() - a.x());
        umin = std::min(umin, u), umax = std::max(umax, u);
      }
      if (umin <= umax) lane_pts.emplace_back(from_uv(umin, v), from_uv(umax, v));
    }
    if (roof_uav < n && !lane_pts.empty()) {
      auto& a = pick.uavs[roof_uav];
      const Point entry = a.coverage.back().back();
      // of the four ways to fly the lanes, the one starting nearest the entry
      std::vector<Point> best_path;
      for (int way = 0; way < 4; ++way) {
        std::vector<Point> path;
        for (std::size_t k = 0; k < lane_pts.size(); ++k) {
          const std::size_t idx = way & 1 ? lane_pts.size() - 1 - k : k;
          const bool flip = ((k % 2) == 1) != ((way & 2) != 0);
          path.push_back(flip ? lane_pts[idx].second : lane_pts[idx].first);
          path.push_back(flip ? lane_pts[idx].first : lane_pts[idx].second);
        }
        if (best_path.empty() || dist(entry, path.front()) < dist(entry, best_path.front()) - 1e-9)
          best_path = std::move(path);
      }
      std::vector<Point> part{entry};
      part.insert(part.end(), best_path.begin(), best_path.end());
      part.push_back(ring.at(ring.project(best_path.back())));
      std::vector<std::uint8_t> off(part.size() - 1, 1);
      for (std::size_t k = 0; k < lane_pts.size(); ++k) off[1 + 2 * k] = 0;  // the lanes: camera on
      Attitude att;
      att.altitude_m = lay.roof_altitude_m;
      att.gimbal_pitch_deg = -90.0;
      a.coverage.push_back(std::move(part));
      a.camera_off.push_back(std::move(off));
      a.attitude.push_back(std::move(att));
      a.diagnostics["roof_altitude_m"] = lay.roof_altitude_m;
    }
  }

  // regions: a sector's band between the wall and the orbit (exclusive); shared layers: the ring for
  // every UAV with layers (the UAVs are separated in height, not on the ground; docs/patterns.md)
  double work_total = 0;
  std::vector<double> work(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (const auto& c : pick.uavs[i].coverage)
      for (std::size_t k = 1; k < c.size(); ++k) work[i] += dist(c[k - 1], c[k]);
  for (double w : work) work_total += w;
  MultiPolygon taken;
  for (std::size_t i = 0; i < n; ++i) {
    auto& a = pick.uavs[i];
    if (use_layers) {
      a.region = a.coverage.empty() ? MultiPolygon{} : problem.free;
    } else {
      MultiPolygon in_free, own;
      bg::intersection(a.region, problem.free, in_free);
      bg::difference(in_free, taken, own);
      a.region = std::move(own);
      MultiPolygon u;
      bg::union_(taken, a.region, u);
      taken = std::move(u);
    }
    a.share_actual = work_total > 0 ? work[i] / work_total : 0.0;
  }

  // vertical separation: shared layers keep each UAV in its own block of heights
  nlohmann::json separation = nullptr;
  if (use_layers && n > 1) {
    double block_gap = kInf, equal_progress = kInf;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) {
        const auto& ai = pick.uavs[i].attitude;
        const auto& aj = pick.uavs[j].attitude;
        for (const auto& x : ai)
          for (const auto& y : aj) block_gap = std::min(block_gap, std::fabs(*x.altitude_m - *y.altitude_m));
        for (std::size_t k = 0; k < std::min(ai.size(), aj.size()); ++k)
          equal_progress = std::min(equal_progress, std::fabs(*ai[k].altitude_m - *aj[k].altitude_m));
      }
    if (std::isfinite(block_gap))
      separation = {{"min_m", block_gap},
                    {"at_equal_progress_m", std::isfinite(equal_progress) ? equal_progress : block_gap}};
  }

  Assignment out;
  out.uavs = std::move(pick.uavs);
  out.diagnostics["structure"] = {
      {"strategy", use_layers ? "layers" : "sectors"},
      {"layers_m", lay.heights_m},
      {"layer_spacing_m", lay.layer_spacing_m},
      {"trigger_distance_m", lay.trigger_m},
      {"photo_width_m", lay.photo_width_m},
      {"photo_height_m", lay.photo_height_m},
      {"orbit_length_m", ring.length},
      {"estimated_finish_min", {{"layers", layers.makespan}, {"sectors", sectors.makespan}}},
      {"vertical_separation", separation},
      {"roof_uav", roof_uav < n ? nlohmann::json(roof_uav) : nlohmann::json(nullptr)}};
  if (lay.heights_m.front() - lay.photo_height_m / 2 > 1e-9)
    out.warnings.push_back(fmt::format(
        "structure: the bottom layer at {:.1f} m (safe_height_m) sees the wall from {:.1f} m up only",
        lay.heights_m.front(), lay.heights_m.front() - lay.photo_height_m / 2));
  return out;
}

}  // namespace uavcover::planners::structure
