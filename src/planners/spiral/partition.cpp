#include "planners/spiral/partition.hpp"

#include <algorithm>
#include <boost/geometry/index/rtree.hpp>
#include <cmath>
#include <deque>
#include <limits>
#include <numbers>
#include <queue>
#include <tuple>

namespace uavcover::planners::spiral {

namespace {

namespace bgi = bg::index;

double dist(Point a, Point b) { return std::hypot(a.x() - b.x(), a.y() - b.y()); }

Point vertex(const Mesh& m, std::size_t t, int i) {
  return m.vertices[static_cast<std::size_t>(m.triangles[t][static_cast<std::size_t>(i)])];
}

/// Seeds: per UAV the triangle nearest its start that no earlier UAV took.
std::vector<int> seeds_of(const std::vector<Point>& centroid, const std::vector<Point>& starts) {
  using Value = std::pair<Point, int>;
  std::vector<Value> values;
  values.reserve(centroid.size());
  for (std::size_t t = 0; t < centroid.size(); ++t) values.emplace_back(centroid[t], static_cast<int>(t));
  const bgi::rtree<Value, bgi::rstar<16>> tree(values.begin(), values.end());
  std::vector<int> seed;
  std::vector<char> taken(centroid.size(), 0);
  for (const Point s : starts) {
    std::vector<Value> near;
    tree.query(bgi::nearest(s, static_cast<unsigned>(starts.size() + 1)), std::back_inserter(near));
    std::sort(near.begin(), near.end(), [&](const Value& a, const Value& b) {
      return std::make_pair(dist(a.first, s), a.second) < std::make_pair(dist(b.first, s), b.second);
    });
    for (const auto& [p, t] : near)
      if (!taken[static_cast<std::size_t>(t)]) {
        taken[static_cast<std::size_t>(t)] = 1;
        seed.push_back(t);
        break;
      }
  }
  return seed;
}

}  // namespace

std::vector<Point> centroids(const Mesh& mesh) {
  std::vector<Point> out;
  out.reserve(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Point a = vertex(mesh, t, 0), b = vertex(mesh, t, 1), c = vertex(mesh, t, 2);
    out.emplace_back((a.x() + b.x() + c.x()) / 3.0, (a.y() + b.y() + c.y()) / 3.0);
  }
  return out;
}

std::vector<double> areas(const Mesh& mesh) {
  std::vector<double> out;
  out.reserve(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Point a = vertex(mesh, t, 0), b = vertex(mesh, t, 1), c = vertex(mesh, t, 2);
    out.push_back(0.5 * std::abs((b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y())));
  }
  return out;
}

AngleStats angle_stats(const Mesh& mesh) {
  AngleStats s;
  s.min_deg = mesh.triangles.empty() ? 0.0 : 180.0;
  std::size_t near60 = 0, angles = 0;
  double sum_min = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    double smallest = 180.0;
    for (int i = 0; i < 3; ++i) {
      const Point p = vertex(mesh, t, i), q = vertex(mesh, t, (i + 1) % 3), r = vertex(mesh, t, (i + 2) % 3);
      const double ux = q.x() - p.x(), uy = q.y() - p.y(), vx = r.x() - p.x(), vy = r.y() - p.y();
      const double deg =
          std::atan2(std::abs(ux * vy - uy * vx), ux * vx + uy * vy) * 180.0 / std::numbers::pi;
      ++s.bins[std::min<std::size_t>(17, static_cast<std::size_t>(deg / 10.0))];
      smallest = std::min(smallest, deg);
      if (deg >= 50.0 && deg <= 70.0) ++near60;
      ++angles;
    }
    s.min_deg = std::min(s.min_deg, smallest);
    sum_min += smallest;
  }
  if (!mesh.triangles.empty()) {
    s.mean_min_deg = sum_min / static_cast<double>(mesh.triangles.size());
    s.within_10_of_60 = static_cast<double>(near60) / static_cast<double>(angles);
  }
  return s;
}

