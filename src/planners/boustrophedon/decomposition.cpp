#include "planners/boustrophedon/decomposition.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace uavcover::planners::boustro {

namespace {

constexpr double kEps = 1e-6;  // metres: X values closer than this are one event line

/// X of the vertices where the boundary turns back in X (local extrema): the only places where the
/// number of intervals of a line X = const can change.
void critical_xs(const Ring& ring, std::vector<double>& out) {
  if (ring.size() < 4) return;
  const std::size_t n = ring.size() - 1;  // closed ring
  for (std::size_t i = 0; i < n; ++i) {
    const double x = ring[i].x();
    double before = 0.0, after = 0.0;
    for (std::size_t k = 1; k < n; ++k) {
      const double d = ring[(i + n - k) % n].x() - x;
      if (std::abs(d) > kEps) {
        before = d;
        break;
      }
    }
    for (std::size_t k = 1; k < n; ++k) {
      const double d = ring[(i + k) % n].x() - x;
      if (std::abs(d) > kEps) {
        after = d;
        break;
      }
    }
    if (before * after > 0.0) out.push_back(x);
  }
}

/// X of the reflex vertices (interior angle above 180 degrees; rings oriented as Boost's default,
/// so the region lies to the right of every ring).
void reflex_xs(const Ring& ring, std::vector<double>& out) {
  if (ring.size() < 4) return;
  const std::size_t n = ring.size() - 1;
  for (std::size_t i = 0; i < n; ++i) {
    const Point& a = ring[(i + n - 1) % n];
    const Point& b = ring[i];
    const Point& c = ring[(i + 1) % n];
    const double cr = (b.x() - a.x()) * (c.y() - b.y()) - (b.y() - a.y()) * (c.x() - b.x());
    if (cr > 1e-9 * dist(a, b) * dist(b, c)) out.push_back(b.x());
  }
}

/// Interval [y0, y1] where a monotone piece touches the line X = x, or an empty interval.
std::pair<double, double> side_interval(const Monotone& m, bool right) {
  const Point& lo = right ? m.lower.back() : m.lower.front();
  const Point& hi = right ? m.upper.back() : m.upper.front();
  return {lo.y(), hi.y()};
}

void append_chain(std::vector<Point>& acc, const std::vector<Point>& next) {
  for (const auto& p : next) {
    if (!acc.empty() && dist(acc.back(), p) < kEps) continue;
    acc.push_back(p);
  }
}

}  // namespace

double area(const Monotone& m) {
  double a = 0.0;
  auto trapezoids = [&a](const std::vector<Point>& c, double sign) {
    for (std::size_t i = 1; i < c.size(); ++i)
      a += sign * (c[i].x() - c[i - 1].x()) * 0.5 * (c[i].y() + c[i - 1].y());
  };
  trapezoids(m.upper, 1.0);
  trapezoids(m.lower, -1.0);
  return std::max(a, 0.0);
}

Monotone clip(const Monotone& m, double x0, double x1) {
  x0 = std::max(x0, m.xmin());
  x1 = std::min(x1, m.xmax());
  // A chain may step along X = x (a boundary edge parallel to the legs, e.g. at a reflex vertex, where
  // the cuts are): the piece right of x starts at the step's last point, the piece left of it ends at
  // its first (chain_at's). Starting both at the first point dropped the area between the step's ends
  // (a star's point, issue 26).
  auto right_of = [](const std::vector<Point>& c, double x) {
    const auto it =
        std::upper_bound(c.begin(), c.end(), x + 1e-9, [](double v, const Point& p) { return v < p.x(); });
    if (it != c.begin() && std::prev(it)->x() >= x - 1e-9) return std::prev(it)->y();
    return chain_at(c, x);
  };
  auto cut = [&](const std::vector<Point>& c) {
    std::vector<Point> out{Point{x0, right_of(c, x0)}};
    for (const auto& p : c)
      if (p.x() > x0 && p.x() < x1) out.push_back(p);
    out.emplace_back(x1, chain_at(c, x1));
    return out;
  };
  return Monotone{cut(m.lower), cut(m.upper)};
}

