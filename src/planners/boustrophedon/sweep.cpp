#include "planners/boustrophedon/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace uavcover::planners::boustro {

namespace {

constexpr double kPi = std::numbers::pi;

/// Normalises a direction to [0, pi) (legs have no heading).
double axis(double a) {
  a = std::fmod(a, kPi);
  if (a < 0) a += kPi;
  if (a >= kPi - 1e-12) a = 0.0;
  return a;
}

double cross(Point o, Point a, Point b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

/// Shortest path from a to b (a.x < b.x) on the inside of a chain: below the upper chain
/// (`below` = true) or above the lower chain. Returns the intermediate vertices only.
std::vector<Point> taut(const std::vector<Point>& chain, Point a, Point b, bool below) {
  std::vector<Point> hull{a};
  auto it =
      std::upper_bound(chain.begin(), chain.end(), a.x(), [](double v, const Point& p) { return v < p.x(); });
  auto push = [&](Point p) {
    while (hull.size() >= 2) {
      const double c = cross(hull[hull.size() - 2], hull.back(), p);
      if (below ? c <= 0.0 : c >= 0.0)
        hull.pop_back();
      else
        break;
    }
    hull.push_back(p);
  };
  for (; it != chain.end() && it->x() < b.x(); ++it) push(*it);
  push(b);
  return {hull.begin() + 1, hull.end() - 1};
}

}  // namespace

int leg_count(double width, double spacing) {
  if (width <= spacing * (1.0 + 1e-3)) return 1;
  return static_cast<int>(std::ceil(width / spacing - 1e-3));  // a 0.1 % wider spacing, not a lane more
}

std::vector<double> leg_positions(double xmin, double xmax, double spacing) {
  const double w = xmax - xmin;
  const int n = leg_count(w, spacing);
  if (n == 1) return {0.5 * (xmin + xmax)};
  std::vector<double> xs(static_cast<std::size_t>(n));
  const double step = (w - spacing) / (n - 1);
  for (int k = 0; k < n; ++k) xs[static_cast<std::size_t>(k)] = xmin + 0.5 * spacing + k * step;
  return xs;
}

CellSweep choose_direction(const Monotone& cell, const Frame& frame, double preferred, double spacing,
                           std::optional<double> fixed) {
  preferred = axis(preferred);
  auto same = [](double a, double b) {
    const double d = std::abs(axis(a) - axis(b));
    return std::min(d, kPi - d) < 1e-9;
  };
  const Polygon world = monotone_polygon(cell, frame);
  const Ring& ring = world.outer();
  Ring hull;  // widths are the convex hull's
  bg::convex_hull(ring, hull);
  auto legs_for = [&](double a) {
    const Frame f(a);
    double lo = 1e300, hi = -1e300;
    for (const auto& p : hull) {
      const double x = f.to(p).x();
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    return leg_count(hi - lo, spacing);
  };
  auto in_frame = [&](double a) -> std::optional<CellSweep> {
    if (same(a, preferred)) return CellSweep{preferred, cell, legs_for(preferred)};
    const Frame f(a);
    auto mono = monotone_chains(to_frame(ring, f), 1e-6);
    if (!mono) return std::nullopt;
    return CellSweep{axis(a), std::move(*mono), legs_for(a)};
  };
  if (fixed) {
    if (auto s = in_frame(*fixed)) return *s;
    return CellSweep{preferred, cell, legs_for(preferred)};  // not monotone that way: keep the cell's
  }
  // the narrowest width is across a hull edge (rotating calipers); when no such direction leaves
  // the cell monotone, a 1-degree scan offers the others
  std::vector<double> cand{preferred};
  for (std::size_t i = 1; i < hull.size(); ++i) {
    const double dx = hull[i].x() - hull[i - 1].x(), dy = hull[i].y() - hull[i - 1].y();
    if (std::hypot(dx, dy) > 1e-6) cand.push_back(axis(std::atan2(dy, dx)));
  }
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1)
      for (int d = 0; d < 180; ++d) cand.push_back(d * kPi / 180.0);
    std::vector<std::pair<int, std::size_t>> ranked;
    for (std::size_t i = 0; i < cand.size(); ++i) ranked.emplace_back(legs_for(cand[i]), i);
    std::stable_sort(ranked.begin(), ranked.end());
    for (const auto& [legs, i] : ranked) {
      if (pass == 0 && legs > ranked.front().first) break;
      if (auto s = in_frame(cand[i])) return *s;
    }
  }
  return CellSweep{preferred, cell, legs_for(preferred)};
}

