// The plan codec in memory: plan.json and paths.geojson from a Plan and back (no files: tests/io has the
// plan folder); the documents follow RFC 7946 and bad documents are refused naming the field.
#include <gtest/gtest.h>

#include <functional>
#include "codec/plan_codec.hpp"

#include "support/errors.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"

using namespace uavcover;

namespace {

Plan small_plan() {
  const Mission m = parse_mission(R"({
    "area": {"type": "Polygon", "coordinates": [[[22.90, 40.60], [22.906, 40.60], [22.906, 40.604], [22.90, 40.604]]]},
    "no_fly_zones": [{"type": "Polygon", "coordinates": [[[22.902, 40.601], [22.903, 40.601], [22.903, 40.602], [22.902, 40.602]]]}],
    "spacing_m": 30, "uavs": [{"id": "a", "start": [22.8995, 40.5995]}, {"id": "b", "share": 0.7}], "seed": 4})");
  return plan(m);
}

using uavcover::testing::field_of;

}  // namespace

TEST(PlanCodec, EncodeThenDecodeGivesTheSameDocuments) {
  const Plan p = small_plan();
  const auto pj = codec::plan_json(p);
  const auto gj = codec::paths_geojson(p);
  const Plan q = codec::load_plan(pj, gj);
  ASSERT_EQ(q.uavs.size(), p.uavs.size());
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    EXPECT_EQ(q.uavs[i].id, p.uavs[i].id);
    ASSERT_EQ(q.uavs[i].parts.size(), p.uavs[i].parts.size());
    for (std::size_t k = 0; k < p.uavs[i].parts.size(); ++k)
      EXPECT_EQ(q.uavs[i].parts[k].wgs84, p.uavs[i].parts[k].wgs84);
  }
  // a decoded plan encodes to the same paths document: positions exactly, lengths (recomputed in the
  // local frame rebuilt from the WGS84 positions) within a micrometre
  const auto again = codec::paths_geojson(q);
  ASSERT_EQ(again["features"].size(), gj["features"].size());
  for (std::size_t k = 0; k < gj["features"].size(); ++k) {
    auto a = again["features"][k];
    auto b = gj["features"][k];
    EXPECT_EQ(a["geometry"], b["geometry"]) << k;
    if (b["properties"].contains("length_m")) {
      EXPECT_NEAR(a["properties"]["length_m"].get<double>(), b["properties"]["length_m"].get<double>(), 1e-6);
      a["properties"].erase("length_m");
      b["properties"].erase("length_m");
    }
    EXPECT_EQ(a["properties"], b["properties"]) << k;
  }
}

TEST(PlanCodec, PerUavPathsHoldOnlyThatUav) {
  const Plan p = small_plan();
  const auto gj = codec::paths_geojson(p, 1);
  int lines = 0;
  for (const auto& f : gj["features"])
    if (f["geometry"]["type"] == "LineString") {
      ++lines;
      EXPECT_EQ(f["properties"]["uav"], "b");
    }
  EXPECT_GT(lines, 0);
}

TEST(PlanCodec, BadDocumentsAreRefusedNamingTheField) {
  const Plan p = small_plan();
  const auto gj = codec::paths_geojson(p);
  EXPECT_EQ(field_of([&] { codec::load_plan(nlohmann::json::object(), gj); }), "plan.json: mission");
  auto pj = codec::plan_json(p);
  pj["origin"] = {500, 0};
  EXPECT_EQ(field_of([&] { codec::load_plan(pj, gj); }), "plan.json: origin");
}

TEST(PlanCodec, GeoJsonFollowsRfc7946) {
  const auto gj = codec::paths_geojson(small_plan());
  for (const auto& f : gj["features"]) {
    const auto& g = f["geometry"];
    if (g["type"] != "Polygon") continue;
    for (std::size_t r = 0; r < g["coordinates"].size(); ++r) {
      const auto& ring = g["coordinates"][r];
      ASSERT_GE(ring.size(), 4u);
      EXPECT_EQ(ring.front(), ring.back()) << "closed ring";
      double twice = 0;
      for (std::size_t i = 0; i + 1 < ring.size(); ++i)
        twice += ring[i][0].get<double>() * ring[i + 1][1].get<double>() -
                 ring[i + 1][0].get<double>() * ring[i][1].get<double>();
      if (r == 0) {
        EXPECT_GT(twice, 0) << "exterior rings are counter-clockwise";
      } else {
        EXPECT_LT(twice, 0) << "holes are clockwise";
      }
    }
  }
}
