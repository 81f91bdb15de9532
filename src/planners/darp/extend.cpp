#include "planners/darp/extend.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <boost/geometry/index/rtree.hpp>

namespace uavcover::darp {

namespace {

namespace bgi = bg::index;
using Box = bg::model::box<Point>;
using Seg = bg::model::segment<Point>;

double cross(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

}  // namespace

struct LegExtender::Index {
  using Entry = std::pair<Box, std::size_t>;
  std::vector<grid::Edge> edges;
  bgi::rtree<Entry, bgi::rstar<16>> tree;

  explicit Index(std::vector<grid::Edge> e) : edges(std::move(e)) {
    std::vector<Entry> boxes;
    boxes.reserve(edges.size());
    for (std::size_t i = 0; i < edges.size(); ++i) {
      Box b;
      bg::envelope(Seg(edges[i].a, edges[i].b), b);
      boxes.emplace_back(b, i);
    }
    tree = decltype(tree)(boxes.begin(), boxes.end());
  }

  /// Segment a-b keeps at least `gap` from every edge.
  [[nodiscard]] bool clear(Point a, Point b, double gap) const {
    Box q;
    bg::envelope(Seg(a, b), q);
    q.min_corner() = Point(q.min_corner().x() - gap, q.min_corner().y() - gap);
    q.max_corner() = Point(q.max_corner().x() + gap, q.max_corner().y() + gap);
    const Seg s(a, b);
    for (auto it = tree.qbegin(bgi::intersects(q)); it != tree.qend(); ++it) {
      const auto& e = edges[it->second];
      if (bg::comparable_distance(s, Seg(e.a, e.b)) < gap * gap) return false;
    }
    return true;
  }

