// Corridor sweeps (docs/patterns.md).
#include "planners/corridor/corridor.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "uavcover/error.hpp"

namespace uavcover::planners::corridor {

namespace {

using Line = bg::model::linestring<Point>;
using MultiLine = bg::model::multi_linestring<Line>;

constexpr const char* kStage = "corridor";
/// Legs that end at a no-fly zone end this far from it (as the boustrophedon planner's).
constexpr double kNoFlyClearanceM = 0.5;

Point add(Point a, Point b, double k = 1.0) { return {a.x() + k * b.x(), a.y() + k * b.y()}; }
Point sub(Point a, Point b) { return {a.x() - b.x(), a.y() - b.y()}; }
double dot(Point a, Point b) { return a.x() * b.x() + a.y() * b.y(); }
double norm(Point a) { return std::hypot(a.x(), a.y()); }
double dist(Point a, Point b) { return norm(sub(a, b)); }

/// The centre line with its arc lengths, unit tangents and left normals per segment.
struct Centre {
  std::vector<Point> c;
  std::vector<double> s;  ///< arc length at each vertex
  std::vector<Point> t, n;
  explicit Centre(const std::vector<Point>& pts) {
    for (const auto& p : pts)
      if (c.empty() || dist(c.back(), p) > 1e-6) c.push_back(p);
    if (c.size() < 2) throw InputError("corridor.line", "needs at least two distinct vertices");
    s.push_back(0.0);
    for (std::size_t i = 1; i < c.size(); ++i) {
      const Point d = sub(c[i], c[i - 1]);
      const double l = norm(d);
      s.push_back(s.back() + l);
      t.push_back({d.x() / l, d.y() / l});
      n.push_back({-d.y() / l, d.x() / l});
    }
  }
  [[nodiscard]] double length() const { return s.back(); }
  /// The segment holding arc length x (at a vertex: the one after it; `end`: the one before it).
  [[nodiscard]] std::size_t seg(double x, bool end = false) const {
    const auto it = end ? std::lower_bound(s.begin(), s.end(), x) : std::upper_bound(s.begin(), s.end(), x);
    const auto i = static_cast<std::ptrdiff_t>(it - s.begin()) - 1;
    return static_cast<std::size_t>(
        std::clamp<std::ptrdiff_t>(i, 0, static_cast<std::ptrdiff_t>(t.size()) - 1));
  }
  [[nodiscard]] Point at(double x) const {
    const std::size_t i = seg(x);
    return add(c[i], t[i], x - s[i]);
  }
  /// Arc length of the point of the line nearest `p`.
  [[nodiscard]] double project(Point p) const {
    double best = 1e300, where = 0.0;
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double l = s[i + 1] - s[i];
      const double u = std::clamp(dot(sub(p, c[i]), t[i]), 0.0, l);
      const double d = dist(p, add(c[i], t[i], u));
      if (d < best - 1e-9) best = d, where = s[i] + u;
    }
    return where;
  }
  /// The centre line between arc lengths a and b.
  [[nodiscard]] std::vector<Point> piece(double a, double b) const {
    std::vector<Point> out{at(a)};
    for (std::size_t i = seg(a) + 1; i <= seg(b, true); ++i) out.push_back(c[i]);
    out.push_back(add(c[seg(b, true)], t[seg(b, true)], b - s[seg(b, true)]));
    return out;
  }
};

void joint(const Centre& L, std::size_t i, double d, std::vector<Point>& out) {
  const Point n1 = L.n[i - 1], n2 = L.n[i];
  const double cr = L.t[i - 1].x() * L.t[i].y() - L.t[i - 1].y() * L.t[i].x();
  const double co = dot(n1, n2);
  const bool outer = d * cr < 0.0;
  if (outer && 1.0 + co < 0.5) {  // sharper than 120 degrees: round on the outside
    const double a1 = std::atan2(n1.y(), n1.x());
    double delta = std::atan2(n2.y(), n2.x()) - a1;
    while (delta > std::numbers::pi) delta -= 2 * std::numbers::pi;
    while (delta < -std::numbers::pi) delta += 2 * std::numbers::pi;
    const int steps = std::max(2, static_cast<int>(std::ceil(std::fabs(delta) / (std::numbers::pi / 12))));
    for (int k = 0; k <= steps; ++k) {
      const double a = a1 + delta * k / steps;
      out.push_back(add(L.c[i], Point{std::cos(a), std::sin(a)}, d));
    }
    return;
  }
  if (1.0 + co < 1e-9) {  // a U-turn on the inside: both ends
    out.push_back(add(L.c[i], n1, d));
    out.push_back(add(L.c[i], n2, d));
    return;
  }
  const Point m{(n1.x() + n2.x()) / (1.0 + co), (n1.y() + n2.y()) / (1.0 + co)};  // the mitre
  out.push_back(add(L.c[i], m, d));
}

std::vector<Point> lane_of(const Centre& L, double d, double a, double b) {
  const std::size_t ia = L.seg(a), ib = L.seg(b, true);
  std::vector<Point> out{add(L.at(a), L.n[ia], d)};
  for (std::size_t i = ia + 1; i <= ib; ++i) joint(L, i, d, out);
  out.push_back(add(add(L.c[ib], L.t[ib], b - L.s[ib]), L.n[ib], d));
  return out;
}

/// Arc length along `pts` of the point nearest `p`.
double locate(const std::vector<Point>& pts, Point p) {
  double best = 1e300, where = 0.0, run = 0.0;
  for (std::size_t i = 1; i < pts.size(); ++i) {
    const Point d = sub(pts[i], pts[i - 1]);
    const double l = norm(d);
    const double u = l > 0 ? std::clamp(dot(sub(p, pts[i - 1]), d) / l, 0.0, l) : 0.0;
    const double e = l > 0 ? dist(p, add(pts[i - 1], d, u / l)) : dist(p, pts[i - 1]);
    if (e < best - 1e-9) best = e, where = run + u;
    run += l;
  }
  return where;
}

/// One leg: its points and, per segment, whether the camera is off.
struct Leg {
  std::vector<Point> pts;
  std::vector<std::uint8_t> off;
};
/// A lane: its legs in the lane's direction (no-fly zones cut a lane into several).
using Lane = std::vector<Leg>;

struct Geometry {
  const MultiPolygon* grown = nullptr;  ///< no-fly zones grown by the clearance
  double turnaround = 0.0;
  std::uint8_t turn_off = 1;  ///< the flag of turns and turnarounds (0 with capture_in_turnaround)