double longest_edge(const Mesh& mesh) {
  double best = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int i = 0; i < 3; ++i) best = std::max(best, dist(vertex(mesh, t, i), vertex(mesh, t, (i + 1) % 3)));
  return best;
}

Partition partition(const Mesh& mesh, const std::vector<Point>& centroid, const std::vector<double>& area,
                    const std::vector<Point>& starts, const std::vector<double>& shares, double tolerance,
                    const Context& ctx) {
  const std::size_t n = mesh.triangles.size(), uavs = starts.size();
  Partition out;
  out.owner.assign(n, -1);
  out.share.assign(uavs, 0.0);
  if (n == 0 || uavs == 0) return out;
  double total = 0.0;
  for (double a : area) total += a;
  std::vector<double> target(uavs), have(uavs, 0.0);
  for (std::size_t k = 0; k < uavs; ++k) target[k] = shares[k] * total;
  auto fill = [&](std::size_t k) {
    return target[k] > 0.0 ? have[k] / target[k] : std::numeric_limits<double>::infinity();
  };

  // growth: per UAV a frontier ordered by distance from its seed
  using Entry = std::pair<double, int>;
  std::vector<std::priority_queue<Entry, std::vector<Entry>, std::greater<>>> frontier(uavs);
  std::vector<Point> origin(uavs);
  auto take = [&](std::size_t k, int t) {
    out.owner[static_cast<std::size_t>(t)] = static_cast<int>(k);
    have[k] += area[static_cast<std::size_t>(t)];
    for (int nb : mesh.neighbours[static_cast<std::size_t>(t)])
      if (nb >= 0 && out.owner[static_cast<std::size_t>(nb)] < 0)
        frontier[k].emplace(dist(centroid[static_cast<std::size_t>(nb)], origin[k]), nb);
  };
  out.seed = seeds_of(centroid, starts);
  std::size_t assigned = 0;
  for (std::size_t k = 0; k < out.seed.size(); ++k) {
    origin[k] = centroid[static_cast<std::size_t>(out.seed[k])];
    take(k, out.seed[k]);
    ++assigned;
  }
  out.seed.resize(uavs, -1);  // more UAVs than triangles: the last ones get nothing
  while (assigned < n) {
    if (assigned % 4096 == 0) ctx.check();
    std::size_t best = uavs;
    for (std::size_t k = 0; k < uavs; ++k)
      if (!frontier[k].empty() && (best == uavs || fill(k) < fill(best))) best = k;
    if (best == uavs) {
      // a component no growth reached: the neediest UAV takes its triangle nearest that UAV's seed
      std::size_t k = 0;
      for (std::size_t j = 1; j < uavs; ++j)
        if (out.seed[j] >= 0 && fill(j) < fill(k)) k = j;
      int nearest = -1;
      for (std::size_t t = 0; t < n; ++t)
        if (out.owner[t] < 0 &&
            (nearest < 0 ||
             dist(centroid[t], origin[k]) < dist(centroid[static_cast<std::size_t>(nearest)], origin[k])))
          nearest = static_cast<int>(t);
      take(k, nearest);
      ++assigned;
      ++out.extra_seeds;
      continue;
    }
    const int t = frontier[best].top().second;
    frontier[best].pop();
    if (out.owner[static_cast<std::size_t>(t)] >= 0) continue;
    take(best, t);
    ++assigned;
  }

  // balancing: move border triangles from a sub-area to an adjacent one with less (over target)
  std::vector<int> stamp(n, 0);
  int generation = 0;
  auto removable = [&](int t) {
    const int i = out.owner[static_cast<std::size_t>(t)];
    if (out.seed[static_cast<std::size_t>(i)] == t) return false;
    std::vector<int> same;
    for (int nb : mesh.neighbours[static_cast<std::size_t>(t)])
      if (nb >= 0 && out.owner[static_cast<std::size_t>(nb)] == i) same.push_back(nb);
    if (same.size() <= 1) return true;
    // the others must meet again without t, searched locally (a bounded search; false when unsure)
    ++generation;
    stamp[static_cast<std::size_t>(t)] = generation;
    std::deque<int> queue{same[0]};
    stamp[static_cast<std::size_t>(same[0])] = generation;
    int budget = 256;
    while (!queue.empty() && budget-- > 0) {
      const int u = queue.front();
      queue.pop_front();
      for (int nb : mesh.neighbours[static_cast<std::size_t>(u)])
        if (nb >= 0 && out.owner[static_cast<std::size_t>(nb)] == i &&
            stamp[static_cast<std::size_t>(nb)] != generation) {
          stamp[static_cast<std::size_t>(nb)] = generation;
          queue.push_back(nb);
        }
    }
    return std::all_of(same.begin(), same.end(),
                       [&](int s) { return stamp[static_cast<std::size_t>(s)] == generation; });
  };
  const int max_moves = static_cast<int>(std::min<std::size_t>(4 * n, 200000));
  for (out.moves = 0; out.moves < max_moves;) {
    bool balanced = true;
    for (std::size_t k = 0; k < uavs; ++k)
      if (std::abs(have[k] - target[k]) > tolerance * target[k]) balanced = false;
    if (balanced) break;
    ctx.check();
    // candidate moves (t from its owner i to a neighbouring j) that lower the squared deviations
    std::vector<std::tuple<double, double, int, int>> cand;  // -(excess gap), distance to j's seed, t, j
    for (std::size_t t = 0; t < n; ++t) {
      const int i = out.owner[t];
      const double dev_i = have[static_cast<std::size_t>(i)] - target[static_cast<std::size_t>(i)];
      for (int nb : mesh.neighbours[t]) {
        if (nb < 0) continue;
        const int j = out.owner[static_cast<std::size_t>(nb)];
        if (j == i || out.seed[static_cast<std::size_t>(j)] < 0) continue;
        const double gap = dev_i - (have[static_cast<std::size_t>(j)] - target[static_cast<std::size_t>(j)]);
        if (gap <= area[t]) continue;
        cand.emplace_back(-gap, dist(centroid[t], origin[static_cast<std::size_t>(j)]), static_cast<int>(t),
                          j);
      }
    }
    std::sort(cand.begin(), cand.end());
    bool moved = false;
    for (const auto& [g, d, t, j] : cand) {
      if (!removable(t)) continue;
      const auto i = static_cast<std::size_t>(out.owner[static_cast<std::size_t>(t)]);
      have[i] -= area[static_cast<std::size_t>(t)];
      have[static_cast<std::size_t>(j)] += area[static_cast<std::size_t>(t)];
      out.owner[static_cast<std::size_t>(t)] = j;
      moved = true;
      break;
    }
    if (!moved) break;
    ++out.moves;
  }
  for (std::size_t k = 0; k < uavs; ++k) {
    out.share[k] = have[k] / total;
    if (shares[k] > 0.0)
      out.max_deviation = std::max(out.max_deviation, std::abs(out.share[k] - shares[k]) / shares[k]);
  }
  return out;
}

std::vector<int> levels(const Mesh& mesh, const std::vector<int>& owner) {
  const std::size_t n = mesh.triangles.size();
  std::vector<int> level(n, -1);
  std::deque<int> queue;
  for (std::size_t t = 0; t < n; ++t)
    for (int nb : mesh.neighbours[t])
      if (nb < 0 || owner[static_cast<std::size_t>(nb)] != owner[t]) {
        level[t] = 0;
        queue.push_back(static_cast<int>(t));
        break;
      }
  while (!queue.empty()) {
    const auto t = static_cast<std::size_t>(queue.front());
    queue.pop_front();
    for (int nb : mesh.neighbours[t])
      if (nb >= 0 && level[static_cast<std::size_t>(nb)] < 0 &&
          owner[static_cast<std::size_t>(nb)] == owner[t]) {
        level[static_cast<std::size_t>(nb)] = level[t] + 1;
        queue.push_back(nb);
      }
  }
  return level;
}

}  // namespace uavcover::planners::spiral
