#include "geometry/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>

namespace uavcover::geometry {

namespace {
using Segment = bg::model::segment<Point>;
using MultiLine = bg::model::multi_linestring<Polyline>;
}  // namespace

Polygon to_local(const GeoPolygon& poly, const geodesy::LocalFrame& frame) {
  Polygon out;
  for (std::size_t r = 0; r < poly.size(); ++r) {
    auto& ring = r == 0 ? out.outer() : out.inners().emplace_back();
    for (const auto& ll : poly[r]) ring.push_back(frame.to_local(ll));
  }
  bg::correct(out);
  return out;
}

MultiPolygon to_local(const std::vector<GeoPolygon>& polys, const geodesy::LocalFrame& frame) {
  MultiPolygon out;
  for (const auto& p : polys) out.push_back(to_local(p, frame));
  return out;
}

MultiPolygon unite(const MultiPolygon& polys) {
  MultiPolygon acc;
  for (const auto& p : polys) {
    MultiPolygon next;
    bg::union_(acc, p, next);
    acc = std::move(next);
  }
  return acc;
}

MultiPolygon free_space(const MultiPolygon& area, const MultiPolygon& no_fly) {
  MultiPolygon a = unite(area);
  if (no_fly.empty()) return a;
  MultiPolygon out;
  bg::difference(a, unite(no_fly), out);
  return out;
}

double distance(const MultiPolygon& set, Point p) {
  if (set.empty()) return std::numeric_limits<double>::infinity();
  if (bg::covered_by(p, set)) return 0.0;
  return bg::distance(p, set);
}

bool segment_within(const MultiPolygon& set, Point a, Point b, double tol) {
  if (distance(set, a) > tol || distance(set, b) > tol) return false;
  Polyline line{a, b};
  MultiLine outside;
  bg::difference(line, set, outside);
  for (const auto& piece : outside) {
    for (const auto& q : piece)
      if (distance(set, q) > tol) return false;
    // the deepest point of a straight piece outside a polygon lies at a vertex of the polygon
    // boundary's projection; sample the piece densely enough for a tolerance check
    const double len = bg::length(piece);
    const int n = std::clamp(static_cast<int>(len / std::max(tol, 0.05)), 1, 10000);
    for (int i = 1; i < n; ++i) {
      const double t = static_cast<double>(i) / n;
      const Point q{piece.front().x() + t * (piece.back().x() - piece.front().x()),
                    piece.front().y() + t * (piece.back().y() - piece.front().y())};
      if (distance(set, q) > tol) return false;
    }
  }
  return true;
}

bool segment_enters(const MultiPolygon& obstacles, Point a, Point b, double tol) {
  const Segment seg{a, b};
  const Polyline line{a, b};
  for (const auto& poly : obstacles) {
    if (!bg::intersects(seg, poly)) continue;  // cheap test first
    MultiLine inside;
    bg::intersection(line, poly, inside);
    for (const auto& piece : inside) {
      if (bg::length(piece) <= tol) continue;
      // a piece running along the boundary is not "inside"; test its midpoint's depth
      const Point mid{(piece.front().x() + piece.back().x()) / 2, (piece.front().y() + piece.back().y()) / 2};
      if (!bg::within(mid, poly)) continue;
      // distance to the boundary (rings as lines: bg::distance to a ring would be 0 inside it)
      auto boundary_distance = [&](const auto& ring) {
        return bg::distance(mid, Polyline(ring.begin(), ring.end()));
      };
      double d = boundary_distance(bg::exterior_ring(poly));
      for (const auto& in : bg::interior_rings(poly)) d = std::min(d, boundary_distance(in));
      if (d > tol) return true;
    }
  }
  return false;
}

std::vector<Point> route_around(const MultiPolygon& obstacles, Point a, Point b, double clearance) {
  // touching an obstacle's boundary is fine; entering it is not
  auto clear = [&](Point p, Point q) { return !segment_enters(obstacles, p, q, 0.0); };
  if (clear(a, b)) return {a, b};

  // nodes: vertices of the obstacles, pushed outward by `clearance` along the vertex bisector
  std::vector<Point> nodes{a, b};
  auto add_ring = [&](const auto& ring, bool outer) {
    const std::size_t n = ring.size() > 1 ? ring.size() - 1 : 0;  // closed ring
    for (std::size_t i = 0; i < n; ++i) {
      const Point& p = ring[i];
      const Point& prev = ring[(i + n - 1) % n];
      const Point& next = ring[(i + 1) % n];
      double e1x = p.x() - prev.x(), e1y = p.y() - prev.y();
      double e2x = next.x() - p.x(), e2y = next.y() - p.y();
      const double l1 = std::hypot(e1x, e1y), l2 = std::hypot(e2x, e2y);
      if (l1 < 1e-9 || l2 < 1e-9) continue;
      e1x /= l1, e1y /= l1, e2x /= l2, e2y /= l2;
      // outward normals for a clockwise outer ring point to the left of travel direction
      double nx = -(e1y + e2y), ny = (e1x + e2x);
      if (!outer) nx = -nx, ny = -ny;
      const double nl = std::hypot(nx, ny);
      if (nl < 1e-9) continue;
      for (double k : {1.0, 3.0}) {
        const Point q{p.x() + nx / nl * clearance * k, p.y() + ny / nl * clearance * k};
        nodes.push_back(q);
      }
    }
  };
  for (const auto& poly : obstacles) {
    add_ring(bg::exterior_ring(poly), true);
    for (const auto& in : bg::interior_rings(poly)) add_ring(in, false);
  }
  // Dijkstra on the visibility graph (lazy edge checks)
  const std::size_t n = nodes.size();
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  std::vector<std::size_t> prev(n, n);
  std::vector<char> done(n, 0);
  using QE = std::pair<double, std::size_t>;
  std::priority_queue<QE, std::vector<QE>, std::greater<>> pq;
  dist[0] = 0;
  pq.push({0, 0});
  while (!pq.empty()) {
    auto [d, u] = pq.top();
    pq.pop();
    if (done[u]) continue;
    done[u] = 1;
    if (u == 1) break;
    for (std::size_t v = 0; v < n; ++v) {
      if (done[v] || v == u) continue;
      const double w = bg::distance(nodes[u], nodes[v]);
      if (d + w >= dist[v]) continue;
      if (!clear(nodes[u], nodes[v])) continue;
      dist[v] = d + w;
      prev[v] = u;
      pq.push({dist[v], v});
    }
  }
  if (!std::isfinite(dist[1])) return {a, b};
  std::vector<Point> path;
  for (std::size_t v = 1; v != n; v = prev[v]) {
    path.push_back(nodes[v]);
    if (v == 0) break;
  }
  std::reverse(path.begin(), path.end());
  return path;
}

double length(const std::vector<Point>& pts) {
  double s = 0;
  for (std::size_t i = 1; i < pts.size(); ++i) s += bg::distance(pts[i - 1], pts[i]);
  return s;
}

int count_turns(const std::vector<Point>& pts, double angle_tol_deg) {
  int turns = 0;
  const double tol = angle_tol_deg * std::numbers::pi / 180.0;
  for (std::size_t i = 1; i + 1 < pts.size(); ++i) {
    const double a1 = std::atan2(pts[i].y() - pts[i - 1].y(), pts[i].x() - pts[i - 1].x());
    const double a2 = std::atan2(pts[i + 1].y() - pts[i].y(), pts[i + 1].x() - pts[i].x());
    double d = std::fabs(a2 - a1);
    if (d > std::numbers::pi) d = 2 * std::numbers::pi - d;
    if (d > tol) ++turns;
  }
  return turns;
}

}  // namespace uavcover::geometry
