#include "engine/local_mission.hpp"

#include <algorithm>

#include "geometry/geometry.hpp"

namespace uavcover::engine {

LocalMission to_local(const Mission& mission) {
  LocalMission lm{geodesy::LocalFrame(geodesy::centroid(mission.area)), {}, {}, {}};
  lm.area = geometry::unite(geometry::to_local(mission.area, lm.frame));
  lm.no_fly = geometry::unite(geometry::to_local(mission.no_fly_zones, lm.frame));
  lm.free = geometry::free_space(lm.area, lm.no_fly);
  return lm;
}

Point random_free_point(const MultiPolygon& free, std::mt19937_64& rng) {
  bg::model::box<Point> box;
  bg::envelope(free, box);
  std::uniform_real_distribution<double> ux(box.min_corner().x(), box.max_corner().x());
  std::uniform_real_distribution<double> uy(box.min_corner().y(), box.max_corner().y());
  for (int i = 0; i < 100000; ++i) {
    const Point p{ux(rng), uy(rng)};
    if (bg::within(p, free)) return p;
  }
  Point c;
  bg::centroid(free, c);
  return c;
}

std::vector<GeoPolygon> to_wgs84(const MultiPolygon& mp, const geodesy::LocalFrame& frame) {
  std::vector<GeoPolygon> out;
  for (const auto& poly : mp) {
    GeoPolygon gp;
    auto ring_of = [&](const auto& ring) {
      GeoRing r;
      for (const auto& p : ring) r.push_back(frame.to_wgs84(p));
      return r;
    };
    // GeoJSON (RFC 7946): counter-clockwise outer ring, clockwise holes; Boost's are the reverse
    GeoRing outer = ring_of(poly.outer());
    std::reverse(outer.begin(), outer.end());
    gp.push_back(std::move(outer));
    for (const auto& inner : poly.inners()) {
      GeoRing h = ring_of(inner);
      std::reverse(h.begin(), h.end());
      gp.push_back(std::move(h));
    }
    out.push_back(std::move(gp));
  }
  return out;
}

}  // namespace uavcover::engine