  /// Distance along the ray p + t d (|d| = 1, 0 <= t <= tmax) to its first crossing of an edge; tmax
  /// when none.
  [[nodiscard]] double first_hit(Point p, Point d, double tmax) const {
    const Point e(p.x() + tmax * d.x(), p.y() + tmax * d.y());
    Box q;
    bg::envelope(Seg(p, e), q);
    double best = tmax;
    for (auto it = tree.qbegin(bgi::intersects(q)); it != tree.qend(); ++it) {
      const auto& ed = edges[it->second];
      const double ux = ed.b.x() - ed.a.x(), uy = ed.b.y() - ed.a.y();
      const double den = cross(d.x(), d.y(), ux, uy);
      if (std::fabs(den) < 1e-12) continue;  // parallel
      const double wx = ed.a.x() - p.x(), wy = ed.a.y() - p.y();
      const double t = cross(wx, wy, ux, uy) / den, s = cross(wx, wy, d.x(), d.y()) / den;
      if (t >= 0 && s >= 0 && s <= 1) best = std::min(best, t);
    }
    return best;
  }
};

LegExtender::LegExtender(const grid::Prepared& prep, const grid::Grid& g, const MultiPolygon& free)
    : g_(g),
      free_(free),
      mode_(prep.mode),
      no_fly_(std::make_unique<Index>(prep.nfz_edges)),
      boundary_(std::make_unique<Index>(prep.free_edges)) {}

bool LegExtender::clear(Point a, Point b) const {
  return no_fly_->clear(a, b, grid::kClearance) && (mode_ == Mode::Coverage || boundary_->clear(a, b, 0.01));
}

LegExtender::~LegExtender() = default;

int LegExtender::extend(std::vector<Point>& loop) const {
  const std::size_t m = loop.size() >= 2 ? loop.size() - 1 : 0;  // distinct vertices
  if (m < 4) return 0;
  const double ds = g_.ds, dn = g_.dn, w2 = 0.75 * ds, eps = 1e-6 * ds;
  std::vector<char> moved(m, 0);
  int count = 0;
  auto at = [&](std::size_t i) -> Point& { return loop[i % m]; };
  auto cell_of = [&](Point p) {
    const Point q = g_.local_to_q(p);
    return std::pair{static_cast<int>(std::floor((q.y() - g_.y0) / dn)),
                     static_cast<int>(std::floor((q.x() - g_.x0) / dn))};
  };
  // how far a turn may move into the non-free cell (r1, c1): it sits ds/2 inside its own cell's edge;
  // the whole cell when its own cell is that cell's only free neighbour, else the triangle facing it
  auto cap_into = [&](int r1, int c1) {
    int free_nb = 0;
    for (const auto& [ar, ac] : std::array<std::pair<int, int>, 4>{{{1, 0}, {-1, 0}, {0, 1}, {0, -1}}})
      free_nb += g_.free_at(r1 + ar, c1 + ac);
    return free_nb == 1 ? 0.5 * ds + dn - 2 * grid::kClearance : 0.95 * ds;
  };
  // how far a leg end must move along d for the footprint (w/2 past the end) to reach the boundary
  // straight ahead; a leg end already outside the area (coverage mode) needs nothing. Sampling the
  // boundary across the leg's lane as well (5 rays, +-0.45 ds) reached the corners beside oblique edges:
  // on the paper's 18 regions it cost 0.13 km (strict) for 0.01 % PoC (bench/results/paper.md).
  auto reach = [&](Point p, Point d, double cap) {
    if (!bg::within(p, free_)) return 0.0;
    double t = std::min(boundary_->first_hit(p, d, cap + w2) - w2, cap);
    // keep the clearance: shorten until the extension is clear (the clear lengths form an interval)
    auto ok = [&](double s) { return s <= 0 || clear(p, Point(p.x() + s * d.x(), p.y() + s * d.y())); };
    if (t > 0 && !ok(t)) {
      double lo = 0, hi = t;
      for (int k = 0; k < 20; ++k) {
        const double mid = 0.5 * (lo + hi);
        (ok(mid) ? lo : hi) = mid;
      }
      t = lo;
    }
    return std::max(0.0, t);
  };
  for (std::size_t i = 0; i < m; ++i) {
    const std::size_t ip = (i + m - 1) % m, iw = (i + 1) % m, in = (i + 2) % m;
    if (moved[ip] || moved[i] || moved[iw] || moved[in]) continue;
    const Point prev = at(ip), v = at(i), w = at(iw), next = at(in);
    // a U-turn: prev -> v along d, v -> w across (length ds), w -> next along -d
    const double lx = v.x() - prev.x(), ly = v.y() - prev.y(), ll = std::hypot(lx, ly);
    if (ll < eps) continue;
    const Point d(lx / ll, ly / ll);
    const double cx = w.x() - v.x(), cy = w.y() - v.y();
    if (std::fabs(std::hypot(cx, cy) - ds) > eps || std::fabs(cx * d.x() + cy * d.y()) > eps) continue;
    const double rx = next.x() - w.x(), ry = next.y() - w.y(), rl = std::hypot(rx, ry);
    if (rl < eps || std::fabs(rx / rl + d.x()) > 1e-6 || std::fabs(ry / rl + d.y()) > 1e-6) continue;
    // the turn's mega-cell, and the one beyond it in direction d
    const Point mq = g_.local_to_q(Point((v.x() + w.x()) / 2, (v.y() + w.y()) / 2));
    const int r = static_cast<int>(std::floor((mq.y() - g_.y0) / dn));
    const int c = static_cast<int>(std::floor((mq.x() - g_.x0) / dn));
    const double dqx = g_.cos_t * d.x() + g_.sin_t * d.y(), dqy = -g_.sin_t * d.x() + g_.cos_t * d.y();
    const int dc = static_cast<int>(std::lround(dqx)), dr = static_cast<int>(std::lround(dqy));
    if (std::abs(dc) + std::abs(dr) != 1) continue;
    if (!g_.free_at(r, c)) continue;
    // both turn vertices in that cell (a U-turn along one of its sides, not across a link)
    if (cell_of(v) != std::pair{r, c} || cell_of(w) != std::pair{r, c}) continue;
    const int r1 = r + dr, c1 = c + dc;
    if (g_.free_at(r1, c1)) continue;
    const double cap = cap_into(r1, c1);
    auto wanted = [&](Point p) { return reach(p, d, cap); };
    double tv = wanted(v), tw = wanted(w);
    if (tv < 0.01 * ds && tw < 0.01 * ds) continue;
    auto moved_to = [&](Point p, double t) { return Point(p.x() + t * d.x(), p.y() + t * d.y()); };
    bool ok = clear(moved_to(v, tv), moved_to(w, tw));
    if (!ok) {
      tv = tw = std::min(tv, tw);
      for (int k = 0; k < 6 && !(ok = clear(moved_to(v, tv), moved_to(w, tw))); ++k) tv = tw = 0.5 * tv;
    }
    if (!ok || (tv < 0.01 * ds && tw < 0.01 * ds)) continue;
    at(i) = moved_to(v, tv);
    at(iw) = moved_to(w, tw);
    moved[i] = moved[iw] = 1;
    ++count;
  }
  loop.back() = loop.front();
  return count;
}

int LegExtender::shift(const std::vector<std::vector<Point>*>& loops,
                       const std::vector<double>& swaths) const {
  const double ds = g_.ds, dn = g_.dn, eps = 1e-6 * ds;
  // 0.45 ds: the leg stays in its own mega-cell, and its swath (w/2 = 0.75 ds) still meets the inner
  // lane's, ds away (up to 0.5 ds). 0.49 ds gave the same means (bench/results/darp-quality.md)
  const double gap = 0.05 * ds;
  // every segment of every loop: (loop, k) is loop[k] -> loop[k + 1]
  using Entry = std::pair<Box, std::pair<int, int>>;
  const auto entry = [&](int l, int k) {
    const auto& lp = *loops[static_cast<std::size_t>(l)];
    Box b;
    bg::envelope(Seg(lp[static_cast<std::size_t>(k)], lp[static_cast<std::size_t>(k) + 1]), b);
    return Entry(b, {l, k});
  };
  std::vector<Entry> all;
  for (std::size_t l = 0; l < loops.size(); ++l)
    for (std::size_t k = 0; k + 1 < loops[l]->size(); ++k)
      all.push_back(entry(static_cast<int>(l), static_cast<int>(k)));
  bgi::rtree<Entry, bgi::rstar<16>> segs(all.begin(), all.end());
  int count = 0;
  for (std::size_t l = 0; l < loops.size(); ++l) {
    auto& lp = *loops[l];
    const std::size_t m = lp.size() >= 2 ? lp.size() - 1 : 0;
    if (m < 4) continue;
    // a UAV's own camera of width w: a leg shifted by more than w - ds leaves a gap beside its inner
    // lane's (a 46 m camera at ds 44.7 m swept 94.5 % of its region, issue 26)
    const double own = l < swaths.size() ? swaths[l] : 0.0;
    const double w2 = own > 0.0 ? 0.5 * own : 0.75 * ds;
    const double cap = own > 0.0 ? std::clamp(own - ds, 0.0, 0.45 * ds) : 0.45 * ds;
    if (!(cap > 0.0)) continue;
    // a new segment a-b of loop l, in place of its segments k-1 .. k+1, meets no other segment
    auto meets = [&](Point a, Point b, std::size_t k) {
      Box q;
      bg::envelope(Seg(a, b), q);
      q.min_corner() = Point(q.min_corner().x() - gap, q.min_corner().y() - gap);
      q.max_corner() = Point(q.max_corner().x() + gap, q.max_corner().y() + gap);
      for (auto it = segs.qbegin(bgi::intersects(q)); it != segs.qend(); ++it) {
        const auto [ol, ok] = it->second;
        if (ol == static_cast<int>(l)) {
          const std::size_t d = (static_cast<std::size_t>(ok) + m - k) % m;  // its offset from leg k
          if (d <= 2 || d >= m - 2) continue;  // the replaced segments and their neighbours
        }
        const auto& op = *loops[static_cast<std::size_t>(ol)];
        const Seg o(op[static_cast<std::size_t>(ok)], op[static_cast<std::size_t>(ok) + 1]);
        if (bg::comparable_distance(Seg(a, b), o) < gap * gap) return true;
      }
      return false;
    };
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t kp = (k + m - 1) % m, kn = (k + 1) % m, kq = (k + 2) % m;
      const Point a = lp[k], b = lp[kn];
      const Point qa = g_.local_to_q(a), qb = g_.local_to_q(b);
      const bool horiz = std::fabs(qa.y() - qb.y()) < eps, vert = std::fabs(qa.x() - qb.x()) < eps;
      if (horiz == vert) continue;  // oblique (a moved turn) or degenerate
      // the lane: sub-row (horizontal leg) or sub-column (vertical) j; its outer side is the side of its
      // mega-cell it lies on
      const double across = horiz ? qa.y() - g_.y0 : qa.x() - g_.x0;
      const double jf = across / ds - 0.5;
      const long j = std::lround(jf);
      if (j < 0 || std::fabs(jf - static_cast<double>(j)) > 1e-6) continue;  // not on a lane (moved)
      const int side = (j % 2) ? 1 : -1, r = static_cast<int>(j / 2), r_out = r + side;
      const double lo = std::min(horiz ? qa.x() : qa.y(), horiz ? qb.x() : qb.y()) - (horiz ? g_.x0 : g_.y0);
      const double hi = std::max(horiz ? qa.x() : qa.y(), horiz ? qb.x() : qb.y()) - (horiz ? g_.x0 : g_.y0);
      if (hi - lo < 0.99 * ds) continue;
      const int n = std::max(2, static_cast<int>(std::ceil((hi - lo) / (0.5 * ds))));
      const Point nq(horiz ? 0.0 : side, horiz ? side : 0.0);
      const Point nl(g_.cos_t * nq.x() - g_.sin_t * nq.y(), g_.sin_t * nq.x() + g_.cos_t * nq.y());
      bool outer = true;
      double hmax = 0, hmin = std::numeric_limits<double>::infinity();
      int inside = 0;
      for (int s = 0; s <= n && outer; ++s) {
        const double t = lo + (hi - lo) * s / n;
        const int c = std::clamp(static_cast<int>(std::floor(t / dn)), 0, (horiz ? g_.cols : g_.rows) - 1);
        outer = horiz ? !g_.free_at(r_out, c) : !g_.free_at(c, r_out);  // nothing free beyond the leg
        if (!outer) break;
        const Point p =
            horiz ? g_.q_to_local(g_.x0 + t, g_.y0 + across) : g_.q_to_local(g_.x0 + across, g_.y0 + t);
        if (!bg::within(p, free_)) continue;
        const double h = boundary_->first_hit(p, nl, w2 + cap);
        hmax = std::max(hmax, h), hmin = std::min(hmin, h), ++inside;
      }
      if (!outer || inside == 0) continue;
      // as far as the farthest boundary point beside the leg needs (the mean of the samples: 0.11 % less
      // PoC in strict mode, 0.08 % in coverage mode)
      double delta = std::clamp(hmax - w2, 0.0, cap);
      if (mode_ == Mode::Strict) delta = std::min(delta, hmin - 0.01 * ds);
      bool ok = false;
      for (int tries = 0; tries < 4 && delta >= 0.02 * ds; ++tries, delta *= 0.5) {
        const Point a1(a.x() + delta * nl.x(), a.y() + delta * nl.y()),
            b1(b.x() + delta * nl.x(), b.y() + delta * nl.y());
        const Point prev = lp[kp], next = lp[kq];
        if (clear(prev, a1) && clear(a1, b1) && clear(b1, next) && !meets(prev, a1, k) && !meets(a1, b1, k) &&
            !meets(b1, next, k)) {
          for (std::size_t e : {kp, k, kn}) segs.remove(entry(static_cast<int>(l), static_cast<int>(e)));
          lp[k] = a1;
          lp[kn] = b1;
          lp[m] = lp[0];
          for (std::size_t e : {kp, k, kn}) segs.insert(entry(static_cast<int>(l), static_cast<int>(e)));
          ok = true;
          break;
        }
      }
      count += ok;
    }
  }
  return count;
}

}  // namespace uavcover::darp
