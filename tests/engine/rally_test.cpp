// Issue 31: rally points the planner proposes (one per UAV, free ground in its own region, clear of the
// no-fly zones) and the mission's own, carried by the plan into the QGC .plan's rallyPoints.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "engine/rally.hpp"
#include "export/export.hpp"
#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "json/strict.hpp"
#include "support/files.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover {
namespace {

using nlohmann::json;

json olive_grove() {
  return json::parse(
      testing::slurp(std::filesystem::path(UAVCOVER_SOURCE_DIR) / "examples" / "olive-grove.json"));
}

TEST(Rally, ProposedPointsLieInEachRegionClearOfTheZones) {
  json doc = olive_grove();
  doc["propose_rally"] = true;
  const Mission m = parse_mission(doc.dump());
  ASSERT_FALSE(m.no_fly_zones.empty());
  const Plan p = plan(m);
  ASSERT_EQ(p.rally.size(), p.uavs.size());
  const geodesy::LocalFrame frame(p.origin);
  const MultiPolygon zones = geometry::unite(geometry::to_local(m.no_fly_zones, frame));
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    SCOPED_TRACE(p.uavs[i].id);
    const Point q = frame.to_local(p.rally[i]);
    EXPECT_TRUE(bg::covered_by(q, p.uavs[i].region_local));
    EXPECT_FALSE(bg::covered_by(q, zones));
    EXPECT_GE(geometry::distance(zones, q), engine::kRallyClearanceM - 1e-6);
  }
  // deterministic, and kept in plan.json
  EXPECT_EQ(plan(m).rally, p.rally);
  // the .plan carries them: [lat, lon, alt] at the UAV's transition altitude (relative to home)
  const auto arts = exporting::export_artifacts(p, {"qgc"}, {});
  const auto it = std::find_if(arts.begin(), arts.end(),
                               [&](const auto& a) { return a.name == "export/" + p.uavs[0].id + ".plan"; });
  ASSERT_NE(it, arts.end());
  const json pts = strict::parse_json(it->bytes, "plan").at("rallyPoints").at("points");
  ASSERT_EQ(pts.size(), p.rally.size());
  for (std::size_t k = 0; k < pts.size(); ++k) {
    EXPECT_DOUBLE_EQ(pts[k][0].get<double>(), p.rally[k].lat);
    EXPECT_DOUBLE_EQ(pts[k][1].get<double>(), p.rally[k].lon);
    EXPECT_DOUBLE_EQ(pts[k][2].get<double>(), p.uavs[0].transition_altitude_m);
  }
}

TEST(Rally, TheMissionsOwnPointsAreKeptAndNoneIsProposedUnasked) {
  json doc = olive_grove();
  const Plan none = plan(parse_mission(doc.dump()));
  EXPECT_TRUE(none.rally.empty());
  const auto& a = doc["area"]["coordinates"][0][0];
  doc["rally"] = json::array({a});
  const Plan given = plan(parse_mission(doc.dump()));
  ASSERT_EQ(given.rally.size(), 1U);
  EXPECT_DOUBLE_EQ(given.rally[0].lon, a[0].get<double>());
}

}  // namespace
}  // namespace uavcover
