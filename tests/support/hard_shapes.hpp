// Hard shapes for the planner property suite and bench/hard_shapes (issue 26): non-convex areas,
// holes touching no-fly zones, many small zones, islands, a long strip, an arctic field, a
// heterogeneous fleet and a field cut in two. Every mission is generated here from fixed local
// coordinates (metres east/north of a reference point), strict mode, explicit starts and a fixed seed,
// so that a plan depends on the planner only (not on how the engine draws starts).
//
// own_region_coverage(): the property itself, each UAV's coverage paths swept by the evaluator with
// that UAV's own footprint over that UAV's own region.
#pragma once

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "evaluation/coverage.hpp"
#include "evaluation/evaluate.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::testing {

struct HardShape {
  std::string name;
  nlohmann::json mission;  ///< strict mode, planner not set
};

namespace hard_shapes_detail {

using XY = std::pair<double, double>;

/// Local metres around (lon0, lat0) to WGS84 (equirectangular: exact enough for fixtures of a few km).
struct Place {
  double lon0 = 22.90, lat0 = 40.60;
  [[nodiscard]] nlohmann::json pos(double x, double y) const {
    const double mlat = 1.0 / 110574.0, mlon = 1.0 / (111320.0 * std::cos(lat0 * std::numbers::pi / 180.0));
    return nlohmann::json::array({lon0 + x * mlon, lat0 + y * mlat});
  }
  [[nodiscard]] nlohmann::json ring(const std::vector<XY>& pts) const {
    nlohmann::json r = nlohmann::json::array();
    for (const auto& [x, y] : pts) r.push_back(pos(x, y));
    r.push_back(pos(pts.front().first, pts.front().second));
    return r;
  }
  [[nodiscard]] nlohmann::json polygon(const std::vector<std::vector<XY>>& rings) const {
    nlohmann::json c = nlohmann::json::array();
    for (const auto& r : rings) c.push_back(ring(r));
    return {{"type", "Polygon"}, {"coordinates", c}};
  }
  [[nodiscard]] nlohmann::json multipolygon(const std::vector<std::vector<XY>>& outers) const {
    nlohmann::json c = nlohmann::json::array();
    for (const auto& r : outers) c.push_back(nlohmann::json::array({ring(r)}));
    return {{"type", "MultiPolygon"}, {"coordinates", c}};
  }
};

inline std::vector<XY> box(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

inline nlohmann::json uavs(const Place& p, const std::vector<XY>& starts) {
  nlohmann::json u = nlohmann::json::array();
  for (std::size_t i = 0; i < starts.size(); ++i)
    u.push_back({{"id", "u" + std::to_string(i + 1)}, {"start", p.pos(starts[i].first, starts[i].second)}});
  return u;
}

inline nlohmann::json mission(const std::string& name, const nlohmann::json& area, double spacing,
                              nlohmann::json uav_list, int seed = 7) {
  return {{"name", name},
          {"area", area},
          {"spacing_m", spacing},
          {"mode", "strict"},
          {"uavs", std::move(uav_list)},
          {"seed", seed}};
}

}  // namespace hard_shapes_detail

/// The shapes, in a fixed order (the property suite's parameter is the index).
inline std::vector<HardShape> hard_shapes() {
  using namespace hard_shapes_detail;
  const Place p;
  std::vector<HardShape> out;

  {  // five-pointed star, outer radius 300 m, inner 120 m; 3 UAVs at 35 m (issue 26 §1)
    std::vector<XY> star;
    for (int k = 0; k < 10; ++k) {
      const double r = k % 2 == 0 ? 300.0 : 120.0, a = std::numbers::pi / 2 + k * std::numbers::pi / 5;
      star.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    out.push_back(
        {"star", mission("star", p.polygon({star}), 35, uavs(p, {{-320, -260}, {0, -320}, {320, -260}}))});
  }
  {  // comb: a 100 m base under five teeth 70 m wide and 300 m long, 75 m gaps
    std::vector<XY> comb{{0, 0}, {650, 0}};
    for (int k = 4; k >= 0; --k) {
      const double x0 = 145.0 * k, x1 = x0 + 70.0;
      comb.emplace_back(x1, 400);
      comb.emplace_back(x0, 400);
      if (k > 0) {
        comb.emplace_back(x0, 100);
        comb.emplace_back(x0 - 75.0, 100);
      }
    }
    out.push_back(
        {"comb", mission("comb", p.polygon({comb}), 30, uavs(p, {{-20, -20}, {325, -20}, {670, -20}}))});
  }
  // C (opening east) and U (opening north), 500 m across, 150 m thick arms
  out.push_back(
      {"c_shape",
       mission(
           "c",
           p.polygon(
               {{{0, 0}, {500, 0}, {500, 150}, {150, 150}, {150, 350}, {500, 350}, {500, 500}, {0, 500}}}),
           30, uavs(p, {{-20, -20}, {-20, 520}, {520, 250}}))});
  out.push_back(
      {"u_shape",
       mission(
           "u",
           p.polygon(
               {{{0, 0}, {500, 0}, {500, 500}, {350, 500}, {350, 150}, {150, 150}, {150, 500}, {0, 500}}}),
           30, uavs(p, {{-20, -20}, {520, -20}, {250, 520}}))});
  {  // a hole with a no-fly zone touching it along its east side; 3 UAVs (issue 26 §1)
    nlohmann::json m =
        mission("hole-touching-zone", p.polygon({box(0, 0, 600, 400), box(200, 150, 300, 250)}), 30,
                uavs(p, {{-20, -20}, {620, -20}, {300, 420}}));
    m["no_fly_zones"] = nlohmann::json::array({p.polygon({box(300, 170, 380, 230)})});
    out.push_back({"hole_touching_zone", m});
  }
  {  // forty 14 m no-fly zones on an 8 x 5 lattice
    nlohmann::json m = mission("forty-zones", p.polygon({box(0, 0, 700, 450)}), 30,
                               uavs(p, {{-20, -20}, {720, -20}, {350, 470}}));
    nlohmann::json zones = nlohmann::json::array();
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 5; ++j) {
        const double cx = 87.5 * i + 43.75, cy = 90.0 * j + 45.0;
        zones.push_back(p.polygon({box(cx - 7, cy - 7, cx + 7, cy + 7)}));
      }
    m["no_fly_zones"] = zones;
    out.push_back({"forty_zones", m});
  }
  {  // five separate 180 m islands, 6 UAVs
    std::vector<std::vector<XY>> islands;
    for (const auto& [x, y] : std::vector<XY>{{0, 0}, {280, 0}, {560, 0}, {140, 280}, {420, 280}})
      islands.push_back(box(x, y, x + 180, y + 180));
    out.push_back(
        {"five_islands",
         mission("islands", p.multipolygon(islands), 30,
                 uavs(p, {{-20, -20}, {370, -20}, {760, -20}, {90, 480}, {370, 480}, {620, 480}}))});
  }
  // a 4 km x 150 m strip, 6 UAVs
  out.push_back(
      {"strip_4km",
       mission("strip", p.polygon({box(0, 0, 4000, 150)}), 50,
               uavs(p, {{-20, 75}, {800, -20}, {1600, 170}, {2400, -20}, {3200, 170}, {4020, 75}}))});
  {  // arctic field at 78 N: a hole beside (20 m from) a no-fly zone
    const Place arctic{15.0, 78.0};
    nlohmann::json m = mission("arctic", arctic.polygon({box(0, 0, 600, 400), box(150, 150, 250, 250)}), 30,
                               uavs(arctic, {{-20, -20}, {620, -20}, {300, 420}}));
    m["no_fly_zones"] = nlohmann::json::array({arctic.polygon({box(270, 150, 350, 250)})});
    out.push_back({"arctic_hole_beside_zone", m});
  }
  {  // heterogeneous fleet on an L-shaped field: own cameras (every one seeing at least the spacing),
     // speeds, endurances and shares
    nlohmann::json m = mission("heterogeneous",
                               p.polygon({{{0, 0}, {600, 0}, {600, 250}, {300, 250}, {300, 500}, {0, 500}}}),
                               0, uavs(p, {{-20, -20}, {620, -20}, {-20, 520}}));
    m.erase("spacing_m");
    m["camera"] = {{"altitude_m", 40}, {"hfov_deg", 73.4}, {"overlap", 0.5}};
    m["uavs"][0]["share"] = 0.5;
    m["uavs"][0]["speed_mps"] = 8;
    m["uavs"][1]["share"] = 0.3;
    m["uavs"][1]["camera"] = {{"altitude_m", 40}, {"hfov_deg", 60}, {"overlap", 0.5}};
    m["uavs"][1]["endurance_min"] = 15;
    m["uavs"][2]["share"] = 0.2;
    m["uavs"][2]["camera"] = {{"altitude_m", 40}, {"hfov_deg", 90}, {"overlap", 0.5}};
    m["uavs"][2]["speed_mps"] = 3;
    out.push_back({"heterogeneous_fleet", m});
  }
  {  // a field cut in two by a 40 m no-fly band, every start on the south side
    nlohmann::json m = mission("band", p.polygon({box(0, 0, 600, 400)}), 30,
                               uavs(p, {{-20, -20}, {200, -20}, {400, -20}, {620, -20}}));
    m["no_fly_zones"] = nlohmann::json::array({p.polygon({box(-10, 180, 610, 220)})});
    out.push_back({"cut_by_band", m});
  }
  return out;
}

/// Each UAV's coverage of its own region: the evaluator's PoC over plan.uavs[i].region_local of UAV
/// i's coverage parts alone, swept with UAV i's own footprint. 1 for a UAV without a region.
inline std::vector<double> own_region_coverage(const Plan& plan) {
  std::vector<double> out;
  for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
    const auto& u = plan.uavs[i];
    if (u.region_local.empty() || !(bg::area(u.region_local) > 0.0)) {
      out.push_back(1.0);
      continue;
    }
    evaluation::Flight flight;
    for (const auto& part : u.parts)
      if (part.kind == PartKind::Coverage) flight.push_back(part);
    evaluation::CoverageOptions o;
    o.footprint_m = evaluation::footprint_for(plan.mission, i);
    out.push_back(evaluation::evaluate_coverage(u.region_local, {flight}, o).total.poc);
  }
  return out;
}

/// The UAVs' regions together over the free area (DARP's strict regions are its grid cells inside the
/// area, so for DARP this is below 1 by what its grid leaves out).
inline double regions_over_free_area(const Plan& plan) {
  double regions = 0.0;
  for (const auto& u : plan.uavs) regions += bg::area(u.region_local);
  return plan.free_area_m2 > 0.0 ? regions / plan.free_area_m2 : 0.0;
}

/// The largest |a region's area over all regions' - the requested share| over the UAVs.
inline double worst_share_deviation(const Plan& plan) {
  double regions = 0.0, dev = 0.0;
  for (const auto& u : plan.uavs) regions += bg::area(u.region_local);
  for (const auto& u : plan.uavs)
    dev = std::max(dev,
                   std::abs((regions > 0.0 ? bg::area(u.region_local) / regions : 0.0) - u.share_requested));
  return dev;
}

}  // namespace uavcover::testing
