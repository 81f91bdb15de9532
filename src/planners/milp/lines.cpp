#include "planners/milp/lines.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "planners/boustrophedon/sweep.hpp"
#include "uavcover/error.hpp"

namespace uavcover::planners::milp {

namespace {

using boustro::Box;
using boustro::Frame;
using boustro::Ring;
constexpr double kPi = std::numbers::pi;
/// Segments keep this far from no-fly zones, so that no waypoint lies on (and, after rounding to
/// WGS84, inside) an exclusion polygon.
constexpr double kNoFlyClearanceM = 0.5;

/// Only a stop request ends the work here: past the deadline the planner still returns its best plan.
void stop_check(const Context& ctx) {
  if (ctx.stop_requested()) ctx.check();
}

double axis(double a) {
  a = std::fmod(a, kPi);
  if (a < 0) a += kPi;
  return a;
}

/// Frame X extent of a polygon.
std::pair<double, double> x_extent(const Ring& r, const Frame& f) {
  double lo = 1e300, hi = -1e300;
  for (const auto& p : r) {
    const double x = f.to(p).x();
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  return {lo, hi};
}

/// The paper's direction: along the longest edge of the part's outer boundary.
double longest_edge(const Ring& r) {
  double best = -1.0, angle = 0.0;
  for (std::size_t i = 1; i < r.size(); ++i) {
    const double dx = r[i].x() - r[i - 1].x(), dy = r[i].y() - r[i - 1].y();
    const double len = std::hypot(dx, dy);
    if (len > best + 1e-9) best = len, angle = axis(std::atan2(dy, dx));
  }
  return angle;
}

/// The edge direction of the convex hull with the fewest lines (the narrowest width is across a hull
/// edge); ties go to the longer edge.
double fewest_lines(const Ring& r, double spacing) {
  Ring hull;
  bg::convex_hull(r, hull);
  int best = 1 << 30;
  double best_len = -1.0, angle = longest_edge(r);
  for (std::size_t i = 1; i < hull.size(); ++i) {
    const double dx = hull[i].x() - hull[i - 1].x(), dy = hull[i].y() - hull[i - 1].y();
    const double len = std::hypot(dx, dy);
    if (len < 1e-6) continue;
    const double a = axis(std::atan2(dy, dx));
    const auto [lo, hi] = x_extent(hull, Frame(a));
    const int n = boustro::leg_count(hi - lo, spacing);
    if (n < best || (n == best && len > best_len + 1e-9)) best = n, best_len = len, angle = a;
  }
  return angle;
}

MultiPolygon grown(const MultiPolygon& zones, double d) {
  if (zones.empty()) return {};
  MultiPolygon z = zones, out;
  boustro::remove_near_duplicates(z);
  bg::buffer(z, out, bg::strategy::buffer::distance_symmetric<double>(d),
             bg::strategy::buffer::side_straight(), bg::strategy::buffer::join_miter(),
             bg::strategy::buffer::end_flat(), bg::strategy::buffer::point_square());
  return out;
}

Box frame_box(const MultiPolygon& m) {
  Box b;
  bg::envelope(m, b);
  return b;
}

}  // namespace

Lines build_lines(const MultiPolygon& free, const MultiPolygon& no_fly, double spacing, Direction dir,
                  std::optional<double> fixed, const Context& ctx) {
  Lines out;
  // lines first counted, so that a tiny spacing is refused before anything is allocated
  std::size_t total = 0;
  std::vector<double> angles;
  for (const auto& poly : free) {
    const double a = fixed                    ? axis(*fixed)
                     : dir == Direction::Auto ? fewest_lines(poly.outer(), spacing)
                                              : longest_edge(poly.outer());
    angles.push_back(a);
    const auto [lo, hi] = x_extent(poly.outer(), Frame(a));
    total += static_cast<std::size_t>(std::min(1e9, (hi - lo) / spacing + 2.0));
  }
  if (total > kMaxLines)
    throw InputError("spacing_m", "the milp planner plans at most " + std::to_string(kMaxLines) +
                                      " lines; this spacing gives about " + std::to_string(total));
  const MultiPolygon zones = grown(no_fly, kNoFlyClearanceM);
  for (std::size_t c = 0; c < free.size(); ++c) {
    stop_check(ctx);
    Part part;
    part.angle = angles[c];
    part.frame = Frame(part.angle);
    MultiPolygon clear{free[c]};
    if (!zones.empty()) {
      MultiPolygon d;
      bg::difference(clear, zones, d);
      clear = std::move(d);
    }
    const MultiPolygon clear_f = boustro::to_frame(clear, part.frame);
    const Box fb = frame_box(boustro::to_frame(MultiPolygon{free[c]}, part.frame));
    part.xs = boustro::leg_positions(fb.min_corner().x(), fb.max_corner().x(), spacing);
    for (std::size_t l = 0; l < part.xs.size(); ++l) {
      if (l % 64 == 63) stop_check(ctx);
      const double x = part.xs[l];
      bg::model::linestring<Point> line{{x, fb.min_corner().y() - 1.0}, {x, fb.max_corner().y() + 1.0}};
      bg::model::multi_linestring<bg::model::linestring<Point>> pieces;
      bg::intersection(line, clear_f, pieces);
      std::vector<std::pair<double, double>> iv;
      for (const auto& ls : pieces) {
        if (ls.empty()) continue;
        double y0 = 1e300, y1 = -1e300;
        for (const auto& p : ls) y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
        iv.emplace_back(y0, y1);
      }
      std::sort(iv.begin(), iv.end());
      std::vector<std::pair<double, double>> merged;
      for (const auto& v : iv)
        if (!merged.empty() && v.first <= merged.back().second + 1e-9)
          merged.back().second = std::max(merged.back().second, v.second);
        else
          merged.push_back(v);
      bool any = false;
      for (const auto& [y0, y1] : merged) {
        if (y1 - y0 < 1e-3) continue;
        Segment s;
        s.a = part.frame.from(Point{x, y0});
        s.b = part.frame.from(Point{x, y1});
        s.part = static_cast<int>(c);
        s.line = static_cast<int>(l);
        out.segments.push_back(s);
        any = true;
      }
      if (any) ++part.lines_with_segments;
    }
    out.parts.push_back(std::move(part));
  }
  return out;
}

std::vector<MultiPolygon> regions(const Lines& lines, const MultiPolygon& free, const std::vector<int>& owner,
                                  int uavs, const Context& ctx) {
  std::vector<MultiPolygon> out(static_cast<std::size_t>(uavs));
  const double total = bg::area(free);
  for (std::size_t c = 0; c < lines.parts.size() && c < free.size(); ++c) {
    const Part& part = lines.parts[c];
    if (part.xs.empty()) continue;
    const MultiPolygon free_f = boustro::to_frame(MultiPolygon{free[c]}, part.frame);
    const Box fb = frame_box(free_f);
    const double ylo = fb.min_corner().y() - 1.0, yhi = fb.max_corner().y() + 1.0;
    // strip bounds: the midlines between neighbouring lines, the outer ones beyond the part
    std::vector<double> bounds{fb.min_corner().x() - 1.0};
    for (std::size_t l = 1; l < part.xs.size(); ++l) bounds.push_back(0.5 * (part.xs[l - 1] + part.xs[l]));
    bounds.push_back(fb.max_corner().x() + 1.0);
    // segments of this part by line
    std::vector<std::vector<std::size_t>> by_line(part.xs.size());
    for (std::size_t s = 0; s < lines.segments.size(); ++s)
      if (lines.segments[s].part == static_cast<int>(c))
        by_line[static_cast<std::size_t>(lines.segments[s].line)].push_back(s);
    std::vector<MultiPolygon> mine(static_cast<std::size_t>(uavs));
    auto mid_of = [&](std::size_t s) {
      const Segment& seg = lines.segments[s];
      return part.frame.to(Point{0.5 * (seg.a.x() + seg.b.x()), 0.5 * (seg.a.y() + seg.b.y())});
    };
    // Each UAV's cells are united as boxes in the frame (axis-aligned, sides on the same coordinates),
    // and the union is cut from the free area once, keeping the pieces its segments run through:
    // uniting pieces already cut from the free area (sides with rounding noise) left polygons that
    // only touch unmerged or lost whole bands (2 km square at 2 m, 10 UAVs: one UAV's 178 m band)
    std::vector<MultiPolygon> boxes(static_cast<std::size_t>(uavs));
    std::vector<std::vector<std::size_t>> through(static_cast<std::size_t>(uavs));
    auto add = [&](int who, const Box& box, const std::vector<std::size_t>& segs_in) {
      Polygon b;
      bg::convert(box, b);
      MultiPolygon next;
      bg::union_(boxes[static_cast<std::size_t>(who)], b, next);
      boxes[static_cast<std::size_t>(who)] = std::move(next);
      auto& t = through[static_cast<std::size_t>(who)];
      t.insert(t.end(), segs_in.begin(), segs_in.end());
    };
    // Each segment's cell: its strip between the midpoints to the segments below and above it on its
    // line; a run of neighbouring lines that each hold one segment of the same UAV is one box.
    int run_owner = -1;
    std::size_t run_first = 0, run_last = 0;
    std::vector<std::size_t> run_segs;
    auto flush = [&] {
      if (run_owner >= 0)
        add(run_owner, Box{{bounds[run_first], ylo}, {bounds[run_last + 1], yhi}}, run_segs);
      run_owner = -1;
      run_segs.clear();
    };
    for (std::size_t l = 0; l < part.xs.size(); ++l) {
      if (l % 32 == 31) stop_check(ctx);
      const auto& on = by_line[l];
      if (on.size() == 1 && owner[on[0]] >= 0 && owner[on[0]] < uavs) {
        if (run_owner == owner[on[0]] && run_last + 1 == l) {
          run_last = l;
        } else {
          flush();
          run_owner = owner[on[0]];
          run_first = run_last = l;
        }
        run_segs.push_back(on[0]);
        continue;
      }
      flush();
      auto span = [&](std::size_t s) {
        const double y0 = part.frame.to(lines.segments[s].a).y(), y1 = part.frame.to(lines.segments[s].b).y();
        return std::pair{std::min(y0, y1), std::max(y0, y1)};
      };
      // The side between the cells of two segments of a line: the cut point where they touch; across a
      // gap (a hole or a no-fly zone, cut from the cells later) the roundest coordinate in its middle
      // half, so that the sides of neighbouring lines' cells across one obstacle are equal. Their
      // midpoints differ by a fraction of a millimetre from line to line where the field is not
      // aligned with the frame (0.2 mm on the arctic hard shape), and such nearly collinear sides made
      // Boost.Geometry's union of a UAV's cells come out empty (that field lost 16 % of its area).
      auto side = [](double end, double next) {
        if (next - end < 1e-6) return 0.5 * (end + next);
        const double a = end + 0.25 * (next - end), b = next - 0.25 * (next - end);
        for (double step = std::pow(10.0, std::ceil(std::log10(next - end))); step > 1e-3; step /= 10.0)
          if (const double m = std::ceil(a / step) * step; m <= b) return m;
        return 0.5 * (end + next);
      };
      for (std::size_t i = 0; i < on.size(); ++i) {
        const int who = owner[on[i]];
        if (who < 0 || who >= uavs) continue;
        const double lo = i == 0 ? ylo : side(span(on[i - 1]).second, span(on[i]).first);
        const double hi = i + 1 == on.size() ? yhi : side(span(on[i]).second, span(on[i + 1]).first);
        add(who, Box{{bounds[l], lo}, {bounds[l + 1], hi}}, {on[i]});
      }
    }
    flush();
    for (int k = 0; k < uavs; ++k) {
      MultiPolygon pieces;
      bg::intersection(free_f, boxes[static_cast<std::size_t>(k)], pieces);
      const auto& t = through[static_cast<std::size_t>(k)];
      for (auto& piece : pieces)
        if (std::any_of(t.begin(), t.end(), [&](std::size_t s) { return bg::covered_by(mid_of(s), piece); }))
          mine[static_cast<std::size_t>(k)].push_back(std::move(piece));
    }
    for (int k = 0; k < uavs; ++k) {
      MultiPolygon world = boustro::from_frame(mine[static_cast<std::size_t>(k)], part.frame);
      bg::correct(world);
      boustro::remove_near_duplicates(world);
      std::erase_if(world, [&](const Polygon& p) { return std::abs(bg::area(p)) < 1e-6 * total; });
      for (auto& p : world) out[static_cast<std::size_t>(k)].push_back(std::move(p));
    }
  }
  return out;
}

std::vector<std::vector<int>> adjacency(const Lines& lines) {
  const auto& segs = lines.segments;
  std::vector<std::vector<int>> adj(segs.size());
  auto span = [&](const Segment& s) {
    const Frame& f = lines.parts[static_cast<std::size_t>(s.part)].frame;
    const double y0 = f.to(s.a).y(), y1 = f.to(s.b).y();
    return std::pair{std::min(y0, y1), std::max(y0, y1)};
  };
  // segments are part by part, line by line: the previous line's segments are just before
  std::size_t prev_begin = 0, prev_end = 0, cur_begin = 0;
  for (std::size_t s = 0; s < segs.size(); ++s) {
    if (s > 0 && (segs[s].part != segs[s - 1].part || segs[s].line != segs[s - 1].line)) {
      const bool next_line = segs[s].part == segs[s - 1].part && segs[s].line == segs[s - 1].line + 1;
      prev_begin = next_line ? cur_begin : s;
      prev_end = next_line ? s : s;
      cur_begin = s;
      if (segs[s].part != segs[s - 1].part) {
        adj[s].push_back(static_cast<int>(s - 1));
        adj[s - 1].push_back(static_cast<int>(s));
      }
    }
    const auto [lo, hi] = span(segs[s]);
    // the two pieces of a cut segment touch end to end on their line
    if (s > cur_begin && std::abs(span(segs[s - 1]).second - lo) < 1e-6) {
      adj[s].push_back(static_cast<int>(s - 1));
      adj[s - 1].push_back(static_cast<int>(s));
    }
    for (std::size_t t = prev_begin; t < prev_end; ++t) {
      const auto [tlo, thi] = span(segs[t]);
      if (std::max(lo, tlo) < std::min(hi, thi)) {
        adj[s].push_back(static_cast<int>(t));
        adj[t].push_back(static_cast<int>(s));
      }
    }
  }
  return adj;
}

std::vector<Segment> extended_for_coverage(const Lines& lines, const MultiPolygon& area,
                                           const MultiPolygon& no_fly, double footprint, double clearance) {
  std::vector<Segment> out = lines.segments;
  const double len = 0.5 * footprint;
  if (!(len > 0.01)) return out;
  const MultiPolygon zones = grown(no_fly, clearance);
  auto extend = [&](Point end, Point other) {
    const double d = boustro::dist(end, other);
    if (d < 1e-9) return end;
    const Point dir{(end.x() - other.x()) / d, (end.y() - other.y()) / d};
    // the end is on the outer boundary when just beyond it is outside the area (and not in a zone)
    const Point probe{end.x() + 0.05 * dir.x(), end.y() + 0.05 * dir.y()};
    if (bg::covered_by(probe, area)) return end;
    const Point far{end.x() + len * dir.x(), end.y() + len * dir.y()};
    if (!zones.empty() && bg::intersects(bg::model::segment<Point>{end, far}, zones)) return end;
    return far;
  };
  for (auto& s : out) {
    const Segment o = s;
    s.a = extend(o.a, o.b);
    s.b = extend(o.b, o.a);
  }
  return out;
}

}  // namespace uavcover::planners::milp
