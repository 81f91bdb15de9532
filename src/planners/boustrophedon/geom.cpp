#include "planners/boustrophedon/geom.hpp"

#include <algorithm>
#include <iterator>

namespace uavcover::planners::boustro {

double chain_at(const std::vector<Point>& chain, double x) {
  if (chain.empty()) return 0.0;
  if (x <= chain.front().x()) return chain.front().y();
  if (x >= chain.back().x()) return chain.back().y();
  const auto it =
      std::lower_bound(chain.begin(), chain.end(), x, [](const Point& p, double v) { return p.x() < v; });
  const Point& q = *it;
  const Point& p = *std::prev(it);
  if (q.x() - p.x() <= 0.0) return q.y();
  return p.y() + (x - p.x()) / (q.x() - p.x()) * (q.y() - p.y());
}

std::optional<Monotone> monotone_chains(const Ring& ring, double tol) {
  if (ring.size() < 4) return std::nullopt;
  const std::size_t n = bg::equals(ring.front(), ring.back()) ? ring.size() - 1 : ring.size();
  // direction changes of X along the ring (cyclic), ignoring steps below the tolerance
  int changes = 0, first = 0, last = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = ring[(i + 1) % n].x() - ring[i].x();
    const int sgn = dx > tol ? 1 : (dx < -tol ? -1 : 0);
    if (sgn == 0) continue;
    if (first == 0) first = sgn;
    if (last != 0 && sgn != last) ++changes;
    last = sgn;
  }
  if (first == 0) return std::nullopt;
  if (last != first) ++changes;
  if (changes != 2) return std::nullopt;
  std::size_t imin = 0, imax = 0;
  for (std::size_t i = 1; i < n; ++i) {
    const Point& p = ring[i];
    if (p.x() < ring[imin].x() || (p.x() == ring[imin].x() && p.y() < ring[imin].y())) imin = i;
    if (p.x() > ring[imax].x() || (p.x() == ring[imax].x() && p.y() > ring[imax].y())) imax = i;
  }
  if (ring[imax].x() - ring[imin].x() <= tol) return std::nullopt;
  std::vector<Point> a, b;
  for (std::size_t i = imin;; i = (i + 1) % n) {
    a.push_back(ring[i]);
    if (i == imax) break;
  }
  for (std::size_t i = imin;; i = (i + n - 1) % n) {
    b.push_back(ring[i]);
    if (i == imax) break;
  }
  // X never decreases along a chain (removes wobble below the tolerance)
  for (auto* c : {&a, &b})
    for (std::size_t i = 1; i < c->size(); ++i)
      if ((*c)[i].x() < (*c)[i - 1].x()) (*c)[i].x((*c)[i - 1].x());
  // keep one point per chain end: the lowest (lower chain) or highest (upper chain) at that X
  auto trim = [tol](std::vector<Point>& c, bool keep_low) {
    auto better = [keep_low](const Point& p, const Point& q) {
      return keep_low ? p.y() < q.y() : p.y() > q.y();
    };
    std::size_t k = 0;
    while (k + 1 < c.size() && c[k + 1].x() - c.front().x() <= tol) ++k;
    Point best = c.front();
    for (std::size_t i = 1; i <= k; ++i)
      if (better(c[i], best)) best = c[i];
    c.erase(c.begin(), c.begin() + static_cast<std::ptrdiff_t>(k));
    c.front() = best;
    k = c.size() - 1;
    while (k > 0 && c.back().x() - c[k - 1].x() <= tol) --k;
    best = c.back();
    for (std::size_t i = k; i + 1 < c.size(); ++i)
      if (better(c[i], best)) best = c[i];
    c.erase(c.begin() + static_cast<std::ptrdiff_t>(k) + 1, c.end());
    c.back() = best;
  };
  const double xm = 0.5 * (a.front().x() + a.back().x());
  Monotone m;
  if (chain_at(a, xm) >= chain_at(b, xm)) {
    m.upper = std::move(a);
    m.lower = std::move(b);
  } else {
    m.upper = std::move(b);
    m.lower = std::move(a);
  }
  trim(m.lower, true);
  trim(m.upper, false);
  if (m.lower.size() < 2 || m.upper.size() < 2) return std::nullopt;
  return m;
}

