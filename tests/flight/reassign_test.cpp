// Reassignment of a failed UAV's remaining coverage (docs/flights.md, "Reassignment") on the olive
// grove example: the remainder against the evaluator's lattice, the helpers' new work against the
// remainder and the no-fly zones, their transition altitudes, determinism and refusals.
#include "flight/reassign.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>
#include <stop_token>

#include "evaluation/evaluate.hpp"
#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "sorties/sorties.hpp"
#include "support/examples.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover {
namespace {

using flight::Helper;

const Plan& olive_grove() { return testing::olive_grove_plan(); }

int waypoint_count(const Plan& p, std::size_t i) {
  return static_cast<int>(sorties::coverage_waypoints(p.uavs[i]).size());
}

/// The coverage UAV i flew up to waypoint lr (inclusive), as the evaluator's flight.
evaluation::Flight flown_prefix(const Plan& p, std::size_t i, int lr) {
  const UavPlan& up = p.uavs[i];
  const auto wps = sorties::coverage_waypoints(up);
  evaluation::Flight out;
  for (int g = 0; g <= lr; ++g) {
    const auto& ref = wps[static_cast<std::size_t>(g)];
    if (g == 0 || wps[static_cast<std::size_t>(g - 1)].part != ref.part)
      out.push_back({PartKind::Coverage, {}, {}});
    out.back().local.push_back(up.parts[ref.part].local[ref.vertex]);
  }
  return out;
}

/// Distance from p to the boundary of `mp` (its rings, as lines: to a ring itself Boost.Geometry's
/// distance is areal, 0 inside it).
double boundary_distance(const MultiPolygon& mp, Point p) {
  double d = std::numeric_limits<double>::infinity();
  auto to_ring = [&](const auto& ring) {
    d = std::min(d, static_cast<double>(bg::distance(p, Polyline(ring.begin(), ring.end()))));
  };
  for (const auto& poly : mp) {
    to_ring(poly.outer());
    for (const auto& in : poly.inners()) to_ring(in);
  }
  return d;
}

std::vector<int> last_reached_cases(int n) { return {-1, 0, n / 4, n / 2, (3 * n) / 4, n - 2}; }

TEST(Remainder, WithTheSweptFootprintItCoversTheRegion) {
  const Plan& p = olive_grove();
  const double w = evaluation::footprint_for(p.mission);
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    const int n = waypoint_count(p, i);
    for (int lr : last_reached_cases(n)) {
      SCOPED_TRACE(p.uavs[i].id + " last_reached " + std::to_string(lr));
      const MultiPolygon rest = flight::remainder_area(p, i, lr);
      evaluation::CoverageOptions co;
      co.footprint_m = w;
      co.lattice_m = 2.0;
      const auto cov = evaluation::evaluate_coverage(p.uavs[i].region_local, {flown_prefix(p, i, lr)}, co);
      const double s = cov.lattice_m;
      double unscanned_outside_m2 = 0.0;
      int unscanned_far = 0, scanned_deep_inside = 0;
      for (int r = 0; r < cov.lattice_rows; ++r)
        for (int c = 0; c < cov.lattice_cols; ++c) {
          const int k = cov.scans[static_cast<std::size_t>(r) * static_cast<std::size_t>(cov.lattice_cols) +
                                  static_cast<std::size_t>(c)];
          if (k < 0) continue;  // outside the region
          const Point q(cov.lattice_origin.x() + c * s, cov.lattice_origin.y() + r * s);
          const bool inside = bg::within(q, rest);
          if (k == 0 && !inside && boundary_distance(rest, q) > s) {
            unscanned_outside_m2 += s * s;
            if (rest.empty() || geometry::distance(rest, q) > w) ++unscanned_far;
          }
          if (k > 0 && inside && boundary_distance(rest, q) > s) ++scanned_deep_inside;
        }
      // what the evaluator leaves unscanned lies in the remainder, up to the dropped pieces (each under
      // one footprint square) and the lattice's step along the remainder's edge
      EXPECT_LE(unscanned_outside_m2, 2.0 * w * w);
      EXPECT_EQ(unscanned_far, 0);
      // and nothing the evaluator counts as scanned is re-planned
      EXPECT_EQ(scanned_deep_inside, 0);
      if (lr == -1) {
        EXPECT_NEAR(bg::area(rest), bg::area(p.uavs[i].region_local), 1.0);
      }
    }
  }
}