  /// The pieces of `pts` outside the grown no-fly zones, in order along it.
  [[nodiscard]] Lane cut(const std::vector<Point>& pts) const {
    Lane out;
    if (pts.size() < 2) return out;
    if (grown->empty()) {
      out.push_back({pts, std::vector<std::uint8_t>(pts.size() - 1, 0)});
      return out;
    }
    Line ls(pts.begin(), pts.end());
    MultiLine pieces;
    bg::difference(ls, *grown, pieces);
    std::vector<std::pair<double, std::vector<Point>>> sorted;
    for (auto& p : pieces) {
      std::vector<Point> v(p.begin(), p.end());
      if (v.size() < 2 || bg::length(p) < 1e-3) continue;
      const double s0 = locate(pts, v.front()), s1 = locate(pts, v.back());
      if (s1 < s0) std::reverse(v.begin(), v.end());
      sorted.emplace_back(std::min(s0, s1), std::move(v));
    }
    std::sort(sorted.begin(), sorted.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (auto& [s, v] : sorted) out.push_back({v, std::vector<std::uint8_t>(v.size() - 1, 0)});
    return out;
  }
  /// Length inside the grown no-fly zones of the segment a-b.
  [[nodiscard]] bool clear(Point a, Point b) const {
    if (grown->empty()) return true;
    Line ls{a, b};
    MultiLine in;
    bg::intersection(ls, *grown, in);
    return bg::length(in) < 1e-6;
  }
  /// How far from p along the unit direction u, up to len, before a no-fly zone.
  [[nodiscard]] double free_run(Point p, Point u, double len) const {
    if (len <= 0) return 0.0;
    if (grown->empty()) return len;
    Line ls{p, add(p, u, len)};
    MultiLine pieces;
    bg::difference(ls, *grown, pieces);
    for (const auto& piece : pieces)
      if (piece.size() >= 2 && dist(piece.front(), p) < 1e-6) return bg::length(piece);
    return 0.0;
  }
};

/// The lanes in flight order (each reversed or not), joined into coverage parts: turns between lanes
/// (camera off unless capture_in_turnaround), turnarounds at both ends of every lane, a new part where
/// the straight turn would cross a no-fly zone (the engine's transit goes around it).
struct Joined {
  std::vector<std::vector<Point>> parts;
  std::vector<std::vector<std::uint8_t>> off;
};
Joined join(const std::vector<Lane>& lanes, const std::vector<std::pair<std::size_t, bool>>& order,
            const Geometry& g) {
  Joined out;
  Leg cur;
  auto flush = [&] {
    if (cur.pts.size() >= 2) {
      out.parts.push_back(std::move(cur.pts));
      out.off.push_back(std::move(cur.off));
    }
    cur = Leg{};
  };
  for (const auto& [li, rev] : order) {
    Lane legs = lanes[li];
    if (legs.empty()) continue;
    if (rev) {
      std::reverse(legs.begin(), legs.end());
      for (auto& l : legs) {
        std::reverse(l.pts.begin(), l.pts.end());
        std::reverse(l.off.begin(), l.off.end());
      }
    }
    if (g.turnaround > 0) {  // the lane's ends extend by the turnaround, camera off
      Leg& first = legs.front();
      const Point u0 = sub(first.pts[0], first.pts[1]);
      const double r0 = g.free_run(first.pts[0], {u0.x() / norm(u0), u0.y() / norm(u0)}, g.turnaround);
      if (r0 > 1e-3) {
        first.pts.insert(first.pts.begin(), add(first.pts[0], u0, r0 / norm(u0)));
        first.off.insert(first.off.begin(), g.turn_off);
      }
      Leg& last = legs.back();
      const std::size_t e = last.pts.size() - 1;
      const Point u1 = sub(last.pts[e], last.pts[e - 1]);
      const double r1 = g.free_run(last.pts[e], {u1.x() / norm(u1), u1.y() / norm(u1)}, g.turnaround);
      if (r1 > 1e-3) {
        last.pts.push_back(add(last.pts[e], u1, r1 / norm(u1)));
        last.off.push_back(g.turn_off);
      }
    }
    for (auto& leg : legs) {
      if (cur.pts.empty()) {
        cur = std::move(leg);
        continue;
      }
      if (!g.clear(cur.pts.back(), leg.pts.front())) {
        flush();
        cur = std::move(leg);
        continue;
      }
      if (dist(cur.pts.back(), leg.pts.front()) > 1e-9) {
        cur.pts.push_back(leg.pts.front());
        cur.off.push_back(g.turn_off);
      }
      cur.pts.insert(cur.pts.end(), leg.pts.begin() + 1, leg.pts.end());
      cur.off.insert(cur.off.end(), leg.off.begin(), leg.off.end());
    }
  }
  flush();
  return out;
}

/// Lane order: 0, 1, 2, ... or, alternating transects, 0, 2, 4, ... and back over the odd ones.
std::vector<std::size_t> base_order(std::size_t n, bool alternate) {
  std::vector<std::size_t> o;
  if (!alternate) {
    for (std::size_t k = 0; k < n; ++k) o.push_back(k);
    return o;
  }
  for (std::size_t k = 0; k < n; k += 2) o.push_back(k);
  for (std::size_t k = n; k-- > 0;)
    if (k % 2 == 1) o.push_back(k);
  return o;
}

/// The four ways to fly the lanes (either end, either side first), the one the entry rule picks:
/// "auto" the first waypoint nearest `start`, a corner the first waypoint furthest that way.
Joined best_variant(const std::vector<Lane>& lanes, bool alternate, const std::string& entry, Point start,
                    const Geometry& g) {
  const std::vector<std::size_t> base = base_order(lanes.size(), alternate);
  double sx = 0, sy = 0;
  if (entry.size() == 2) {
    sy = entry[0] == 'n' ? 1.0 : -1.0;
    sx = entry[1] == 'e' ? 1.0 : -1.0;
  }
  std::optional<Joined> best;
  double best_score = 1e300;
  for (int v = 0; v < 4; ++v) {
    std::vector<std::size_t> o = base;
    if (v / 2 == 1) std::reverse(o.begin(), o.end());
    std::vector<std::pair<std::size_t, bool>> order;
    for (std::size_t i = 0; i < o.size(); ++i) order.emplace_back(o[i], (i % 2 == 1) != (v % 2 == 1));
    Joined j = join(lanes, order, g);
    if (j.parts.empty()) continue;
    const Point f = j.parts.front().front();
    // corners: the furthest first waypoint that way (ties within 1 cm: the nearest the start)
    const double score =
        entry.size() == 2 ? -(sx * f.x() + sy * f.y()) * 100.0 + dist(f, start) * 1e-6 : dist(f, start);
    if (score < best_score - 1e-12) best_score = score, best = std::move(j);
  }
  return best ? std::move(*best) : Joined{};
}

MultiPolygon band(const std::vector<Point>& piece, double width) {
  Line ls(piece.begin(), piece.end());
  bg::strategy::buffer::distance_symmetric<double> distance(0.5 * width);
  bg::strategy::buffer::side_straight side;
  bg::strategy::buffer::join_miter join(2.0);
  bg::strategy::buffer::end_flat end;
  bg::strategy::buffer::point_square point;
  MultiPolygon out;
  bg::buffer(ls, out, distance, side, join, end, point);
  return out;
}

}  // namespace

int lane_count(double width_m, double spacing_m) {
  return std::max(1, static_cast<int>(std::ceil(width_m / spacing_m - 1e-9)));
}

std::vector<Point> offset_lane(const std::vector<Point>& line, double offset_m, double from_m, double to_m) {
  return lane_of(Centre(line), offset_m, from_m, to_m);
}

Assignment plan(const Problem& p, const Context& ctx) {
  ctx.check();
  ctx.report(kStage, 0.0);
  const std::size_t n_uav = p.starts.size();
  if (n_uav == 0) throw InputError("uavs", "at least one UAV is needed");
  if (!(p.spacing_m > 0.0))
    throw InputError("spacing_m", "the line spacing must be a positive number of metres");
  const Centre L(p.corridor_line);
  const double width = p.corridor_width_m;
  const int lanes_n = lane_count(width, p.spacing_m);
  if (lanes_n > 1000)
    throw InputError("corridor.width_m",
                     "needs " + std::to_string(lanes_n) + " lanes at this spacing (at most 1000)");
  const double half_fp = 0.5 * (p.footprint_m > 0.0 ? p.footprint_m : 1.5 * p.spacing_m);
  const Pattern pat = p.pattern.value_or(Pattern{});

  MultiPolygon grown;
  if (!p.no_fly.empty()) {
    bg::strategy::buffer::distance_symmetric<double> distance(kNoFlyClearanceM);
    bg::strategy::buffer::side_straight side;
    bg::strategy::buffer::join_miter join;
    bg::strategy::buffer::end_flat end;
    bg::strategy::buffer::point_square point;
    bg::buffer(p.no_fly, grown, distance, side, join, end, point);
  }
  Geometry g;
  g.grown = &grown;
  g.turnaround = pat.turnaround_m;
  g.turn_off = pat.capture_in_turnaround || !p.pattern ? 0 : 1;

  // the UAVs along the line in the order of their starts' projections, each a piece by share
  std::vector<std::size_t> along(n_uav);
  std::iota(along.begin(), along.end(), 0);
  std::vector<double> where(n_uav);
  for (std::size_t i = 0; i < n_uav; ++i) where[i] = L.project(p.starts[i]);
  std::stable_sort(along.begin(), along.end(),
                   [&](std::size_t x, std::size_t y) { return where[x] < where[y]; });
  double total_share = 0.0;
  for (double s : p.shares) total_share += s;

  Assignment out;
  out.uavs.resize(n_uav);
  const double free_area = bg::area(p.free);
  MultiPolygon taken;
  double cum = 0.0;
  const double len = L.length();
  for (std::size_t r = 0; r < n_uav; ++r) {
    ctx.check();
    const std::size_t u = along[r];
    const double a = len * cum / total_share;
    cum += p.shares[u];
    const double b = r + 1 == n_uav ? len : len * cum / total_share;
    auto& ua = out.uavs[u];
    if (b - a < 1e-6) continue;
    // the lanes, left (k = 0) to right, extended past the corridor's ends in coverage mode
    std::vector<Lane> lanes;
    for (int k = 0; k < lanes_n; ++k) {
      const double d = (0.5 * (lanes_n - 1) - k) * p.spacing_m;
      std::vector<Point> pts = lane_of(L, d, a, b);
      if (p.mode == Mode::Coverage && a <= 1e-9)
        pts.insert(pts.begin(), add(pts.front(), L.t.front(), -half_fp));
      if (p.mode == Mode::Coverage && b >= len - 1e-9) pts.push_back(add(pts.back(), L.t.back(), half_fp));
      lanes.push_back(g.cut(pts));
    }
    Joined j = best_variant(lanes, pat.alternate_transects, pat.entry, p.starts[u], g);
    int cross_legs = 0;
    if (pat.crosshatch) {
      // the second sweep at 90 degrees: legs across the corridor, `spacing` apart along the centre line
      const int m = std::max(1, static_cast<int>(std::ceil((b - a) / p.spacing_m - 1e-9)));
      const double reach = p.mode == Mode::Coverage ? 0.5 * width + half_fp : 0.5 * width - 0.01;
      std::vector<Lane> across;
      for (int q = 0; q < m; ++q) {
        const double s = a + (q + 0.5) * (b - a) / m;
        const Point c = L.at(s), nn = L.n[L.seg(s)];
        std::vector<Point> leg{add(c, nn, -reach), add(c, nn, reach)};
        if (p.mode == Mode::Strict) {  // inside the corridor (the ends of a bend's fan may leave it)
          Line ls(leg.begin(), leg.end());
          MultiLine in;
          bg::intersection(ls, p.area, in);
          Lane lane;
          for (const auto& piece : in)
            for (auto& l : g.cut(std::vector<Point>(piece.begin(), piece.end())))
              lane.push_back(std::move(l));
          std::sort(lane.begin(), lane.end(), [&](const Leg& x, const Leg& y) {
            return locate(leg, x.pts.front()) < locate(leg, y.pts.front());
          });
          across.push_back(std::move(lane));
        } else {
          across.push_back(g.cut(leg));
        }
        cross_legs += across.back().empty() ? 0 : 1;
      }
      const Point end = j.parts.empty() ? p.starts[u] : j.parts.back().back();
      Joined second = best_variant(across, pat.alternate_transects, "auto", end, g);
      for (std::size_t k = 0; k < second.parts.size(); ++k) {
        if (k == 0 && !j.parts.empty() && g.clear(j.parts.back().back(), second.parts[0].front())) {
          j.parts.back().push_back(second.parts[0].front());
          j.off.back().push_back(g.turn_off);
          j.parts.back().insert(j.parts.back().end(), second.parts[0].begin() + 1, second.parts[0].end());
          j.off.back().insert(j.off.back().end(), second.off[0].begin(), second.off[0].end());
          continue;
        }
        j.parts.push_back(std::move(second.parts[k]));
        j.off.push_back(std::move(second.off[k]));
      }
    }
    ua.coverage = std::move(j.parts);
    ua.camera_off = std::move(j.off);
    // the region: the piece of the corridor, exclusive of the pieces before it
    MultiPolygon piece = band(L.piece(a, b), width), inside, mine;
    bg::intersection(piece, p.free, inside);
    bg::difference(inside, taken, mine);
    for (const auto& poly : mine) taken.push_back(poly);
    MultiPolygon merged;
    bg::union_(taken, MultiPolygon{}, merged);
    taken = merged;
    ua.region = mine;
    ua.share_actual = free_area > 0 ? bg::area(mine) / free_area : 0.0;
    ua.diagnostics = {{"corridor_from_m", a}, {"corridor_to_m", b}, {"lanes", lanes_n}};
    if (pat.crosshatch) ua.diagnostics["crosshatch_legs"] = cross_legs;
    ctx.report(kStage, static_cast<double>(r + 1) / static_cast<double>(n_uav));
  }
  out.diagnostics = {{"corridor_length_m", len}, {"corridor_width_m", width}, {"lanes", lanes_n}};
  return out;
}

}  // namespace uavcover::planners::corridor
