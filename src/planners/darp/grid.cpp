#include "planners/darp/grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace uavcover::grid {

namespace {

struct QEdge {
  double xa, ya, xb, yb;  // ya <= yb
};

template <typename Ring>
void add_ring(const Ring& ring, std::vector<Edge>& out) {
  for (std::size_t i = 1; i < ring.size(); ++i) out.push_back({ring[i - 1], ring[i]});
  // Boost rings are closed; if one isn't, close it
  if (ring.size() > 2 && !bg::equals(ring.front(), ring.back())) out.push_back({ring.back(), ring.front()});
}

void add_multi(const MultiPolygon& mp, std::vector<Edge>& out) {
  for (const auto& poly : mp) {
    add_ring(poly.outer(), out);
    for (const auto& in : poly.inners()) add_ring(in, out);
  }
}

/// Even-odd scanline fill: out[row * ncols + col] = 1 when lattice point
/// (xfirst + col*step, yfirst + row*step) lies inside the rings formed by `edges`
/// (sorted by ya).
template <typename RowFn>
void scan_rows(const std::vector<QEdge>& edges, double xfirst, double yfirst, double step, int ncols,
               int nrows, RowFn&& fn) {
  std::vector<int> active;
  std::vector<double> xs;
  std::size_t next = 0;
  for (int row = 0; row < nrows; ++row) {
    const double y = yfirst + row * step;
    while (next < edges.size() && edges[next].ya <= y) active.push_back(static_cast<int>(next++));
    xs.clear();
    for (std::size_t k = 0; k < active.size();) {
      const QEdge& e = edges[active[k]];
      if (e.yb <= y) {
        active[k] = active.back();
        active.pop_back();
        continue;
      }
      xs.push_back(e.xa + (y - e.ya) * (e.xb - e.xa) / (e.yb - e.ya));
      ++k;
    }
    std::sort(xs.begin(), xs.end());
    for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
      const int lo = std::max(0, static_cast<int>(std::ceil((xs[k] - xfirst) / step)));
      const int hi = std::min(ncols - 1, static_cast<int>(std::floor((xs[k + 1] - xfirst) / step)));
      if (lo <= hi) fn(row, lo, hi);
    }
  }
}

void scan(const std::vector<QEdge>& edges, double xfirst, double yfirst, double step, int ncols, int nrows,
          std::vector<std::uint8_t>& out) {
  out.assign(static_cast<std::size_t>(ncols) * nrows, 0);
  scan_rows(edges, xfirst, yfirst, step, ncols, nrows, [&](int row, int lo, int hi) {
    std::uint8_t* line = out.data() + static_cast<std::size_t>(row) * ncols;
    std::fill(line + lo, line + hi + 1, 1);
  });
}

std::vector<QEdge> to_q(const std::vector<Edge>& edges, const Grid& g) {
  std::vector<QEdge> out;
  out.reserve(edges.size());
  for (const auto& e : edges) {
    const Point a = g.local_to_q(e.a), b = g.local_to_q(e.b);
    if (a.y() <= b.y())
      out.push_back({a.x(), a.y(), b.x(), b.y()});
    else
      out.push_back({b.x(), b.y(), a.x(), a.y()});
  }
  return out;
}

inline double orient(double px, double py, double qx, double qy, double rx, double ry) {
  return (qx - px) * (ry - py) - (qy - py) * (rx - px);
}

/// Closed segment intersection (touching counts).
bool segments_cross(double ax, double ay, double bx, double by, double cx, double cy, double dx, double dy) {
  if (std::max(ax, bx) < std::min(cx, dx) || std::max(cx, dx) < std::min(ax, bx) ||
      std::max(ay, by) < std::min(cy, dy) || std::max(cy, dy) < std::min(ay, by))
    return false;
  const double d1 = orient(cx, cy, dx, dy, ax, ay), d2 = orient(cx, cy, dx, dy, bx, by);
  const double d3 = orient(ax, ay, bx, by, cx, cy), d4 = orient(ax, ay, bx, by, dx, dy);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  // degenerate: an endpoint on the other segment (bounding boxes overlap already)
  return d1 == 0 || d2 == 0 || d3 == 0 || d4 == 0;
}