TEST(Remainder, ShrinksAsTheUavGoesOn) {
  // the footprint rectangles of a sweep overlap along collinear edges, where Boost.Geometry's overlay
  // on doubles loses polygons; the remainder must still shrink with every waypoint reached
  const Plan& p = olive_grove();
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    const int n = waypoint_count(p, i);
    double before = bg::area(p.uavs[i].region_local) + 1e-6;
    for (int lr = -1; lr < n; ++lr) {
      const double a = bg::area(flight::remainder_area(p, i, lr));
      EXPECT_LE(a, before + 1e-3) << p.uavs[i].id << " last_reached " << lr;
      before = a;
    }
    EXPECT_EQ(before, 0.0);
  }
}

TEST(Remainder, RemainingWaypointsLieInOrNearIt) {
  const Plan& p = olive_grove();
  const double w = evaluation::footprint_for(p.mission);
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    const int n = waypoint_count(p, i);
    const auto wps = sorties::coverage_waypoints(p.uavs[i]);
    for (int lr : last_reached_cases(n)) {
      const MultiPolygon rest = flight::remainder_area(p, i, lr);
      if (rest.empty()) continue;
      double worst = 0.0;
      for (int g = lr + 1; g < n; ++g) {
        const auto& ref = wps[static_cast<std::size_t>(g)];
        worst = std::max(worst, geometry::distance(rest, p.uavs[i].parts[ref.part].local[ref.vertex]));
      }
      EXPECT_LE(worst, w) << p.uavs[i].id << " last_reached " << lr;
    }
  }
}

TEST(Remainder, IsSweptWithTheFailedUavsOwnCamera) {
  // bravo's own camera sees 25 m across, the mission's 74.5 m: halfway, it has scanned less, and the
  // remainder is what the evaluator leaves unscanned with bravo's own footprint
  const Plan& p = olive_grove();
  const Plan own = testing::olive_grove_with_own_camera(1, 25.0);
  const double w = evaluation::footprint_for(own.mission, 1);
  ASSERT_NEAR(w, 25.0, 1e-9);
  const int lr = waypoint_count(p, 1) / 2;
  const MultiPolygon mission_rest = flight::remainder_area(p, 1, lr);
  const MultiPolygon rest = flight::remainder_area(own, 1, lr);
  EXPECT_GT(bg::area(rest), bg::area(mission_rest) + 1000.0);
  // other UAVs keep the mission's camera
  EXPECT_NEAR(bg::area(flight::remainder_area(own, 2, lr)), bg::area(flight::remainder_area(p, 2, lr)), 1e-6);
  evaluation::CoverageOptions co;
  co.lattice_m = 2.0;
  int scanned_deep_inside = 0, scanned_by_mission_camera_deep_inside = 0;
  for (const double width : {w, evaluation::footprint_for(p.mission)}) {
    co.footprint_m = width;
    const auto cov = evaluation::evaluate_coverage(p.uavs[1].region_local, {flown_prefix(p, 1, lr)}, co);
    for (int r = 0; r < cov.lattice_rows; ++r)
      for (int c = 0; c < cov.lattice_cols; ++c) {
        const int k = cov.scans[static_cast<std::size_t>(r) * static_cast<std::size_t>(cov.lattice_cols) +
                                static_cast<std::size_t>(c)];
        const Point q(cov.lattice_origin.x() + c * cov.lattice_m, cov.lattice_origin.y() + r * cov.lattice_m);
        if (k > 0 && bg::within(q, rest) && boundary_distance(rest, q) > cov.lattice_m)
          ++(width == w ? scanned_deep_inside : scanned_by_mission_camera_deep_inside);
      }
  }
  // nothing bravo's own camera scanned is re-planned; much of what the mission's camera would have is
  EXPECT_EQ(scanned_deep_inside, 0);
  EXPECT_GT(scanned_by_mission_camera_deep_inside, 1000);
}

/// Bravo fails halfway; alpha (half a battery left) and charlie (full) help.
const flight::Reassignment& bravo_halfway() {
  static const flight::Reassignment r =
      flight::reassign(olive_grove(), 1, waypoint_count(olive_grove(), 1) / 2, {{0, 0.5}, {2, 1.0}});
  return r;
}

