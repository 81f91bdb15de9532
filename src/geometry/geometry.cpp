#include "geometry/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <numbers>
#include <queue>

#include <boost/geometry/index/rtree.hpp>

namespace uavcover::geometry {

namespace {
namespace bgi = bg::index;
using Box = bg::model::box<Point>;
using Segment = bg::model::segment<Point>;
using MultiLine = bg::model::multi_linestring<Polyline>;
}  // namespace

namespace {

/// Appends to `out` the local points strictly between lon/lat positions a and b that keep the local
/// polyline within kDensifyTolM of the straight lon/lat edge (as GeoJSON readers draw it): the lon/lat
/// midpoint is inserted, recursively, where it lies farther than that from the local chord's midpoint.
void densify_geo(const geodesy::LocalFrame& frame, const LonLat& a, const LonLat& b, Point pa, Point pb,
                 int depth, std::vector<Point>& out) {
  const LonLat m{(a.lon + b.lon) / 2, (a.lat + b.lat) / 2};
  const Point pm = frame.to_local(m);
  const Point chord{(pa.x() + pb.x()) / 2, (pa.y() + pb.y()) / 2};
  if (depth >= 16 || !(bg::distance(pm, chord) > kDensifyTolM)) return;
  densify_geo(frame, a, m, pa, pm, depth + 1, out);
  out.push_back(pm);
  densify_geo(frame, m, b, pm, pb, depth + 1, out);
}

}  // namespace

std::vector<LonLat> to_wgs84_dense(const std::vector<Point>& local, const geodesy::LocalFrame& frame,
                                   std::vector<Point>* dense_local) {
  std::vector<LonLat> out;
  std::vector<Point> pts;
  out.reserve(local.size());
  for (std::size_t i = 0; i < local.size(); ++i) {
    if (i > 0) {
      // the local segment's lon/lat midpoint against the lon/lat chord's midpoint
      std::vector<Point> between;
      const Point a = local[i - 1], b = local[i];
      auto split = [&](auto&& self, Point p, Point q, int depth) -> void {
        const Point m{(p.x() + q.x()) / 2, (p.y() + q.y()) / 2};
        const LonLat gp = frame.to_wgs84(p), gq = frame.to_wgs84(q);
        const Point chord = frame.to_local(LonLat{(gp.lon + gq.lon) / 2, (gp.lat + gq.lat) / 2});
        if (depth >= 16 || !(bg::distance(m, chord) > kDensifyTolM)) return;
        self(self, p, m, depth + 1);
        between.push_back(m);
        self(self, m, q, depth + 1);
      };
      split(split, a, b, 0);
      for (const auto& m : between) {
        out.push_back(frame.to_wgs84(m));
        pts.push_back(m);
      }
    }
    out.push_back(frame.to_wgs84(local[i]));
    pts.push_back(local[i]);
  }
  if (dense_local != nullptr) *dense_local = std::move(pts);
  return out;
}

Polygon to_local(const GeoPolygon& poly, const geodesy::LocalFrame& frame) {
  Polygon out;
  for (std::size_t r = 0; r < poly.size(); ++r) {
    auto& ring = r == 0 ? out.outer() : out.inners().emplace_back();
    for (std::size_t i = 0; i < poly[r].size(); ++i) {
      const Point p = frame.to_local(poly[r][i]);
      if (i > 0) densify_geo(frame, poly[r][i - 1], poly[r][i], ring.back(), p, 0, ring);
      ring.push_back(p);
    }
  }
  bg::correct(out);
  return out;
}

MultiPolygon to_local(const std::vector<GeoPolygon>& polys, const geodesy::LocalFrame& frame) {
  MultiPolygon out;
  for (const auto& p : polys) out.push_back(to_local(p, frame));
  return out;
}

namespace {
/// Clusters up to this size are united one polygon after the other, in input order (every plan of
/// the golden tests); larger ones pairwise (the same area, in O(n log n) unions of bounded size).
constexpr std::size_t kSequentialUnion = 32;
}  // namespace

Polygon box_polygon(double x0, double y0, double x1, double y1) {
  Polygon p;
  bg::append(p.outer(), Point{x0, y0});
  bg::append(p.outer(), Point{x0, y1});
  bg::append(p.outer(), Point{x1, y1});
  bg::append(p.outer(), Point{x1, y0});
  bg::append(p.outer(), Point{x0, y0});
  bg::correct(p);
  return p;
}

MultiPolygon unite(const MultiPolygon& polys) {
  // Polygons whose boxes overlap (transitively) form a cluster; only a cluster's members are united
  // with each other, in input order, so thousands of separate no-fly zones cost O(n log n), not O(n^2).
  const std::size_t n = polys.size();
  std::vector<std::size_t> parent(n);
  for (std::size_t i = 0; i < n; ++i) parent[i] = i;
  auto find = [&](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  {
    using Entry = std::pair<Box, std::size_t>;
    std::vector<Entry> boxes;
    boxes.reserve(n);
    for (std::size_t i = 0; i < n; ++i) boxes.emplace_back(bg::return_envelope<Box>(polys[i]), i);
    const bgi::rtree<Entry, bgi::rstar<16>> tree(boxes.begin(), boxes.end());
    std::vector<Entry> hits;
    for (const auto& [box, i] : boxes) {
      hits.clear();
      tree.query(bgi::intersects(box), std::back_inserter(hits));
      for (const auto& h : hits) {
        const std::size_t a = find(i), b = find(h.second);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
    }
  }
  std::vector<std::vector<std::size_t>> members(n);
  for (std::size_t i = 0; i < n; ++i) members[find(i)].push_back(i);
  MultiPolygon out;
  for (std::size_t root = 0; root < n; ++root) {  // clusters in the order of their first member
    if (members[root].empty()) continue;
    const auto& group = members[root];
    MultiPolygon acc;
    if (group.size() <= kSequentialUnion) {
      for (const std::size_t i : group) {
        MultiPolygon next;
        bg::union_(acc, polys[i], next);
        acc = std::move(next);
      }
    } else {
      // a large cluster (thousands of overlapping zones): united pairwise, level by level, so each
      // polygon takes part in log2(n) unions of similar size instead of n unions with a growing one
      std::vector<MultiPolygon> level;
      level.reserve(group.size());
      for (const std::size_t i : group) {
        MultiPolygon single;
        bg::union_(MultiPolygon{}, polys[i], single);  // corrected like the sequential path
        level.push_back(std::move(single));
      }
      while (level.size() > 1) {
        std::vector<MultiPolygon> next_level;
        next_level.reserve((level.size() + 1) / 2);
        for (std::size_t k = 0; k + 1 < level.size(); k += 2) {
          MultiPolygon merged;
          bg::union_(level[k], level[k + 1], merged);
          next_level.push_back(std::move(merged));
        }
        if (level.size() % 2 == 1) next_level.push_back(std::move(level.back()));
        level = std::move(next_level);
      }
      acc = std::move(level.front());
    }
    for (auto& p : acc) out.push_back(std::move(p));
  }
  return out;
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

namespace {

/// True when segment a-b enters the interior of `poly` deeper than `tol` (segment_enters for one polygon).
bool enters(const Polygon& poly, Point a, Point b, double tol) {
  const Segment seg{a, b};
  if (!bg::intersects(seg, poly)) return false;  // cheap test first
  const Polyline line{a, b};
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
  return false;
}

/// The visibility-graph nodes of one ring: its vertices pushed outward by `clearance` (and 3 x clearance)
/// along the vertex bisector.
void add_ring_nodes(const Polygon::ring_type& ring, bool outer, double clearance, std::vector<Point>& nodes) {
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
    for (double k : {1.0, 3.0})
      nodes.push_back(Point{p.x() + nx / nl * clearance * k, p.y() + ny / nl * clearance * k});
  }
}

}  // namespace

bool segment_enters(const MultiPolygon& obstacles, Point a, Point b, double tol) {
  for (const auto& poly : obstacles)
    if (enters(poly, a, b, tol)) return true;
  return false;
}

bool segment_enters(const Polygon& obstacle, Point a, Point b, double tol) {
  return enters(obstacle, a, b, tol);
}

struct Router::Index {
  using Entry = std::pair<Box, std::size_t>;
  bgi::rtree<Entry, bgi::rstar<16>> tree;
};

Router::Router(MultiPolygon obstacles, double clearance)
    : obstacles_(std::move(obstacles)), index_(std::make_unique<Index>()) {
  std::vector<Index::Entry> boxes;
  boxes.reserve(obstacles_.size());
  nodes_.resize(obstacles_.size());
  for (std::size_t i = 0; i < obstacles_.size(); ++i) {
    boxes.emplace_back(bg::return_envelope<Box>(obstacles_[i]), i);
    add_ring_nodes(bg::exterior_ring(obstacles_[i]), true, clearance, nodes_[i]);
    for (const auto& in : bg::interior_rings(obstacles_[i])) add_ring_nodes(in, false, clearance, nodes_[i]);
  }
  index_->tree = decltype(index_->tree)(boxes.begin(), boxes.end());
}

Router::~Router() = default;

bool Router::clear_of(Point a, Point b, const std::vector<char>* only,
                      std::vector<std::size_t>* entered) const {
  // the obstacles whose bounding box the segment itself crosses (not its own bounding box: a long
  // diagonal's box holds every obstacle of a field)
  const Segment seg{a, b};
  bool clear = true;
  for (auto it = index_->tree.qbegin(bgi::intersects(seg)); it != index_->tree.qend(); ++it) {
    const std::size_t i = it->second;
    if (only != nullptr && !(*only)[i]) continue;
    if (!enters(obstacles_[i], a, b, 0.0)) continue;
    clear = false;
    if (entered == nullptr) break;
    entered->push_back(i);
  }
  return clear;
}

bool Router::clear(Point a, Point b) const { return clear_of(a, b, nullptr, nullptr); }

std::vector<Point> Router::route(Point a, Point b) const {
  // touching an obstacle's boundary is fine; entering it is not
  std::vector<std::size_t> entered;
  if (clear_of(a, b, nullptr, &entered)) return {a, b};
  std::vector<char> in_graph(obstacles_.size(), 0);
  if (obstacles_.size() <= kFullGraph) std::fill(in_graph.begin(), in_graph.end(), 1);
  for (const std::size_t i : entered) in_graph[i] = 1;
  for (;;) {
    // nodes: a, b, then the nodes of the obstacles in the graph (in obstacle order)
    std::vector<Point> nodes{a, b};
    for (std::size_t i = 0; i < obstacles_.size(); ++i)
      if (in_graph[i]) nodes.insert(nodes.end(), nodes_[i].begin(), nodes_[i].end());
    // Lazy A* on the visibility graph: straight-line distance to b as the heuristic (consistent), and
    // an edge checked against the obstacles in the graph only when it leaves the queue as the best
    // way to its node; a node leaves for good with its first clear edge, at its shortest distance.
    const std::size_t n = nodes.size();
    std::vector<std::size_t> prev(n, n);
    std::vector<char> done(n, 0);
    struct Entry {
      double f, g;
      std::size_t node, from;
      bool operator>(const Entry& o) const { return f > o.f || (f == o.f && node > o.node); }
    };
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> pq;
    auto h = [&](std::size_t v) { return bg::distance(nodes[v], nodes[1]); };
    pq.push({h(0), 0.0, 0, n});
    bool found = false;
    while (!pq.empty()) {
      const Entry e = pq.top();
      pq.pop();
      if (done[e.node]) continue;
      if (e.from != n && !clear_of(nodes[e.from], nodes[e.node], &in_graph, nullptr)) continue;
      done[e.node] = 1;
      prev[e.node] = e.from;
      if (e.node == 1) {
        found = true;
        break;
      }
      for (std::size_t v = 0; v < n; ++v)
        if (!done[v]) {
          const double g = e.g + bg::distance(nodes[e.node], nodes[v]);
          pq.push({g + h(v), g, v, e.node});
        }
    }
    if (!found) return {a, b};
    std::vector<Point> path;
    for (std::size_t v = 1; v != n; v = prev[v]) path.push_back(nodes[v]);
    std::reverse(path.begin(), path.end());
    // obstacles outside the graph that the route enters join it; done when there are none
    entered.clear();
    for (std::size_t k = 1; k < path.size(); ++k) clear_of(path[k - 1], path[k], nullptr, &entered);
    bool grew = false;
    for (const std::size_t i : entered)
      if (!in_graph[i]) in_graph[i] = 1, grew = true;
    if (!grew) return path;
  }
}

std::vector<Point> route_around(const MultiPolygon& obstacles, Point a, Point b, double clearance) {
  return Router(obstacles, clearance).route(a, b);
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