std::array<std::vector<Point>, 2> lawnmower(const CellSweep& sweep, const SweepOptions& opt,
                                            const Surroundings& env, const Context& ctx,
                                            std::array<std::vector<std::uint8_t>, 2>* camera_off) {
  const Frame f(sweep.angle);
  const Monotone& m = sweep.mono;
  const std::vector<double> xs = leg_positions(m.xmin(), m.xmax(), opt.spacing);
  const Point up = f.up();
  const double half_w = 0.5 * opt.footprint;

  // one end of a leg: strict point (frame and world) and extended point (world)
  struct End {
    Point frame_pt, strict, ext;
    bool extended = false;
  };
  auto overhang = [&](double x, bool upper) {
    const auto& c = upper ? m.upper : m.lower;
    const double lo = std::max(m.xmin(), x - 0.5 * opt.spacing),
                 hi = std::min(m.xmax(), x + 0.5 * opt.spacing);
    double best =
        upper ? std::max(chain_at(c, lo), chain_at(c, hi)) : std::min(chain_at(c, lo), chain_at(c, hi));
    for (const auto& p : c)
      if (p.x() > lo && p.x() < hi) best = upper ? std::max(best, p.y()) : std::min(best, p.y());
    const double here = chain_at(c, x);
    return upper ? best - here : here - best;
  };
  auto make_end = [&](double x, bool upper) {
    End e;
    e.frame_pt = Point{x, chain_at(upper ? m.upper : m.lower, x)};
    e.strict = f.from(e.frame_pt);
    e.ext = e.strict;
    if (opt.mode != Mode::Coverage) return e;
    const Point dir = upper ? up : Point{-up.x(), -up.y()};
    const Point probe{e.strict.x() + 0.05 * dir.x(), e.strict.y() + 0.05 * dir.y()};
    if (env.area && bg::covered_by(probe, *env.area)) return e;  // inside: another cell or region
    if (env.no_fly && !env.no_fly->empty() && bg::covered_by(probe, *env.no_fly)) return e;
    if (env.others && !env.others->empty() && bg::distance(e.strict, *env.others) <= opt.footprint) return e;
    double len = half_w;
    if (opt.overhang) len = std::max(len, overhang(x, upper) - half_w);
    if (!(len > 0.01)) return e;
    const Point far{e.strict.x() + len * dir.x(), e.strict.y() + len * dir.y()};
    if (auto hit = env.stops.first_hit(e.strict, far, 1e-4 / len)) len = *hit * len - 0.01;
    if (len < 0.01) return e;
    e.ext = Point{e.strict.x() + len * dir.x(), e.strict.y() + len * dir.y()};
    e.extended = true;
    return e;
  };
  std::vector<End> lows, highs;
  lows.reserve(xs.size());
  highs.reserve(xs.size());
  for (std::size_t k = 0; k < xs.size(); ++k) {
    if (k % 256 == 255) ctx.check();
    lows.push_back(make_end(xs[k], false));
    highs.push_back(make_end(xs[k], true));
  }

  auto connection_ok = [&](Point a, Point b) {
    if (env.no_fly_edges.first_hit(a, b, 0.0)) return false;
    if (env.others && !env.others->empty() &&
        bg::distance(bg::model::segment<Point>{a, b}, *env.others) < half_w)
      return false;
    return true;
  };
  std::array<std::vector<Point>, 2> out;
  if (opt.pattern != nullptr) {
    // the pattern options (docs/patterns.md): lanes in order (every other one first with alternate
    // transects), each extended at both ends by the turnaround (up to a no-fly zone), the camera off over
    // turns and turnarounds unless capture_in_turnaround
    const Pattern& pat = *opt.pattern;
    const std::uint8_t turn_off = pat.capture_in_turnaround ? 0 : 1;
    std::vector<std::size_t> order;
    for (std::size_t k = 0; k < xs.size(); k += pat.alternate_transects ? 2 : 1) order.push_back(k);
    if (pat.alternate_transects)
      for (std::size_t k = xs.size(); k-- > 0;)
        if (k % 2 == 1) order.push_back(k);
    auto reach = [&](Point p, Point u, double len) {  // how far the turnaround goes before a no-fly zone
      if (len <= 0) return 0.0;
      const Point far{p.x() + len * u.x(), p.y() + len * u.y()};
      if (auto hit = env.no_fly_edges.first_hit(p, far, 1e-4 / len)) return std::max(0.0, *hit * len - 0.01);
      return len;
    };
    for (int v = 0; v < 2; ++v) {
      auto& path = out[static_cast<std::size_t>(v)];
      std::vector<std::uint8_t> off;
      auto push = [&](Point p, std::uint8_t flag) {
        if (!path.empty() && dist(path.back(), p) <= 1e-9) return;
        if (!path.empty()) off.push_back(flag);
        path.push_back(p);
      };
      const End* prev_end = nullptr;
      bool prev_up = false;
      for (std::size_t i = 0; i < order.size(); ++i) {
        const std::size_t k = order[i];
        const bool going_up = ((i % 2 == 0) == (v == 0));
        const End& from = going_up ? lows[k] : highs[k];
        const End& to = going_up ? highs[k] : lows[k];
        const Point u = going_up ? up : Point{-up.x(), -up.y()};
        const double r0 = reach(from.ext, {-u.x(), -u.y()}, pat.turnaround_m);
        const double r1 = reach(to.ext, u, pat.turnaround_m);
        const Point pre{from.ext.x() - r0 * u.x(), from.ext.y() - r0 * u.y()};
        const Point post{to.ext.x() + r1 * u.x(), to.ext.y() + r1 * u.y()};
        if (prev_end != nullptr) {
          // the turn: straight where it may go, else back to the strict ends and along the boundary
          const bool adjacent = std::max(k, order[i - 1]) - std::min(k, order[i - 1]) == 1;
          const bool plain = pat.turnaround_m <= 0 && !prev_end->extended && !from.extended && adjacent;
          if (plain || !connection_ok(path.back(), pre)) {
            push(prev_end->strict, turn_off);
            const Point a = prev_end->frame_pt, b = from.frame_pt;
            const auto& chain = prev_up ? m.upper : m.lower;
            std::vector<Point> mid = a.x() < b.x() ? taut(chain, a, b, prev_up) : taut(chain, b, a, prev_up);
            if (a.x() >= b.x()) std::reverse(mid.begin(), mid.end());
            for (const auto& q : mid) push(f.from(q), turn_off);
            push(from.strict, turn_off);
          }
        }
        push(pre, turn_off);
        push(from.ext, turn_off);
        push(to.ext, 0);
        push(post, turn_off);
        prev_end = &to;
        prev_up = going_up;
      }
      if (camera_off != nullptr) (*camera_off)[static_cast<std::size_t>(v)] = std::move(off);
    }
    return out;
  }
  for (int v = 0; v < 2; ++v) {
    auto& path = out[static_cast<std::size_t>(v)];
    path.reserve(2 * xs.size() + 2);
    for (std::size_t k = 0; k < xs.size(); ++k) {
      if (k % 256 == 255) ctx.check();
      const bool going_up = ((k % 2 == 0) == (v == 0));
      const End& from = going_up ? lows[k] : highs[k];
      End to = going_up ? highs[k] : lows[k];
      if (k == 0) path.push_back(from.ext);
      if (k + 1 == xs.size()) {
        path.push_back(to.ext);
        break;
      }
      // connection to the next leg on the `going_up` side
      End next = going_up ? highs[k + 1] : lows[k + 1];
      if ((to.extended || next.extended) && !connection_ok(to.ext, next.ext)) {
        to.ext = to.strict;
        next.ext = next.strict;
        to.extended = next.extended = false;
      }
      path.push_back(to.ext);
      // both on the boundary: along it (taut inside the cell); else straight (checked above)
      if (!to.extended && !next.extended)
        for (const auto& q : taut(going_up ? m.upper : m.lower, to.frame_pt, next.frame_pt, going_up))
          path.push_back(f.from(q));
      path.push_back(next.ext);  // the next leg's start; its end comes in the next iteration
    }
    // remove consecutive duplicates
    std::vector<Point> clean;
    clean.reserve(path.size());
    for (const auto& p : path)
      if (clean.empty() || dist(clean.back(), p) > 1e-9) clean.push_back(p);
    path = std::move(clean);
  }
  return out;
}

}  // namespace uavcover::planners::boustro
