#include "engine/rally.hpp"

#include <algorithm>
#include <limits>

#include <boost/geometry/algorithms/point_on_surface.hpp>

#include "geometry/geometry.hpp"

namespace uavcover::engine {

std::vector<LonLat> propose_rally(const Plan& plan, const MultiPolygon& no_fly,
                                  const geodesy::LocalFrame& frame) {
  constexpr int kGrid = 16;
  std::vector<LonLat> out;
  for (const auto& up : plan.uavs) {
    const MultiPolygon& region = up.region_local;
    if (region.empty() || !(bg::area(region) > 0.0)) continue;
    Point centre;
    bg::centroid(region, centre);
    bg::model::box<Point> box;
    bg::envelope(region, box);
    std::vector<Point> candidates;
    if (bg::within(centre, region)) candidates.push_back(centre);
    const double w = box.max_corner().x() - box.min_corner().x();
    const double h = box.max_corner().y() - box.min_corner().y();
    for (int iy = 0; iy < kGrid; ++iy)
      for (int ix = 0; ix < kGrid; ++ix) {
        const Point p(box.min_corner().x() + (ix + 0.5) * w / kGrid,
                      box.min_corner().y() + (iy + 0.5) * h / kGrid);
        if (bg::within(p, region)) candidates.push_back(p);
      }
    if (candidates.empty()) {  // a sliver: a point on its surface
      Point p;
      bg::point_on_surface(region, p);
      candidates.push_back(p);
    }
    std::vector<double> clear(candidates.size(), std::numeric_limits<double>::infinity());
    if (!no_fly.empty())
      for (std::size_t k = 0; k < candidates.size(); ++k)
        clear[k] = bg::within(candidates[k], no_fly) ? -1.0 : geometry::distance(no_fly, candidates[k]);
    const double best_clear = *std::max_element(clear.begin(), clear.end());
    const double need = std::min(kRallyClearanceM, best_clear);
    std::size_t pick = candidates.size();
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      if (clear[k] < need) continue;
      const double d = bg::distance(candidates[k], centre);
      if (d < nearest) {
        nearest = d;
        pick = k;
      }
    }
    if (pick == candidates.size() || clear[pick] < 0.0) continue;  // every candidate in a no-fly zone
    out.push_back(frame.to_wgs84(candidates[pick]));
  }
  return out;
}

}  // namespace uavcover::engine
