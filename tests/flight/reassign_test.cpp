// Reassignment of a failed UAV's remaining coverage (docs/flights.md, "Reassignment") on the olive
// grove example: the remainder against the evaluator's lattice, the helpers' new work against the
// remainder and the no-fly zones, their transition altitudes, determinism and refusals.
#include "flight/reassign.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <stop_token>

#include "evaluation/evaluate.hpp"
#include "geometry/geometry.hpp"
#include "sorties/sorties.hpp"
#include "support/files.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover {
namespace {

using flight::Helper;

const Plan& olive_grove() {
  static const Plan p = [] {
    const Mission m = parse_mission(
        testing::slurp(std::filesystem::path(UAVCOVER_SOURCE_DIR) / "examples" / "olive-grove.json"));
    return plan(m);
  }();
  return p;
}

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

/// Distance from p to the boundary of `mp` (its rings).
double boundary_distance(const MultiPolygon& mp, Point p) {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& poly : mp) {
    d = std::min(d, static_cast<double>(bg::distance(p, poly.outer())));
    for (const auto& in : poly.inners()) d = std::min(d, static_cast<double>(bg::distance(p, in)));
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

}  // namespace
}  // namespace uavcover