Decomposition decompose(const MultiPolygon& world, const Frame& frame, const Context& ctx, bool reflex_cuts) {
  Decomposition d;
  d.frame = frame;
  MultiPolygon m = to_frame(world, frame);
  remove_near_duplicates(m);
  if (m.empty()) return d;
  Box box;
  bg::envelope(m, box);
  std::vector<double> xs;
  for (const auto& poly : m) {
    critical_xs(poly.outer(), xs);
    for (const auto& in : poly.inners()) critical_xs(in, xs);
  }
  std::vector<double> reflex;
  if (reflex_cuts)
    for (const auto& poly : m) {
      reflex_xs(poly.outer(), reflex);
      for (const auto& in : poly.inners()) reflex_xs(in, reflex);
    }
  xs.insert(xs.end(), reflex.begin(), reflex.end());
  xs.push_back(box.min_corner().x());
  xs.push_back(box.max_corner().x());
  std::sort(xs.begin(), xs.end());
  std::vector<double> lines;
  for (double x : xs)
    if (lines.empty() || x - lines.back() > 100 * kEps) lines.push_back(x);

  // pieces of each slab between consecutive event lines
  struct Piece {
    Monotone m;
    int slab = 0;
    int next = -1, prev = -1;  // 1-1 neighbours (same cell)
    std::vector<int> right;    // touching pieces of the next slab
    int left_count = 0;
    int cell = -1;
  };
  std::vector<Piece> pieces;
  std::vector<std::vector<int>> by_slab(lines.size());
  const double y0 = box.min_corner().y() - 1.0, y1 = box.max_corner().y() + 1.0;
  for (std::size_t i = 0; i + 1 < lines.size(); ++i) {
    ctx.check();
    MultiPolygon out;
    bg::intersection(m, Box{Point{lines[i], y0}, Point{lines[i + 1], y1}}, out);
    for (const auto& poly : out) {
      auto mono = monotone_chains(poly.outer(), kEps);
      if (!mono) mono = monotone_chains(poly.outer(), 1e-4);
      if (!mono || area(*mono) < 1e-6) continue;
      // the sides on the slab's lines exactly on them (so that neighbours share them exactly)
      for (auto* c : {&mono->lower, &mono->upper})
        for (auto& q : *c)
          for (double x : {lines[i], lines[i + 1]})
            if (std::abs(q.x() - x) < 1e-6) q.x(x);
      by_slab[i].push_back(static_cast<int>(pieces.size()));
      pieces.push_back(Piece{std::move(*mono), static_cast<int>(i), -1, -1, {}, 0, -1});
    }
  }
  // touching pieces of consecutive slabs; 1-1 touches continue a cell
  for (std::size_t i = 0; i + 2 < lines.size(); ++i)
    for (int a : by_slab[i])
      for (int b : by_slab[i + 1]) {
        auto [a0, a1] = side_interval(pieces[static_cast<std::size_t>(a)].m, true);
        auto [b0, b1] = side_interval(pieces[static_cast<std::size_t>(b)].m, false);
        if (std::min(a1, b1) - std::max(a0, b0) > 1e-4) {
          pieces[static_cast<std::size_t>(a)].right.push_back(b);
          ++pieces[static_cast<std::size_t>(b)].left_count;
        }
      }
  for (auto& p : pieces)
    if (p.right.size() == 1 && pieces[static_cast<std::size_t>(p.right[0])].left_count == 1) {
      p.next = p.right[0];
      pieces[static_cast<std::size_t>(p.next)].prev = static_cast<int>(&p - pieces.data());
    }
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (pieces[i].prev >= 0) continue;
    Monotone cell;
    std::vector<double> cuts;
    const int id = static_cast<int>(d.cells.size());
    for (int k = static_cast<int>(i); k >= 0; k = pieces[static_cast<std::size_t>(k)].next) {
      auto& p = pieces[static_cast<std::size_t>(k)];
      p.cell = id;
      if (!cell.lower.empty()) cuts.push_back(p.m.xmin());
      append_chain(cell.lower, p.m.lower);
      append_chain(cell.upper, p.m.upper);
    }
    d.cells.push_back(std::move(cell));
    d.cuts.push_back(std::move(cuts));
  }
  for (const auto& p : pieces)
    if (p.next < 0)
      for (int b : p.right) d.links.push_back({p.cell, pieces[static_cast<std::size_t>(b)].cell, p.m.xmax()});
  return d;
}

}  // namespace uavcover::planners::boustro
