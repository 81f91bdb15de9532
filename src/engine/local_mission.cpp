#include "engine/local_mission.hpp"

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

}  // namespace uavcover::engine
