#include "export/separation.hpp"

#include "terrain/terrain.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <numbers>

#include <boost/geometry/index/rtree.hpp>

#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"

namespace uavcover::exporting {

using namespace waypoints;  // the waypoint model the formats write

namespace bgi = bg::index;

struct RegionMap::Index {
  using Box = bg::model::box<Point>;
  using Entry = std::pair<Box, std::pair<std::size_t, std::size_t>>;  // (UAV, polygon of its region)
  bgi::rtree<Entry, bgi::rstar<16>> tree;
};

RegionMap::~RegionMap() = default;

RegionMap::RegionMap(const Plan& plan) : index_(std::make_unique<Index>()) {
  regions_.resize(plan.uavs.size());
  for (std::size_t u = 0; u < plan.uavs.size(); ++u) {
    regions_[u] = plan.uavs[u].region_local;
    if (!regions_[u].empty()) continue;
    // a plan without regions (paths from another tool): the areas its closed coverage loops enclose
    for (const auto& part : plan.uavs[u].parts) {
      if (part.kind != PartKind::Coverage || part.local.size() < 4) continue;
      if (bg::distance(part.local.front(), part.local.back()) > 1e-6) continue;
      Polygon poly;
      for (const auto& p : part.local) bg::append(poly.outer(), p);
      bg::correct(poly);
      regions_[u].push_back(poly);
    }
  }
  std::vector<Index::Entry> boxes;
  for (std::size_t u = 0; u < regions_.size(); ++u)
    for (std::size_t k = 0; k < regions_[u].size(); ++k)
      boxes.emplace_back(bg::return_envelope<Index::Box>(regions_[u][k]), std::pair{u, k});
  index_->tree = decltype(index_->tree)(boxes.begin(), boxes.end());
}

int RegionMap::owner(Point p) const {
  // the lowest UAV index whose region holds p
  int best = -1;
  for (auto it = index_->tree.qbegin(bgi::intersects(p)); it != index_->tree.qend(); ++it) {
    const auto [u, k] = it->second;
    if ((best < 0 || static_cast<int>(u) < best) && bg::within(p, regions_[u][k])) best = static_cast<int>(u);
  }
  return best;
}

int RegionMap::entered_by(Point a, Point b, std::size_t except, double tol) const {
  Index::Box box;
  bg::envelope(bg::model::segment<Point>(a, b), box);
  int best = -1;
  for (auto it = index_->tree.qbegin(bgi::intersects(box)); it != index_->tree.qend(); ++it) {
    const auto [u, k] = it->second;
    if (u == except || (best >= 0 && static_cast<int>(u) >= best)) continue;
    if (geometry::segment_enters(regions_[u][k], a, b, tol)) best = static_cast<int>(u);
  }
  return best;
}

std::vector<std::string> check_separation(const Plan& plan, const AltitudeOptions& options,
                                          const SeparationOptions& sep) {
  std::vector<std::string> problems;
  const std::size_t n = plan.uavs.size();
  const double mission_alt = plan.mission.altitude_m;
  const AltitudeOptions opt =
      resolve_altitudes(options, altitude_slots(plan), mission_alt);  // the altitudes actually flown
  for (std::size_t i = 0; i < n; ++i) {
    const double ti = transition_altitude(opt, altitude_slot(plan, i), mission_alt);
    if (ti < mission_alt + sep.min_vertical_m)
      problems.push_back(
          fmt::format("uav '{}': transition altitude {} m is not above the mission altitude {} m (raise the "
                      "transition base)",
                      plan.uavs[i].id, ti, mission_alt));
    for (std::size_t j = i + 1; j < n; ++j) {
      // altitude layers: UAVs share a layer only where the conflict graph found no conflict
      if (altitude_slots(plan) < n && altitude_slot(plan, i) == altitude_slot(plan, j)) continue;
      const double tj = transition_altitude(opt, altitude_slot(plan, j), mission_alt);
      if (std::abs(ti - tj) < sep.min_vertical_m)
        problems.push_back(fmt::format(
            "uavs '{}' and '{}' share the transition altitude {} m (use a non-zero transition step)",
            plan.uavs[i].id, plan.uavs[j].id, ti));
    }
  }

  const RegionMap regions(plan);
  const geodesy::LocalFrame frame(plan.origin);
  for (std::size_t u = 0; u < n; ++u) {
    const auto items = mission_items(plan, u, opt);
    // below the transit altitude: with a DEM (AMSL heights) anything under the UAV's transit altitude
    const double low_limit = terrain::grid(plan.mission) != nullptr
                                 ? flight_transit_altitude(plan, opt, u) - 1e-3
                                 : mission_alt + 1e-3;
    const MissionItem* prev = nullptr;
    for (const auto& it : items) {
      if (!has_position(it)) continue;
      if (prev != nullptr) {
        const bool low = std::min(prev->alt, it.alt) <= low_limit;
        const bool coverage_leg = waypoints::in_coverage_leg(*prev) && waypoints::in_coverage_leg(it) &&
                                  prev->part == it.part && it.part >= 0;
        if (low && !coverage_leg && it.command != kNavLand) {
          const Point a = frame.to_local({prev->lon, prev->lat});
          const Point b = frame.to_local({it.lon, it.lat});
          const int o = regions.entered_by(a, b, u, sep.tolerance_m);
          if (o >= 0)
            problems.push_back(
                fmt::format("uav '{}': leg at mission altitude from ({:.7f}, {:.7f}) to ({:.7f}, {:.7f}) "
                            "enters the region of uav '{}'",
                            plan.uavs[u].id, prev->lon, prev->lat, it.lon, it.lat,
                            plan.uavs[static_cast<std::size_t>(o)].id));
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
