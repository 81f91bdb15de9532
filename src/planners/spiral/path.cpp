#include "planners/spiral/path.hpp"

#include <algorithm>
#include <boost/geometry/index/rtree.hpp>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <numbers>
#include <optional>

namespace uavcover::planners::spiral {

namespace {

namespace bgi = bg::index;
using Value = std::pair<Point, int>;
using Tree = bgi::rtree<Value, bgi::rstar<16>>;

double dist(Point a, Point b) { return std::hypot(a.x() - b.x(), a.y() - b.y()); }
auto idx(int i) { return static_cast<std::size_t>(i); }

/// The nearest entry of a non-empty tree to p (ties: the smaller triangle index).
Value nearest(const Tree& tree, Point p) {
  std::vector<Value> hits;
  tree.query(bgi::nearest(p, 4), std::back_inserter(hits));
  return *std::min_element(hits.begin(), hits.end(), [&](const Value& a, const Value& b) {
    return std::make_pair(dist(a.first, p), a.second) < std::make_pair(dist(b.first, p), b.second);
  });
}

/// The edge shared by triangles a and b (vertex positions), if any.
std::optional<std::pair<Point, Point>> portal(const Mesh& m, int a, int b) {
  const auto& na = m.neighbours[idx(a)];
  for (int i = 0; i < 3; ++i)
    if (na[idx(i)] == b) {
      const auto& t = m.triangles[idx(a)];
      return std::make_pair(m.vertices[idx(t[idx((i + 1) % 3)])], m.vertices[idx(t[idx((i + 2) % 3)])]);
    }
  return std::nullopt;
}

/// Parameter along p->q where it crosses the portal u-v strictly between its ends, if it does.
std::optional<double> crossing(Point p, Point q, Point u, Point v) {
  const double rx = q.x() - p.x(), ry = q.y() - p.y(), sx = v.x() - u.x(), sy = v.y() - u.y();
  const double den = rx * sy - ry * sx;
  if (std::abs(den) < 1e-12 * (std::hypot(rx, ry) * std::hypot(sx, sy) + 1e-300)) return std::nullopt;
  const double wx = u.x() - p.x(), wy = u.y() - p.y();
  const double t = (wx * sy - wy * sx) / den, s = (wx * ry - wy * rx) / den;
  constexpr double eps = 1e-3;
  if (t < -1e-9 || t > 1.0 + 1e-9 || s < eps || s > 1.0 - eps) return std::nullopt;
  return t;
}

}  // namespace

SpiralOrder spiral_order(const Mesh& mesh, const std::vector<Point>& centroid, const std::vector<int>& owner,
                         const std::vector<int>& level, int uav, Point start, double valley_sensitivity,
                         const Context& ctx) {
  SpiralOrder out;
  int max_level = -1;
  double max_neighbour = 0.0;
  std::vector<std::vector<Value>> by_level;
  for (std::size_t t = 0; t < owner.size(); ++t) {
    if (owner[t] != uav) continue;
    const int l = std::max(0, level[t]);
    if (l > max_level) {
      max_level = l;
      by_level.resize(idx(l) + 1);
    }
    by_level[idx(l)].emplace_back(centroid[t], static_cast<int>(t));
    for (int nb : mesh.neighbours[t])
      if (nb >= 0 && owner[idx(nb)] == uav)
        max_neighbour = std::max(max_neighbour, dist(centroid[t], centroid[idx(nb)]));
  }
  if (max_level < 0) return out;
  std::vector<Tree> tree;
  std::size_t remaining = 0;
  for (const auto& v : by_level) {
    tree.emplace_back(v.begin(), v.end());
    remaining += v.size();
  }
  out.step_bound_m = valley_sensitivity * max_neighbour;
  auto deeper = [&](int l) {
    for (int d = l + 1; d <= max_level; ++d)
      if (!tree[idx(d)].empty()) return true;
    return false;
  };
  std::vector<Value> deferred;
  Point here = start;
  int l = 0;
  if (!tree[0].empty()) {  // the first triangle: the border's nearest to the start
    const Value v = nearest(tree[0], here);
    tree[0].remove(v);
    out.order.push_back(v.second);
    here = v.first;
    --remaining;
  }
  while (remaining > 0) {
    if (out.order.size() % 1024 == 0) ctx.check();
    if (!tree[idx(l)].empty()) {
      const Value v = nearest(tree[idx(l)], here);
      tree[idx(l)].remove(v);
      if (dist(here, v.first) > out.step_bound_m && deeper(l)) {
        // a valley: keep the far step for later and go on inwards from here
        deferred.push_back(v);
        ++out.deferred;
        ++l;
        continue;
      }
      out.order.push_back(v.second);
      here = v.first;
      --remaining;
    } else if (!deferred.empty()) {
      const auto it = std::min_element(deferred.begin(), deferred.end(), [&](const Value& a, const Value& b) {
        return std::make_pair(dist(a.first, here), a.second) < std::make_pair(dist(b.first, here), b.second);
      });
      const Value v = *it;
      deferred.erase(it);
      out.order.push_back(v.second);
      here = v.first;
      --remaining;
      l = std::max(0, level[idx(v.second)]);
    } else {
      int next = -1;
      for (int d = l + 1; d <= max_level && next < 0; ++d)
        if (!tree[idx(d)].empty()) next = d;
      for (int d = 0; d <= max_level && next < 0; ++d)
        if (!tree[idx(d)].empty()) next = d;
      if (next < 0) break;
      l = next;
    }
  }
  return out;
}

std::vector<std::vector<Point>> route(const Mesh& mesh, const std::vector<Point>& centroid,
                                      const std::vector<int>& owner, int uav, const std::vector<int>& order,
                                      const Context& ctx) {
  std::vector<std::vector<Point>> parts;
  if (order.empty()) return parts;
  std::vector<int> stamp(mesh.triangles.size(), 0), parent(mesh.triangles.size(), -1);
  int generation = 0;
  // shortest chain of neighbouring triangles of the sub-area from a to b (breadth first), or empty
  auto chain = [&](int a, int b) {
    ++generation;
    std::deque<int> queue{a};
    stamp[idx(a)] = generation;
    parent[idx(a)] = -1;
    while (!queue.empty()) {
      const int u = queue.front();
      queue.pop_front();
      if (u == b) break;
      for (int nb : mesh.neighbours[idx(u)])
        if (nb >= 0 && owner[idx(nb)] == uav && stamp[idx(nb)] != generation) {
          stamp[idx(nb)] = generation;
          parent[idx(nb)] = u;
          queue.push_back(nb);
        }
    }
    std::vector<int> c;
    if (stamp[idx(b)] != generation) return c;
    for (int u = b; u >= 0; u = parent[idx(u)]) c.push_back(u);
    std::reverse(c.begin(), c.end());
    return c;
  };
  // appends the path from the centroid of c.front() to that of c.back() inside the chain's triangles
  auto pull = [&](const std::vector<int>& c, std::vector<Point>& out) {
    std::vector<std::pair<Point, Point>> portals;
    for (std::size_t m = 0; m + 1 < c.size(); ++m) portals.push_back(*portal(mesh, c[m], c[m + 1]));
    Point anchor = centroid[idx(c.front())];
    std::size_t a = 0;  // anchor lies in triangle c[a]
    auto visible = [&](std::size_t j) {
      double last = -1.0;
      for (std::size_t m = a; m < j; ++m) {
        const auto t = crossing(anchor, centroid[idx(c[j])], portals[m].first, portals[m].second);
        if (!t || *t < last) return false;
        last = *t;
      }
      return true;
    };
    while (a + 1 < c.size()) {
      std::size_t j = a + 1;
      if (!visible(j)) {
        // not even the next centroid is in sight: through the middle of the shared edge
        const Point mid((portals[a].first.x() + portals[a].second.x()) / 2.0,
                        (portals[a].first.y() + portals[a].second.y()) / 2.0);
        out.push_back(mid);
        anchor = mid;
        ++a;
        if (a + 1 == c.size()) out.push_back(centroid[idx(c[a])]);
        continue;
      }
      while (j + 1 < c.size() && visible(j + 1)) ++j;
      out.push_back(centroid[idx(c[j])]);
      anchor = centroid[idx(c[j])];
      a = j;
    }
  };
  parts.push_back({centroid[idx(order.front())]});
  for (std::size_t i = 1; i < order.size(); ++i) {
    if (i % 256 == 0) ctx.check();
    const std::vector<int> c = chain(order[i - 1], order[i]);
    if (c.empty()) {
      parts.push_back({centroid[idx(order[i])]});  // another component of the sub-area
      continue;
    }
    pull(c, parts.back());
  }
  for (auto& p : parts) p = merge_collinear(p);
  return parts;
}

std::vector<Point> merge_collinear(const std::vector<Point>& pts, double tol_deg) {
  std::vector<Point> out;
  for (const Point p : pts) {
    if (!out.empty() && dist(out.back(), p) < 1e-9) continue;
    while (out.size() >= 2) {
      const Point a = out[out.size() - 2], b = out.back();
      const double ux = b.x() - a.x(), uy = b.y() - a.y(), vx = p.x() - b.x(), vy = p.y() - b.y();
      const double turn =
          std::atan2(std::abs(ux * vy - uy * vx), ux * vx + uy * vy) * 180.0 / std::numbers::pi;
      if (turn >= tol_deg) break;
      out.pop_back();  // b is on the straight line from a to p
    }
    out.push_back(p);
  }
  return out;
}

double turn_angle_deg(Point a, Point b, Point c) {
  const double ux = a.x() - b.x(), uy = a.y() - b.y();
  const double vx = c.x() - b.x(), vy = c.y() - b.y();
  return std::atan2(std::abs(ux * vy - uy * vx), ux * vx + uy * vy) * 180.0 / std::numbers::pi;
}

int smooth_order(const std::vector<Point>& centroid, const std::vector<int>& level, std::vector<int>& order,
                 double reversal_deg, const Context& ctx) {
  if (!(reversal_deg > 0.0) || order.size() < 4) return 0;
  constexpr std::size_t kWindow = 4;  // longest run reversed in one move
  const auto c = [&](std::size_t i) { return centroid[static_cast<std::size_t>(order[i])]; };
  // reversals and length of the turns at positions [lo, hi] and the legs between lo-1 and hi+1
  const auto cost = [&](std::size_t lo, std::size_t hi, int& reversals, double& length) {
    reversals = 0;
    length = 0.0;
    for (std::size_t m = std::max<std::size_t>(lo, 1); m <= hi && m + 1 < order.size(); ++m)
      if (turn_angle_deg(c(m - 1), c(m), c(m + 1)) < reversal_deg) ++reversals;
    for (std::size_t m = std::max<std::size_t>(lo, 1); m <= std::min(hi + 1, order.size() - 1); ++m)
      length += dist(c(m - 1), c(m));
  };
  int moves = 0;
  for (int pass = 0; pass < 3; ++pass) {
    bool changed = false;
    for (std::size_t a = 1; a + 1 < order.size(); ++a) {
      if (a % 1024 == 0) ctx.check();
      if (turn_angle_deg(c(a - 1), c(a), c(a + 1)) >= reversal_deg) continue;
      // a reversal at a: try reversing a run order[i..j] around it, all of one level
      bool done = false;
      for (std::size_t i = a > kWindow ? a - kWindow + 1 : 1; i <= a + 1 && !done; ++i)
        for (std::size_t j = std::max(i + 1, a); j < std::min(order.size() - 1, i + kWindow) && !done; ++j) {
          const int lv = level[static_cast<std::size_t>(order[i])];
          bool same = true;
          for (std::size_t k = i; k <= j && same; ++k) same = level[static_cast<std::size_t>(order[k])] == lv;
          if (!same) continue;
          const std::size_t lo = i > 0 ? i - 1 : 0, hi = j + 1;
          int r0 = 0, r1 = 0;
          double l0 = 0.0, l1 = 0.0;
          cost(lo, hi, r0, l0);
          std::reverse(order.begin() + static_cast<std::ptrdiff_t>(i),
                       order.begin() + static_cast<std::ptrdiff_t>(j + 1));
          cost(lo, hi, r1, l1);
          // fewer reversals, the local path at most a quarter longer
          if (r1 < r0 && l1 <= 1.25 * l0) {
            done = changed = true;
            ++moves;
          } else {
            std::reverse(order.begin() + static_cast<std::ptrdiff_t>(i),
                         order.begin() + static_cast<std::ptrdiff_t>(j + 1));
          }
        }
    }
    if (!changed) break;
  }
  return moves;
}

PathStats path_stats(const std::vector<std::vector<Point>>& parts) {
  PathStats s;
  double angle_sum = 0.0;
  int angles = 0;
  s.min_step_m = std::numeric_limits<double>::infinity();
  s.min_angle_deg = 180.0;
  for (const auto& p : parts) {
    s.waypoints += static_cast<int>(p.size());
    for (std::size_t k = 1; k < p.size(); ++k) {
      const double d = dist(p[k - 1], p[k]);
      s.length_m += d;
      s.min_step_m = std::min(s.min_step_m, d);
      s.max_step_m = std::max(s.max_step_m, d);
      if (k + 1 < p.size()) {
        const double deg = turn_angle_deg(p[k - 1], p[k], p[k + 1]);
        s.min_angle_deg = std::min(s.min_angle_deg, deg);
        s.max_angle_deg = std::max(s.max_angle_deg, deg);
        angle_sum += deg;
        ++angles;
        ++s.angle_bins[std::min<std::size_t>(5, static_cast<std::size_t>(deg / 30.0))];
      }
    }
  }
  if (!std::isfinite(s.min_step_m)) s.min_step_m = 0.0;
  if (angles == 0) s.min_angle_deg = 0.0;
  s.mean_angle_deg = angles > 0 ? angle_sum / angles : 0.0;
  return s;
}

MultiPolygon region_of(const Mesh& mesh, const std::vector<int>& owner, int uav) {
  // directed boundary edges with the sub-area on their left (triangles are counter-clockwise)
  std::vector<std::pair<int, int>> edges;
  std::map<int, std::vector<std::size_t>> out_of;  // vertex -> boundary edges leaving it
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (owner[t] != uav) continue;
    for (int i = 0; i < 3; ++i) {
      const int nb = mesh.neighbours[t][idx(i)];
      if (nb >= 0 && owner[idx(nb)] == uav) continue;
      const int a = mesh.triangles[t][idx((i + 1) % 3)], b = mesh.triangles[t][idx((i + 2) % 3)];
      out_of[a].push_back(edges.size());
      edges.emplace_back(a, b);
    }
  }
  std::vector<char> used(edges.size(), 0);
  std::vector<std::vector<Point>> rings;
  for (std::size_t e0 = 0; e0 < edges.size(); ++e0) {
    if (used[e0]) continue;
    std::vector<Point> ring;
    std::size_t e = e0;
    while (!used[e]) {
      used[e] = 1;
      const auto [a, b] = edges[e];
      ring.push_back(mesh.vertices[idx(a)]);
      // at a vertex where the sub-area touches itself, keep to the same wedge: the leaving edge
      // nearest clockwise from the way back
      const Point pb = mesh.vertices[idx(b)], back = mesh.vertices[idx(a)];
      const double back_angle = std::atan2(back.y() - pb.y(), back.x() - pb.x());
      std::optional<std::size_t> next;
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t cand : out_of[b]) {
        if (used[cand]) continue;
        const Point w = mesh.vertices[idx(edges[cand].second)];
        double cw = back_angle - std::atan2(w.y() - pb.y(), w.x() - pb.x());
        while (cw <= 0.0) cw += 2.0 * std::numbers::pi;
        if (cw < best) best = cw, next = cand;
      }
      if (!next) break;
      e = *next;
    }
    if (ring.size() >= 3) rings.push_back(std::move(ring));
  }
  auto signed_area = [](const std::vector<Point>& r) {
    double s = 0.0;
    for (std::size_t i = 0; i < r.size(); ++i) {
      const Point p = r[i], q = r[(i + 1) % r.size()];
      s += p.x() * q.y() - q.x() * p.y();
    }
    return s / 2.0;
  };
  auto as_ring = [](const std::vector<Point>& r) {
    Polygon::ring_type out(r.rbegin(), r.rend());  // Boost's order: clockwise outer rings
    out.push_back(out.front());
    return out;
  };
  MultiPolygon out;
  std::vector<double> outer_area;
  std::vector<const std::vector<Point>*> holes;
  for (const auto& r : rings) {
    const double a = signed_area(r);
    if (a > 0.0) {
      Polygon p;
      p.outer() = as_ring(r);
      out.push_back(std::move(p));
      outer_area.push_back(a);
    } else if (a < 0.0) {
      holes.push_back(&r);
    }
  }
  for (const auto* h : holes) {
    const Point mid(((*h)[0].x() + (*h)[1].x()) / 2.0, ((*h)[0].y() + (*h)[1].y()) / 2.0);
    std::optional<std::size_t> best;
    for (std::size_t k = 0; k < out.size(); ++k) {
      Polygon shell;
      shell.outer() = out[k].outer();
      if (bg::within(mid, shell) && (!best || outer_area[k] < outer_area[*best])) best = k;
    }
    if (!best) continue;
    Polygon::ring_type ring(h->rbegin(), h->rend());
    ring.push_back(ring.front());
    out[*best].inners().push_back(std::move(ring));
  }
  bg::correct(out);
  return out;
}

}  // namespace uavcover::planners::spiral