MultiPolygon local_area(const Plan& p, const flight::Reassignment& r) {
  return geometry::to_local(r.area, geodesy::LocalFrame(p.origin));
}

TEST(Reassign, RemainingWaypointsAndAreaOfTheFailedUav) {
  const Plan& p = olive_grove();
  const auto& r = bravo_halfway();
  const int n = waypoint_count(p, 1);
  EXPECT_EQ(r.failed_uav, "bravo");
  EXPECT_EQ(r.last_reached, n / 2);
  ASSERT_EQ(static_cast<int>(r.remaining_waypoints.size()), n - 1 - n / 2);
  for (std::size_t k = 0; k < r.remaining_waypoints.size(); ++k)
    EXPECT_EQ(r.remaining_waypoints[k], n / 2 + 1 + static_cast<int>(k));
  const MultiPolygon rest = flight::remainder_area(p, 1, n / 2);
  EXPECT_NEAR(r.area_m2, bg::area(rest), 1e-6 * bg::area(rest));
  // the WGS84 area is the remainder: back in the plan's frame it has the same area
  EXPECT_NEAR(bg::area(local_area(p, r)), r.area_m2, 0.001 * r.area_m2);
  ASSERT_FALSE(r.work.empty());
}

TEST(Reassign, HelpersCoverTheRemainderInsideItAndOutOfTheZones) {
  const Plan& p = olive_grove();
  const auto& r = bravo_halfway();
  const geodesy::LocalFrame frame(p.origin);
  const MultiPolygon rest = local_area(p, r);
  const MultiPolygon zones = geometry::to_local(p.mission.no_fly_zones, frame);
  const double w = evaluation::footprint_for(p.mission);
  std::vector<evaluation::Flight> flights;
  for (const auto& wk : r.work) {
    SCOPED_TRACE(wk.uav);
    EXPECT_TRUE(wk.uav == "alpha" || wk.uav == "charlie");
    EXPECT_EQ(wk.uav, p.uavs[wk.index].id);
    int waypoints = 0;
    for (const auto& part : wk.parts) {
      ASSERT_EQ(part.local.size(), part.wgs84.size());
      for (std::size_t k = 0; k < part.local.size(); ++k) {
        // local coordinates are in the full plan's frame
        const Point q = frame.to_local(part.wgs84[k]);
        EXPECT_NEAR(bg::distance(q, part.local[k]), 0.0, 1e-6);
      }
      for (std::size_t k = 1; k < part.local.size(); ++k) {
        EXPECT_FALSE(geometry::segment_enters(zones, part.local[k - 1], part.local[k], 0.5));
        // the area planned is the remainder grown by half a footprint
        if (part.kind == PartKind::Coverage) {
          EXPECT_TRUE(geometry::segment_within(rest, part.local[k - 1], part.local[k], w / 2 + 0.01));
        }
      }
      if (part.kind == PartKind::Coverage) waypoints += static_cast<int>(part.local.size());
    }
    EXPECT_EQ(wk.waypoints, waypoints);
    ASSERT_FALSE(wk.sorties.empty());
    EXPECT_EQ(wk.missions.size(), wk.sorties.size());
    EXPECT_EQ(wk.sorties.front().first_waypoint, 0);
    EXPECT_EQ(wk.sorties.back().last_waypoint, wk.waypoints - 1);
    for (const auto& so : wk.sorties)
      for (const auto& part : so.parts)
        for (std::size_t k = 1; k < part.local.size(); ++k)
          EXPECT_FALSE(geometry::segment_enters(zones, part.local[k - 1], part.local[k], 0.5));
    // every coverage waypoint of the work is flown, in order, by the missions
    int next = 0;
    for (std::size_t m = 0; m < wk.missions.size(); ++m) {
      const auto& so = wk.sorties[m];
      int expected = so.first_waypoint;
      for (const auto& it : wk.missions[m])
        if (it.role == "coverage") {
          EXPECT_EQ(it.waypoint, expected++);
        }
      EXPECT_EQ(expected, so.last_waypoint + 1);
      next = std::max(next, expected);
    }
    EXPECT_EQ(next, wk.waypoints);
    flights.push_back(wk.parts);
  }
  // the evaluator's coverage of the remainder by the helpers' new work
  evaluation::CoverageOptions co;
  co.footprint_m = w;
  const auto cov = evaluation::evaluate_coverage(rest, flights, co);
  EXPECT_GE(cov.total.poc, 0.9);  // 0.943 measured (the whole plan's PoC is 0.961)
}