Polygon from_frame(const Polygon& p, const Frame& f) {
  Polygon out;
  out.outer() = from_frame(p.outer(), f);
  for (const auto& in : p.inners()) out.inners().push_back(from_frame(in, f));
  return out;
}

MultiPolygon from_frame(const MultiPolygon& m, const Frame& f) {
  MultiPolygon out;
  for (const auto& p : m) out.push_back(from_frame(p, f));
  return out;
}

Polygon monotone_polygon(const Monotone& m, const Frame& frame) {
  Polygon out = from_frame(monotone_polygon(m), frame);
  bg::correct(out);
  return out;
}

Polygon monotone_polygon(const Monotone& m) {
  Polygon out;
  for (const auto& p : m.lower) out.outer().push_back(p);
  for (auto it = m.upper.rbegin(); it != m.upper.rend(); ++it) {
    const Point q = *it;
    if (!out.outer().empty() && dist(out.outer().back(), q) < 1e-12) continue;
    out.outer().push_back(q);
  }
  if (!out.outer().empty() && dist(out.outer().back(), out.outer().front()) > 1e-12)
    out.outer().push_back(out.outer().front());
  bg::correct(out);
  return out;
}

namespace {
bool clean_ring(Ring& r, double tol) {
  Ring out;
  for (const auto& p : r)
    if (out.empty() || dist(out.back(), p) > tol) out.push_back(p);
  while (out.size() > 1 && dist(out.back(), out.front()) <= tol) out.pop_back();
  if (out.size() < 3) return false;
  out.push_back(out.front());
  r = std::move(out);
  return true;
}
}  // namespace

void remove_near_duplicates(MultiPolygon& m, double tol) {
  MultiPolygon out;
  for (auto& p : m) {
    if (!clean_ring(p.outer(), tol)) continue;
    std::erase_if(p.inners(), [tol](Ring& r) { return !clean_ring(r, tol); });
    out.push_back(std::move(p));
  }
  m = std::move(out);
}

void EdgeIndex::add(const Ring& ring) {
  for (std::size_t i = 1; i < ring.size(); ++i) {
    const Seg s{ring[i - 1], ring[i]};
    Box box;
    bg::envelope(s, box);
    tree_.insert({box, segs_.size()});
    segs_.push_back(s);
  }
}

void EdgeIndex::add(const MultiPolygon& polys) {
  for (const auto& p : polys) {
    add(p.outer());
    for (const auto& in : p.inners()) add(in);
  }
}

std::optional<double> EdgeIndex::first_hit(Point a, Point b, double t_min) const {
  if (tree_.empty()) return std::nullopt;
  Box box;
  bg::envelope(Seg{a, b}, box);
  std::vector<Value> hits;
  tree_.query(bg::index::intersects(box), std::back_inserter(hits));
  const double dx = b.x() - a.x(), dy = b.y() - a.y();
  const double dd = dx * dx + dy * dy;
  if (dd <= 0.0) return std::nullopt;
  std::optional<double> best;
  auto consider = [&](double t) {
    if (t < t_min || t > 1.0) return;
    if (!best || t < *best) best = t;
  };
  for (const auto& [_, idx] : hits) {
    const Point& p = segs_[idx].first;
    const Point& q = segs_[idx].second;
    const double ex = q.x() - p.x(), ey = q.y() - p.y();
    const double apx = p.x() - a.x(), apy = p.y() - a.y();
    const double denom = dx * ey - dy * ex;
    const double scale = std::sqrt(dd * (ex * ex + ey * ey));
    if (std::abs(denom) <= 1e-12 * scale) {
      // parallel: a hit only when collinear and overlapping
      if (std::abs(apx * dy - apy * dx) > 1e-9 * dd) continue;
      const double tp = (apx * dx + apy * dy) / dd;
      const double tq = ((q.x() - a.x()) * dx + (q.y() - a.y()) * dy) / dd;
      const double lo = std::max(std::min(tp, tq), t_min), hi = std::min(std::max(tp, tq), 1.0);
      if (lo <= hi) consider(lo);
      continue;
    }
    const double t = (apx * ey - apy * ex) / denom;
    const double u = (apx * dy - apy * dx) / denom;
    if (u < -1e-12 || u > 1.0 + 1e-12) continue;
    consider(t);
  }
  return best;
}

}  // namespace uavcover::planners::boustro