/// Squared distance from (px, py) to segment a-b.
double point_segment_d2(double px, double py, double ax, double ay, double bx, double by) {
  const double vx = bx - ax, vy = by - ay, l2 = vx * vx + vy * vy;
  const double t = l2 > 0 ? std::clamp(((px - ax) * vx + (py - ay) * vy) / l2, 0.0, 1.0) : 0.0;
  const double dx = ax + t * vx - px, dy = ay + t * vy - py;
  return dx * dx + dy * dy;
}

/// Segments a-b and c-d meet or come closer than `gap`.
bool segments_meet(double ax, double ay, double bx, double by, double cx, double cy, double dx, double dy,
                   double gap) {
  if (std::max(ax, bx) + gap < std::min(cx, dx) || std::max(cx, dx) + gap < std::min(ax, bx) ||
      std::max(ay, by) + gap < std::min(cy, dy) || std::max(cy, dy) + gap < std::min(ay, by))
    return false;
  if (segments_cross(ax, ay, bx, by, cx, cy, dx, dy)) return true;
  const double g2 = gap * gap;
  return point_segment_d2(ax, ay, cx, cy, dx, dy) < g2 || point_segment_d2(bx, by, cx, cy, dx, dy) < g2 ||
         point_segment_d2(cx, cy, ax, ay, bx, by) < g2 || point_segment_d2(dx, dy, ax, ay, bx, by) < g2;
}

/// Coverage estimate on a KxK sample lattice per mega-cell (K <= 16, step dn/K, aligned with the
/// grid): samples in free cells are covered; samples of other cells are covered when they lie
/// within ds/4 of a free neighbour (footprint w = 1.5 ds reaches ds/4 beyond a cell's outer
/// sub-cell centres).
double estimate_coverage(const Grid& g, const std::vector<QEdge>& fe_sorted, int K) {
  static const auto popcount16 = [] {
    std::array<std::uint8_t, 1 << 16> t{};
    for (unsigned i = 1; i < t.size(); ++i) t[i] = static_cast<std::uint8_t>(t[i >> 1] + (i & 1));
    return t;
  }();
  const int rows = g.rows, cols = g.cols;
  int band = 0;  // samples per side within ds/4 = dn/8 of the cell edge
  while ((band + 0.5) / K < 0.125) ++band;
  const std::uint16_t full = static_cast<std::uint16_t>((1u << K) - 1);
  const std::uint16_t low = static_cast<std::uint16_t>((1u << band) - 1);
  const std::uint16_t high = static_cast<std::uint16_t>(low << (K - band));
  std::vector<std::uint16_t> bits(static_cast<std::size_t>(rows) * cols * K, 0);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      std::uint16_t* b = bits.data() + static_cast<std::size_t>(g.idx(r, c)) * K;
      if (g.free[g.idx(r, c)]) {
        std::fill(b, b + K, full);
        continue;
      }
      std::uint16_t side = 0;
      if (g.free_at(r, c - 1)) side |= low;
      if (g.free_at(r, c + 1)) side |= high;
      for (int a = 0; a < K; ++a) b[a] = side;
      const bool dn_ = g.free_at(r - 1, c), up = g.free_at(r + 1, c);
      const std::uint16_t dl = g.free_at(r - 1, c - 1) ? low : 0, dr = g.free_at(r - 1, c + 1) ? high : 0;
      const std::uint16_t ul = g.free_at(r + 1, c - 1) ? low : 0, ur = g.free_at(r + 1, c + 1) ? high : 0;
      for (int a = 0; a < band; ++a) {
        b[a] |= dn_ ? full : static_cast<std::uint16_t>(dl | dr);
        b[K - 1 - a] |= up ? full : static_cast<std::uint16_t>(ul | ur);
      }
    }
  const double step = g.dn / K;
  long inside = 0, covered = 0;
  scan_rows(fe_sorted, g.x0 + 0.5 * step, g.y0 + 0.5 * step, step, K * cols, K * rows,
            [&](int row, int lo, int hi) {
              inside += hi - lo + 1;
              const int r = row / K, a = row % K;
              const std::uint16_t* brow = bits.data() + static_cast<std::size_t>(r) * cols * K + a;
              for (int c = lo / K; c <= hi / K; ++c) {
                unsigned v = brow[static_cast<std::size_t>(c) * K];
                const int x0 = std::max(lo, K * c) - K * c, x1 = std::min(hi, K * c + K - 1) - K * c;
                v &= ((1u << (x1 + 1)) - 1) & ~((1u << x0) - 1);
                covered += popcount16[v];
              }
            });
  return inside ? static_cast<double>(covered) / inside : 0.0;
}

}  // namespace