TEST(Reassign, TheAreaPlannedIsGrownByTheHelpersOwnFootprint) {
  // charlie alone helps, with its own camera 25 m across (the mission's: 74.5 m): its paths keep
  // within half its own footprint of the remainder, not half the mission's
  const Plan own = testing::olive_grove_with_own_camera(2, 25.0);
  const double w = evaluation::footprint_for(own.mission, 2);
  const int lr = waypoint_count(own, 1) / 2;
  const auto r = flight::reassign(own, 1, lr, {{2, 1.0}});
  const auto mission_r = flight::reassign(olive_grove(), 1, lr, {{2, 1.0}});
  // bravo's own remainder does not depend on charlie's camera
  EXPECT_NEAR(r.area_m2, mission_r.area_m2, 1e-6 * r.area_m2);
  const MultiPolygon rest = local_area(own, r);
  // the farthest coverage waypoint of the (one) helper's work from the remainder
  auto farthest = [&rest](const flight::Reassignment& x) {
    double d = 0.0;
    EXPECT_EQ(x.work.size(), 1u);
    for (const auto& wk : x.work)
      for (const auto& part : wk.parts)
        if (part.kind == PartKind::Coverage)
          for (const Point& q : part.local) d = std::max(d, geometry::distance(rest, q));
    return d;
  };
  EXPECT_LE(farthest(r), w / 2 + 0.01);
  EXPECT_GT(farthest(mission_r), w / 2 + 0.01) << "with the mission's footprint the paths reach farther out";
}

TEST(Reassign, HelpersCoverMostOfTheRemainderWhereverTheUavFails) {
  const Plan& p = olive_grove();
  evaluation::CoverageOptions co;
  co.footprint_m = evaluation::footprint_for(p.mission);
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    const int n = waypoint_count(p, i);
    for (int lr : {-1, n / 3, (2 * n) / 3}) {
      std::vector<Helper> helpers;
      for (std::size_t h = 0; h < p.uavs.size(); ++h)
        if (h != i) helpers.push_back({h, 1.0});
      const auto r = flight::reassign(p, i, lr, helpers);
      std::vector<evaluation::Flight> flights;
      for (const auto& wk : r.work) flights.push_back(wk.parts);
      const auto cov = evaluation::evaluate_coverage(local_area(p, r), flights, co);
      std::cout << p.uavs[i].id << " fails after " << lr << ": remainder " << r.area_m2 << " m2, PoC "
                << cov.total.poc << "\n";
    }
  }
}

TEST(Reassign, HelpersKeepTheirTransitionAltitudes) {
  const Plan& p = olive_grove();
  for (const waypoints::AltitudeOptions& alt :
       {waypoints::AltitudeOptions{},
        waypoints::AltitudeOptions{.transition_base_m = 70, .transition_step_m = 15}}) {
    const auto r = flight::reassign(p, 1, 3, {{2, 0.8}, {0, 0.4}}, alt);
    ASSERT_FALSE(r.work.empty());
    for (const auto& wk : r.work) {
      // the helper's own take-off altitude in the full plan's missions
      const auto own = waypoints::mission_items(p, wk.index, alt);
      ASSERT_EQ(own.front().role, "takeoff");
      const float transit = own.front().alt;
      for (const auto& mission : wk.missions) {
        ASSERT_FALSE(mission.empty());
        EXPECT_EQ(mission.front().role, "takeoff");
        for (const auto& it : mission) {
          if (it.role == "takeoff" || it.role == "transit" || it.role == "transition") {
            EXPECT_EQ(it.alt, transit);
          }
          if (it.role == "coverage") {
            EXPECT_FLOAT_EQ(it.alt, static_cast<float>(p.mission.altitude_m));
          }
        }
      }
    }
  }
}

TEST(Reassign, SharesFollowTheBatteryLeft) {
  const Plan& p = olive_grove();
  const int n = waypoint_count(p, 2);
  const auto r = flight::reassign(p, 2, 2, {{0, 0.25}, {1, 1.0}});
  ASSERT_EQ(r.work.size(), 2u);
  const auto& low = r.work[0].uav == "alpha" ? r.work[0] : r.work[1];
  const auto& full = r.work[0].uav == "alpha" ? r.work[1] : r.work[0];
  EXPECT_LT(low.coverage_length_m, full.coverage_length_m);
  EXPECT_LT(low.waypoints, full.waypoints);
  EXPECT_EQ(static_cast<int>(r.remaining_waypoints.size()), n - 3);
}

