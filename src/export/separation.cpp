#include "export/separation.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "geodesy/local_frame.hpp"

namespace uavcover::exporting {

RegionMap::RegionMap(const Plan& plan) : plan_(&plan) {
  const GridInfo& g = plan.grid;
  const bool grid_ok = g.cell_m > 0.0 && g.rows > 0 && g.cols > 0 &&
                       g.owner.size() == static_cast<std::size_t>(g.rows) * static_cast<std::size_t>(g.cols);
  if (grid_ok) {
    // confirm the convention: coverage waypoints lie inside mega-cells of their own UAV
    // candidates: origin as a local point (rotate p - origin) or as a rotated-frame point, either sign
    for (int mode = 0; mode < 4; ++mode) {
      std::size_t total = 0, hits = 0;
      for (std::size_t u = 0; u < plan.uavs.size(); ++u)
        for (const auto& part : plan.uavs[u].parts)
          if (part.kind == PartKind::Coverage)
            for (const auto& p : part.local) {
              ++total;
              hits += grid_owner(p, mode) == static_cast<int>(u) ? 1 : 0;
            }
      if (total > 0 && static_cast<double>(hits) >= 0.95 * static_cast<double>(total)) {
        use_grid_ = true;
        mode_ = mode;
        return;
      }
    }
  }
  loops_.resize(plan.uavs.size());
  for (std::size_t u = 0; u < plan.uavs.size(); ++u)
    for (const auto& part : plan.uavs[u].parts) {
      if (part.kind != PartKind::Coverage || part.local.size() < 4) continue;
      Polygon poly;
      for (const auto& p : part.local) bg::append(poly.outer(), p);
      bg::correct(poly);
      loops_[u].push_back(poly);
    }
}

int RegionMap::grid_owner(Point p, int mode) const {
  const GridInfo& g = plan_->grid;
  const double sign = (mode & 1) != 0 ? -1.0 : 1.0;
  const bool local_origin = (mode & 2) == 0;
  const double th = sign * g.rotation_deg * std::numbers::pi / 180.0;
  // offsets along the grid's axes: rotate by -rotation
  const double x = local_origin ? p.x() - g.origin.x() : p.x();
  const double y = local_origin ? p.y() - g.origin.y() : p.y();
  double qx = x * std::cos(th) + y * std::sin(th);
  double qy = -x * std::sin(th) + y * std::cos(th);
  if (!local_origin) {
    qx -= g.origin.x();
    qy -= g.origin.y();
  }
  const double fc = std::floor(qx / g.cell_m);
  const double fr = std::floor(qy / g.cell_m);
  if (fc < 0 || fr < 0 || fc >= g.cols || fr >= g.rows) return -1;
  return g
      .owner[static_cast<std::size_t>(fr) * static_cast<std::size_t>(g.cols) + static_cast<std::size_t>(fc)];
}

int RegionMap::owner(Point p) const {
  if (use_grid_) return grid_owner(p, mode_);
  for (std::size_t u = 0; u < loops_.size(); ++u)
    if (!loops_[u].empty() && bg::within(p, loops_[u])) return static_cast<int>(u);
  return -1;
}

std::vector<std::string> check_separation(const Plan& plan, const AltitudeOptions& options,
                                          const SeparationOptions& sep) {
  std::vector<std::string> problems;
  const std::size_t n = plan.uavs.size();
  const double mission_alt = plan.mission.altitude_m;
  const AltitudeOptions opt = resolve_altitudes(options, n, mission_alt);  // the altitudes actually flown
  for (std::size_t i = 0; i < n; ++i) {
    const double ti = transition_altitude(opt, i, mission_alt);
    if (ti < mission_alt + sep.min_vertical_m)
      problems.push_back(
          fmt::format("uav '{}': transition altitude {} m is not above the mission altitude {} m (raise the "
                      "transition base)",
                      plan.uavs[i].id, ti, mission_alt));
    for (std::size_t j = i + 1; j < n; ++j) {
      const double tj = transition_altitude(opt, j, mission_alt);
      if (std::abs(ti - tj) < sep.min_vertical_m)
        problems.push_back(fmt::format(
            "uavs '{}' and '{}' share the transition altitude {} m (use a non-zero transition step)",
            plan.uavs[i].id, plan.uavs[j].id, ti));
    }
  }

  const RegionMap regions(plan);
  const geodesy::LocalFrame frame(plan.origin);
  double step = sep.sample_step_m;
  if (plan.grid.cell_m > 0.0) step = std::min(step, plan.grid.cell_m / 4.0);
  step = std::max(step, 0.01);
  for (std::size_t u = 0; u < n; ++u) {
    const auto items = mission_items(plan, u, opt);
    const MissionItem* prev = nullptr;
    for (const auto& it : items) {
      const bool positioned =
          it.command == kNavWaypoint || it.command == kNavTakeoff || it.command == kNavLand;
      if (!positioned) continue;
      if (prev != nullptr) {
        const bool low = std::min(prev->alt, it.alt) <= mission_alt + 1e-3;
        const bool coverage_leg =
            prev->role == "coverage" && it.role == "coverage" && prev->part == it.part && it.part >= 0;
        if (low && !coverage_leg && it.command != kNavLand) {
          const Point a = frame.to_local({prev->lon, prev->lat});
          const Point b = frame.to_local({it.lon, it.lat});
          const double len = bg::distance(a, b);
          const int steps = std::max(1, static_cast<int>(std::ceil(len / step)));
          for (int k = 0; k <= steps; ++k) {
            const double f = static_cast<double>(k) / steps;
            const Point p{a.x() + f * (b.x() - a.x()), a.y() + f * (b.y() - a.y())};
            const int o = regions.owner(p);
            if (o >= 0 && o != static_cast<int>(u)) {
              problems.push_back(
                  fmt::format("uav '{}': leg at mission altitude from ({:.7f}, {:.7f}) to ({:.7f}, {:.7f}) "
                              "enters the region of "
                              "uav '{}'",
                              plan.uavs[u].id, prev->lon, prev->lat, it.lon, it.lat,
                              plan.uavs[static_cast<std::size_t>(o)].id));
              break;
            }
          }
        }
      }
      prev = &it;
    }
  }
  return problems;
}

std::vector<std::string> separation_warnings(const Plan& plan) {
  std::vector<std::string> warnings;
  const RegionMap regions(plan);
  const geodesy::LocalFrame frame(plan.origin);
  for (std::size_t u = 0; u < plan.uavs.size() && u < plan.mission.uavs.size(); ++u) {
    // take-off and landing cross the mission altitude vertically above home
    const int o = regions.owner(frame.to_local(plan.mission.uavs[u].start_resolved));
    if (o >= 0 && o != static_cast<int>(u))
      warnings.push_back(
          fmt::format("uav '{}': take-off and landing at home cross the mission altitude inside the "
                      "region of uav '{}'",
                      plan.uavs[u].id, plan.uavs[static_cast<std::size_t>(o)].id));
  }
  return warnings;
}

}  // namespace uavcover::exporting