Prepared prepare(const MultiPolygon& free, const MultiPolygon& no_fly, double ds, Mode mode) {
  Prepared p;
  add_multi(free, p.free_edges);
  add_multi(no_fly, p.nfz_edges);
  p.free_area = bg::area(free);
  p.free_parts = static_cast<int>(free.size());
  p.ds = ds;
  p.mode = mode;
  return p;
}

int Grid::neighbours(int k, std::array<int, 4>& out) const {
  int n = 0;
  const int r = k / cols, c = k % cols;
  if (link[k] & 1) out[n++] = k + 1;
  if (link[k] & 2) out[n++] = k + cols;
  if (c > 0 && (link[k - 1] & 1)) out[n++] = k - 1;
  if (r > 0 && (link[k - cols] & 2)) out[n++] = k - cols;
  return n;
}

Grid rasterize(const Prepared& prep, double sx, double sy, double theta_deg) {
  Grid g;
  g.ds = prep.ds;
  g.dn = 2 * prep.ds;
  g.sx = sx;
  g.sy = sy;
  g.theta_deg = theta_deg;
  const double t = theta_deg * std::numbers::pi / 180.0;
  g.cos_t = std::cos(t);
  g.sin_t = std::sin(t);

  std::vector<QEdge> fe = to_q(prep.free_edges, g);
  if (fe.empty()) return g;
  g.px0 = g.py0 = std::numeric_limits<double>::infinity();
  g.px1 = g.py1 = -std::numeric_limits<double>::infinity();
  for (const auto& e : fe) {
    g.px0 = std::min({g.px0, e.xa, e.xb});
    g.px1 = std::max({g.px1, e.xa, e.xb});
    g.py0 = std::min(g.py0, e.ya);
    g.py1 = std::max(g.py1, e.yb);
  }
  const double dn = g.dn, ds = g.ds;
  g.x0 = std::floor(g.px0 / dn) * dn;
  g.y0 = std::floor(g.py0 / dn) * dn;
  g.cols = std::max(1, static_cast<int>(std::ceil((g.px1 - g.x0) / dn - 1e-12)));
  g.rows = std::max(1, static_cast<int>(std::ceil((g.py1 - g.y0) / dn - 1e-12)));
  const int rows = g.rows, cols = g.cols;
  const std::size_t n = static_cast<std::size_t>(rows) * cols;
  g.free.assign(n, 0);
  g.link.assign(n, 0);

  auto by_ya = [](const QEdge& a, const QEdge& b) { return a.ya < b.ya; };
  std::sort(fe.begin(), fe.end(), by_ya);
  std::vector<QEdge> ne;  // no-fly zone edges
  if (!prep.nfz_edges.empty()) {
    ne = to_q(prep.nfz_edges, g);
    std::sort(ne.begin(), ne.end(), by_ya);
  }

  std::vector<std::uint8_t> sub;
  const int scols = 2 * cols;
  if (prep.mode == Mode::Strict) {
    scan(fe, g.x0 + 0.5 * ds, g.y0 + 0.5 * ds, ds, scols, 2 * rows, sub);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        const std::size_t b = static_cast<std::size_t>(2 * r) * scols + 2 * c;
        g.free[g.idx(r, c)] = sub[b] & sub[b + 1] & sub[b + scols] & sub[b + scols + 1];
      }
  } else {
    scan(fe, g.x0 + 0.5 * dn, g.y0 + 0.5 * dn, dn, cols, rows, g.free);
    if (!ne.empty()) {  // strict mode: the free area's scan excludes the zones already
      scan(ne, g.x0 + 0.5 * ds, g.y0 + 0.5 * ds, ds, scols, 2 * rows, sub);
      for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) {
          const std::size_t b = static_cast<std::size_t>(2 * r) * scols + 2 * c;
          if (sub[b] | sub[b + 1] | sub[b + scols] | sub[b + scols + 1]) g.free[g.idx(r, c)] = 0;
        }
    }
  }

  // Path segments that would cross an obstacle edge, or come closer than `gap` to it: block the cell
  // (its own square) or drop the link (connectors to the right/upper neighbour). Strict mode: the free
  // area's edges (touching blocks), and in both modes the no-fly zones' edges kept kClearance away.
  std::vector<std::uint8_t> no_link(n, 0);  // bit 0 right, bit 1 up
  const double h = 0.5 * ds;
  const auto block = [&](const std::vector<QEdge>& barrier, double gap) {
    for (const auto& e : barrier) {
      // an edge no longer than dn in |dx| + |dy| is one piece (skips hypot for the many small zones' edges)
      const double dx = std::fabs(e.xb - e.xa), dy = std::fabs(e.yb - e.ya);
      const int pieces =
          dx + dy <= dn ? 1
                        : std::max(1, static_cast<int>(std::ceil(std::hypot(e.xb - e.xa, e.yb - e.ya) / dn)));
      for (int p = 0; p < pieces; ++p) {
        const double t0 = static_cast<double>(p) / pieces, t1 = static_cast<double>(p + 1) / pieces;
        const double ax = e.xa + t0 * (e.xb - e.xa), ay = e.ya + t0 * (e.yb - e.ya);
        const double bx = e.xa + t1 * (e.xb - e.xa), by = e.ya + t1 * (e.yb - e.ya);
        const double bx0 = std::min(ax, bx), bx1 = std::max(ax, bx), by0 = std::min(ay, by),
                     by1 = std::max(ay, by);
        const double m = gap;
        const int c0 = std::max(0, static_cast<int>(std::ceil((bx0 - m - g.x0 - h) / dn - 1.0)));
        const int c1 = std::min(cols - 1, static_cast<int>(std::floor((bx1 + m - g.x0 - h) / dn)));
        const int r0 = std::max(0, static_cast<int>(std::ceil((by0 - m - g.y0 - h) / dn - 1.0)));
        const int r1 = std::min(rows - 1, static_cast<int>(std::floor((by1 + m - g.y0 - h) / dn)));
        for (int r = r0; r <= r1; ++r)
          for (int c = c0; c <= c1; ++c) {
            const int k = g.idx(r, c);
            if (!g.free[k]) continue;
            const double X = g.x0 + c * dn, Y = g.y0 + r * dn;
            const double L = X + h, R = X + 3 * h, B = Y + h, T = Y + 3 * h;
            auto hit = [&](double px, double py, double qx, double qy) {
              return segments_meet(ax, ay, bx, by, px, py, qx, qy, gap);
            };
            if (hit(L, B, R, B) || hit(L, T, R, T) || hit(L, B, L, T) || hit(R, B, R, T)) {
              g.free[k] = 0;
              continue;
            }
            if (hit(R, B, R + ds, B) || hit(R, T, R + ds, T)) no_link[k] |= 1;
            if (hit(L, T, L, T + ds) || hit(R, T, R, T + ds)) no_link[k] |= 2;
          }
      }
    }
  };
  if (prep.mode == Mode::Strict) block(fe, 0.0);
  block(ne, kClearance);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int k = g.idx(r, c);
      if (!g.free[k]) continue;
      ++g.free_cells;
      if (g.fr1 < 0) g.fr0 = r, g.fc0 = c;
      g.fr1 = r;
      g.fc0 = std::min(g.fc0, c);
      g.fc1 = std::max(g.fc1, c);
      if (c + 1 < cols && g.free[k + 1] && !(no_link[k] & 1)) g.link[k] |= 1;
      if (r + 1 < rows && g.free[k + cols] && !(no_link[k] & 2)) g.link[k] |= 2;
    }
  if (prep.estimate_coverage)
    g.coverage_estimate = estimate_coverage(g, fe, std::clamp(prep.estimate_samples, 1, 16));
  return g;
}