TEST(Reassign, IsDeterministic) {
  const Plan& p = olive_grove();
  const auto a = flight::reassign(p, 1, 7, {{0, 0.6}, {2, 0.9}});
  const auto b = flight::reassign(p, 1, 7, {{0, 0.6}, {2, 0.9}});
  ASSERT_EQ(a.area.size(), b.area.size());
  EXPECT_EQ(a.area, b.area);
  ASSERT_EQ(a.work.size(), b.work.size());
  for (std::size_t k = 0; k < a.work.size(); ++k) {
    ASSERT_EQ(a.work[k].parts.size(), b.work[k].parts.size());
    for (std::size_t j = 0; j < a.work[k].parts.size(); ++j)
      EXPECT_EQ(a.work[k].parts[j].wgs84, b.work[k].parts[j].wgs84);
    ASSERT_EQ(a.work[k].missions.size(), b.work[k].missions.size());
    for (std::size_t m = 0; m < a.work[k].missions.size(); ++m) {
      ASSERT_EQ(a.work[k].missions[m].size(), b.work[k].missions[m].size());
      for (std::size_t i = 0; i < a.work[k].missions[m].size(); ++i) {
        EXPECT_EQ(a.work[k].missions[m][i].lat, b.work[k].missions[m][i].lat);
        EXPECT_EQ(a.work[k].missions[m][i].lon, b.work[k].missions[m][i].lon);
        EXPECT_EQ(a.work[k].missions[m][i].alt, b.work[k].missions[m][i].alt);
      }
    }
  }
}

// Issue 33: the depot choice. Without a depot a helper's work starts at its take-off point (the default,
// "home"); with one (reassignment from the air: its live position) the work is planned from there: its
// first mission takes off at the depot, the later ones at home again, and its sorties are cut for the
// battery it has left.
TEST(Reassign, FromTheAirTheWorkStartsAtTheHelpersDepot) {
  const Plan& p = olive_grove();
  const int lr = waypoint_count(p, 1) / 2;
  const geodesy::LocalFrame frame(p.origin);
  // each helper over its own region, halfway through its own coverage
  auto over_own = [&](std::size_t i) {
    const auto wps = sorties::coverage_waypoints(p.uavs[i]);
    const auto& ref = wps[wps.size() / 2];
    return p.uavs[i].parts[ref.part].wgs84[ref.vertex];
  };
  const LonLat a_depot = over_own(0), c_depot = over_own(2);
  const auto home = flight::reassign(p, 1, lr, {{0, 0.5}, {2, 0.5}});
  const auto air = flight::reassign(p, 1, lr, {{0, 0.5, a_depot}, {2, 0.5, c_depot}});
  ASSERT_EQ(home.work.size(), 2U);
  ASSERT_EQ(air.work.size(), 2U);
  EXPECT_EQ(air.area, home.area);  // the same remainder, planned from elsewhere
  auto metres = [&](LonLat a, LonLat b) { return bg::distance(frame.to_local(a), frame.to_local(b)); };
  std::size_t home_sorties = 0, air_sorties = 0;
  for (std::size_t k = 0; k < 2; ++k) {
    const auto& h = home.work[k];
    const auto& a = air.work[k];
    ASSERT_EQ(h.index, a.index);
    const LonLat start = p.mission.uavs[a.index].start_resolved;
    const LonLat depot = a.index == 0 ? a_depot : c_depot;
    ASSERT_GT(metres(start, depot), 50.0);
    ASSERT_FALSE(h.missions.empty());
    ASSERT_FALSE(a.missions.empty());
    for (std::size_t m = 0; m < h.missions.size(); ++m) {
      EXPECT_EQ(h.missions[m].front().role, "takeoff");
      EXPECT_LT(metres(LonLat{h.missions[m].front().lon, h.missions[m].front().lat}, start), 0.01) << m;
    }
    for (std::size_t m = 0; m < a.missions.size(); ++m) {
      EXPECT_EQ(a.missions[m].front().role, "takeoff");
      const LonLat at{a.missions[m].front().lon, a.missions[m].front().lat};
      EXPECT_LT(metres(at, m == 0 ? depot : start), 0.01) << a.uav << " mission " << m;
    }
    home_sorties += h.missions.size();
    air_sorties += a.missions.size();
  }
  // half a battery left: the work from the air is cut into at least as many missions
  EXPECT_GE(air_sorties, home_sorties);
  // a depot that is not a position is refused, naming it
  EXPECT_EQ(testing::input_error_field([&] {
              flight::reassign(p, 1, lr, {{0, 1.0, LonLat{200.0, 0.0}}});
            }),
            "helpers[0].depot");
}

