#include "terrain/terrain.hpp"

#include <algorithm>
#include <cmath>

#include "uavcover/error.hpp"

namespace uavcover {

bool HeightGrid::contains(LonLat p) const {
  return p.lon >= lon0 && p.lat >= lat0 && p.lon <= lon0 + (cols - 1) * dlon &&
         p.lat <= lat0 + (rows - 1) * dlat;
}

double HeightGrid::at(LonLat p) const {
  if (cols < 2 || rows < 2 ||
      heights.size() != static_cast<std::size_t>(cols) * static_cast<std::size_t>(rows))
    return 0.0;
  const double fx = std::clamp((p.lon - lon0) / dlon, 0.0, static_cast<double>(cols - 1));
  const double fy = std::clamp((p.lat - lat0) / dlat, 0.0, static_cast<double>(rows - 1));
  const int c = std::min(static_cast<int>(fx), cols - 2);
  const int r = std::min(static_cast<int>(fy), rows - 2);
  const double tx = fx - c, ty = fy - r;
  auto h = [&](int cc, int rr) {
    return static_cast<double>(heights[static_cast<std::size_t>(rr) * static_cast<std::size_t>(cols) +
                                       static_cast<std::size_t>(cc)]);
  };
  return (1 - ty) * ((1 - tx) * h(c, r) + tx * h(c + 1, r)) +
         ty * ((1 - tx) * h(c, r + 1) + tx * h(c + 1, r + 1));
}

namespace terrain {

const HeightGrid* grid(const Mission& mission) {
  if (!mission.terrain) return nullptr;
  if (!mission.terrain->grid)
    throw InputError("terrain.dem", "the elevation model '" + mission.terrain->dem +
                                        "' has not been read (only the command line reads DEM files)");
  return mission.terrain->grid.get();
}

std::vector<Sample> profile(const HeightGrid& grid, const geodesy::LocalFrame& frame, Point a, Point b) {
  constexpr std::size_t kMaxSamples = 20'000;
  const double len = std::hypot(b.x() - a.x(), b.y() - a.y());
  const double step = std::max(grid.step_m / 4.0, 0.05);
  const auto n =
      static_cast<std::size_t>(std::clamp(std::ceil(len / step), 1.0, static_cast<double>(kMaxSamples)));
  std::vector<Sample> out;
  out.reserve(n + 1);
  for (std::size_t k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) / static_cast<double>(n);
    const Point p{a.x() + t * (b.x() - a.x()), a.y() + t * (b.y() - a.y())};
    out.push_back({t * len, p, grid.at(frame.to_wgs84(p))});
  }
  return out;
}

std::vector<Sample> follow_points(const HeightGrid& grid, const geodesy::LocalFrame& frame, Point a, Point b,
                                  double tolerance_m) {
  const std::vector<Sample> prof = profile(grid, frame, a, b);
  // Douglas-Peucker on the vertical deviation, with a stack of index ranges (no recursion)
  std::vector<char> keep(prof.size(), 0);
  keep.front() = keep.back() = 1;
  std::vector<std::pair<std::size_t, std::size_t>> todo{{0, prof.size() - 1}};
  while (!todo.empty()) {
    const auto [i, j] = todo.back();
    todo.pop_back();
    if (j <= i + 1) continue;
    double worst = 0.0;
    std::size_t at = i;
    for (std::size_t k = i + 1; k < j; ++k) {
      const double t = (prof[k].s - prof[i].s) / (prof[j].s - prof[i].s);
      const double d = std::fabs(prof[k].ground - (prof[i].ground + t * (prof[j].ground - prof[i].ground)));
      if (d > worst) worst = d, at = k;
    }
    if (worst > 0.9 * tolerance_m) {  // a 10 % margin for the ground between samples
      keep[at] = 1;
      todo.emplace_back(i, at);
      todo.emplace_back(at, j);
    }
  }
  std::vector<Sample> out;
  for (std::size_t k = 0; k < prof.size(); ++k)
    if (keep[k]) out.push_back(prof[k]);
  return out;
}

double home_ground(const Mission& mission, std::size_t uav) {
  const HeightGrid* g = grid(mission);
  return g != nullptr && uav < mission.uavs.size() ? g->at(mission.uavs[uav].start_resolved) : 0.0;
}

}  // namespace terrain
}  // namespace uavcover
