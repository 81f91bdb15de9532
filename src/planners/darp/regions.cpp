#include "planners/darp/regions.hpp"

#include <algorithm>
#include <map>
#include <utility>

namespace uavcover::darp {

MultiPolygon cells_to_polygons(int rows, int cols, const std::vector<int>& owner, int uav,
                               const std::function<Point(int c, int r)>& corner) {
  using V = std::pair<int, int>;  // (column, row) of a grid corner
  auto own = [&](int r, int c) {
    return r >= 0 && c >= 0 && r < rows && c < cols &&
           owner[static_cast<std::size_t>(r) * static_cast<std::size_t>(cols) +
                 static_cast<std::size_t>(c)] == uav;
  };
  // directed boundary edges with the owned cell on their left (counter-clockwise around it)
  std::multimap<V, V> edges;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      if (!own(r, c)) continue;
      if (!own(r - 1, c)) edges.emplace(V{c, r}, V{c + 1, r});
      if (!own(r, c + 1)) edges.emplace(V{c + 1, r}, V{c + 1, r + 1});
      if (!own(r + 1, c)) edges.emplace(V{c + 1, r + 1}, V{c, r + 1});
      if (!own(r, c - 1)) edges.emplace(V{c, r + 1}, V{c, r});
    }
  std::vector<std::vector<V>> rings;
  while (!edges.empty()) {
    auto it = edges.begin();
    const V first = it->first;
    V prev = it->first, cur = it->second;
    edges.erase(it);
    std::vector<V> ring{first};
    while (cur != first) {
      // at a vertex where two owned cells touch only diagonally there are two ways on: turn left
      // (stay around the same cell), so that such cells become separate rings
      auto range = edges.equal_range(cur);
      auto pick = range.first;
      if (std::distance(range.first, range.second) > 1) {
        const int dx = cur.first - prev.first, dy = cur.second - prev.second;
        for (auto e = range.first; e != range.second; ++e) {
          const int ex = e->second.first - cur.first, ey = e->second.second - cur.second;
          if (dx * ey - dy * ex > 0) pick = e;  // a left turn
        }
      }
      if (pick == range.second) break;  // cannot happen for a closed edge set
      ring.push_back(cur);
      prev = cur;
      cur = pick->second;
      edges.erase(pick);
    }
    // a ring that passes through a corner twice (cells of one region touching there, around an
    // enclosed part) is split there into simple rings: an outer and a hole touching at that corner
    std::vector<V> open;
    std::map<V, std::size_t> at;
    for (const V& v : ring) {
      if (auto hit = at.find(v); hit != at.end()) {
        rings.emplace_back(open.begin() + static_cast<std::ptrdiff_t>(hit->second), open.end());
        for (std::size_t k = hit->second + 1; k < open.size(); ++k) at.erase(open[k]);
        open.resize(hit->second + 1);
      } else {
        at.emplace(v, open.size());
        open.push_back(v);
      }
    }
    rings.push_back(std::move(open));
  }
  // drop collinear vertices, map to local; counter-clockwise rings are outers, clockwise ones holes
  MultiPolygon outers;
  std::vector<Polygon::ring_type> holes;
  for (const auto& ring : rings) {
    std::vector<V> kept;
    const std::size_t n = ring.size();
    for (std::size_t i = 0; i < n; ++i) {
      const V& a = ring[(i + n - 1) % n];
      const V& b = ring[i];
      const V& c = ring[(i + 1) % n];
      const long cross = static_cast<long>(b.first - a.first) * (c.second - b.second) -
                         static_cast<long>(b.second - a.second) * (c.first - b.first);
      if (cross != 0) kept.push_back(b);
    }
    if (kept.size() < 4) continue;
    long twice_area = 0;
    for (std::size_t i = 0; i < kept.size(); ++i) {
      const V& a = kept[i];
      const V& b = kept[(i + 1) % kept.size()];
      twice_area += static_cast<long>(a.first) * b.second - static_cast<long>(b.first) * a.second;
    }
    Polygon::ring_type out;
    for (const auto& v : kept) out.push_back(corner(v.first, v.second));
    out.push_back(out.front());
    if (twice_area > 0) {
      Polygon poly;
      poly.outer() = std::move(out);
      bg::correct(poly);
      outers.push_back(std::move(poly));
    } else {
      bg::correct(out);
      holes.push_back(std::move(out));
    }
  }
  for (auto& hole : holes) {
    // a hole belongs to the outer ring that contains it
    for (auto& poly : outers) {
      const bool inside =
          std::any_of(hole.begin(), hole.end(), [&](const Point& v) { return bg::within(v, poly.outer()); });
      if (inside) {
        Polygon::ring_type h = hole;
        std::reverse(h.begin(), h.end());  // Boost: holes counter-clockwise
        poly.inners().push_back(std::move(h));
        bg::correct(poly);
        break;
      }
    }
  }
  return outers;
}

}  // namespace uavcover::darp