TEST(Reassign, NothingLeftAfterTheLastWaypoint) {
  const Plan& p = olive_grove();
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    const auto r = flight::reassign(p, i, waypoint_count(p, i) - 1, {{(i + 1) % 3, 1.0}});
    EXPECT_TRUE(r.remaining_waypoints.empty());
    EXPECT_TRUE(r.area.empty());
    EXPECT_EQ(r.area_m2, 0.0);
    EXPECT_TRUE(r.work.empty());
  }
}

TEST(Reassign, NothingFlownGivesTheWholeRegion) {
  const Plan& p = olive_grove();
  const auto r = flight::reassign(p, 0, -1, {{1, 1.0}, {2, 1.0}});
  EXPECT_EQ(static_cast<int>(r.remaining_waypoints.size()), waypoint_count(p, 0));
  EXPECT_NEAR(r.area_m2, bg::area(p.uavs[0].region_local), 1.0);
  EXPECT_FALSE(r.work.empty());
}

using testing::input_error_field;

TEST(Reassign, RefusesBadInputNamingTheField) {
  const Plan& p = olive_grove();
  const int n = waypoint_count(p, 1);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(input_error_field([&] { flight::reassign(p, 3, 0, {{0, 1.0}}); }), "failed");
  EXPECT_EQ(input_error_field([&] { flight::reassign(p, 1, 0, {}); }), "helpers");
  EXPECT_EQ(input_error_field([&] { flight::reassign(p, 1, -2, {{0, 1.0}}); }), "last_reached");
  EXPECT_EQ(input_error_field([&] { flight::reassign(p, 1, n, {{0, 1.0}}); }), "last_reached");
  EXPECT_EQ(input_error_field([&] { flight::reassign(p, 1, 0, {{0, 1.0}, {5, 1.0}}); }), "helpers[1].index");
  EXPECT_EQ(input_error_field([&] { flight::reassign(p, 1, 0, {{1, 1.0}}); }), "helpers[0].index");
  EXPECT_EQ(input_error_field([&] { flight::reassign(p, 1, 0, {{0, 1.0}, {0, 0.5}}); }), "helpers[1].index");
  EXPECT_EQ(input_error_field([&] { flight::reassign(p, 1, 0, {{0, 0.0}}); }), "helpers[0].battery_fraction");
  EXPECT_EQ(input_error_field([&] { flight::reassign(p, 1, 0, {{0, 1.5}}); }), "helpers[0].battery_fraction");
  EXPECT_EQ(input_error_field([&] { flight::reassign(p, 1, 0, {{0, nan}}); }), "helpers[0].battery_fraction");
  EXPECT_EQ(input_error_field([&] {
              flight::reassign(p, 1, 0, {{0, 1.0}}, {.transition_base_m = -1});
            }),
            "altitude.transition_base_m");
  EXPECT_EQ(input_error_field([&] { flight::remainder_area(p, 1, n); }), "last_reached");
  EXPECT_EQ(input_error_field([&] { flight::remainder_area(p, 7, 0); }), "failed");
}

TEST(Reassign, ReportsProgressAndStops) {
  const Plan& p = olive_grove();
  std::vector<std::string> stages;
  const Context ctx([&](std::string_view stage, double) { stages.emplace_back(stage); });
  flight::reassign(p, 1, 4, {{0, 1.0}, {2, 1.0}}, {}, ctx);
  EXPECT_EQ(stages.front(), "reassign");
  EXPECT_NE(std::find(stages.begin(), stages.end(), "reassign/sorties"), stages.end());
  std::stop_source stop;
  stop.request_stop();
  EXPECT_THROW(flight::reassign(p, 1, 4, {{0, 1.0}, {2, 1.0}}, {}, Context({}, stop.get_token())), Cancelled);
}

}  // namespace
}  // namespace uavcover