double coverage_proxy(const Prepared& prep, const Grid& g, int samples_per_cell) {
  if (g.free_cells == 0) return 0.0;
  std::vector<QEdge> fe = to_q(prep.free_edges, g);
  std::sort(fe.begin(), fe.end(), [](const QEdge& a, const QEdge& b) { return a.ya < b.ya; });
  return estimate_coverage(g, fe, std::clamp(samples_per_cell, 1, 16));
}

int components(const Grid& g, std::vector<int>& label) {
  const int n = g.rows * g.cols;
  label.assign(n, -1);
  std::vector<int> stack;
  std::array<int, 4> nb{};
  int count = 0;
  for (int k = 0; k < n; ++k) {
    if (!g.free[k] || label[k] >= 0) continue;
    label[k] = count;
    stack.push_back(k);
    while (!stack.empty()) {
      const int u = stack.back();
      stack.pop_back();
      const int m = g.neighbours(u, nb);
      for (int i = 0; i < m; ++i)
        if (label[nb[i]] < 0) {
          label[nb[i]] = count;
          stack.push_back(nb[i]);
        }
    }
    ++count;
  }
  return count;
}

Score score(const Prepared& prep, const Grid& g, const Weights& w) {
  Score s;
  s.free_cells = g.free_cells;
  if (g.rows == 0 || prep.free_area <= 0) return s;
  const double dn = g.dn;
  s.J1 = g.free_cells * dn * dn / prep.free_area;
  const double X1 = g.x0 + g.cols * dn, Y1 = g.y0 + g.rows * dn;
  s.J2 = prep.free_area / ((X1 - g.x0) * (Y1 - g.y0));
  if (g.free_cells > 0) {
    const double ex0 = g.x0 + g.fc0 * dn, ex1 = g.x0 + (g.fc1 + 1) * dn;
    const double ey0 = g.y0 + g.fr0 * dn, ey1 = g.y0 + (g.fr1 + 1) * dn;
    const double bx = std::max(ex1, g.px1) - std::min(ex0, g.px0);
    const double by = std::max(ey1, g.py1) - std::min(ey0, g.py0);
    s.J3 = std::fabs((ex1 - g.px1) - (g.px0 - ex0)) / (2 * bx) +
           std::fabs((ey1 - g.py1) - (g.py0 - ey0)) / (2 * by);
  }
  std::vector<int> label;
  s.components = components(g, label);
  s.J = w.a * s.J1 + w.b * s.J2 - w.c * s.J3;
  if (s.components > std::max(1, prep.free_parts)) s.J -= w.disconnected_penalty;
  s.key = s.J - w.length_weight * s.J1;
  if (w.coverage_weight > 0) {
    s.coverage = g.coverage_estimate;
    s.key += w.coverage_weight * s.coverage;
  }
  return s;
}

}  // namespace uavcover::grid
