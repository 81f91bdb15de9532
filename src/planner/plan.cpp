// The facade: plan(mission, options, progress) -> plan. Chains the stages:
// geodesy -> geometry (free space) -> planner stage (DARP) -> transit legs -> WGS84.
#include <chrono>
#include <cmath>
#include <random>

#include "darp/darp_planner.hpp"
#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "planner/local_mission.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover {

namespace planner {

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

}  // namespace planner

Plan plan(const Mission& mission, const PlanOptions& options, const Progress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  Plan out;
  out.mission = mission;
  if (options.seed) out.mission.seed = *options.seed;
  if (out.mission.uavs.empty()) throw InputError("uavs", "at least one UAV is needed");
  if (out.mission.planner != "darp")
    throw InputError("planner", "unknown planner '" + out.mission.planner + "' (available: darp)");

  const planner::LocalMission lm = planner::to_local(out.mission);
  out.origin = lm.frame.origin();
  out.free_area_m2 = bg::area(lm.free);
  if (lm.free.empty() || out.free_area_m2 <= 0.0)
    throw InputError("no_fly_zones", "the no-fly zones remove the whole area");

  // starts: given, or drawn inside the free area from the seed
  std::mt19937_64 rng(out.mission.seed ^ 0x5eedf00dULL);
  darp::Input in;
  in.free = lm.free;
  in.no_fly = lm.no_fly;
  in.ds = out.mission.spacing_m;
  in.mode = out.mission.mode;
  in.seed = out.mission.seed;
  for (auto& u : out.mission.uavs) {
    Point s = u.start ? lm.frame.to_local(*u.start) : planner::random_free_point(lm.free, rng);
    u.start_resolved = u.start ? *u.start : lm.frame.to_wgs84(s);
    in.starts.push_back(s);
    in.shares.push_back(u.share);
  }

  const darp::Output res = darp::run(in, options, progress);
  out.placement = res.placement;
  out.grid = res.grid;
  out.warnings = res.warnings;
  out.darp_converged = res.converged;
  out.darp_iterations = res.iterations;

  auto make_part = [&](PartKind kind, std::vector<Point> pts) {
    PathPart part{kind, std::move(pts), {}};
    part.wgs84.reserve(part.local.size());
    for (const auto& p : part.local) part.wgs84.push_back(lm.frame.to_wgs84(p));
    return part;
  };
  for (std::size_t i = 0; i < out.mission.uavs.size(); ++i) {
    const auto& u = out.mission.uavs[i];
    const auto& r = res.uavs.at(i);
    UavPlan up;
    up.id = u.id;
    up.share_requested = u.share;
    up.share_actual = r.share_actual;
    up.cells = r.cells;
    up.regions = static_cast<int>(r.loops.size());
    Point here = in.starts[i];
    auto transit_to = [&](Point target) {
      if (bg::distance(here, target) < 1e-6) return;
      up.parts.push_back(make_part(PartKind::Transit, geometry::route_around(lm.no_fly, here, target)));
      here = target;
    };
    for (const auto& loop : r.loops) {
      if (loop.empty()) continue;
      transit_to(loop.front());
      up.parts.push_back(make_part(PartKind::Coverage, loop));
      up.coverage_length_m += geometry::length(loop);
      up.turns += static_cast<int>(loop.size());
      here = loop.back();
    }
    transit_to(in.starts[i]);
    for (const auto& part : up.parts) up.length_m += geometry::length(part.local);
    out.uavs.push_back(std::move(up));
  }
  if (progress) progress("done", 1.0);
  out.compute_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace uavcover
