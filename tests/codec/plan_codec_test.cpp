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

// PathPart::attitude (issue 30) is written per part in paths.geojson ("attitude", only when set, so
// plans without it are unchanged) and read back as untrusted input.
namespace {

/// small_plan() with an attitude on UAV a's first coverage part; `feature` receives that part's index
/// among paths.geojson's features.
Plan plan_with_attitude(std::size_t* feature = nullptr) {
  Plan p = small_plan();
  auto& parts = p.uavs[0].parts;
  std::size_t at = 0;
  while (at < parts.size() && parts[at].kind != PartKind::Coverage) ++at;
  PathPart& part = parts.at(at);
  part.attitude.altitude_m = 33.5;
  for (std::size_t k = 0; k < part.local.size(); ++k) part.attitude.heading_deg.push_back(10.0 * k);
  part.attitude.gimbal_pitch_deg = -30.0;
  part.attitude.roi = part.local.front();
  part.attitude.trigger_distance_m = 6.5;
  if (feature != nullptr) *feature = p.mission.area.size() + p.mission.no_fly_zones.size() + at;
  return p;
}

}  // namespace

TEST(PlanCodec, AttitudeRoundTripsAndIsAbsentWhenEmpty) {
  std::size_t f = 0;
  const Plan p = plan_with_attitude(&f);
  const auto gj = codec::paths_geojson(p);
  const auto& props = gj["features"][f]["properties"];
  ASSERT_TRUE(props.contains("attitude"));
  EXPECT_EQ(props["attitude"]["heading_deg"].size(), gj["features"][f]["geometry"]["coordinates"].size());
  int with = 0;  // only that part carries one
  for (const auto& feat : gj["features"]) with += feat["properties"].contains("attitude") ? 1 : 0;
  EXPECT_EQ(with, 1);
  const Plan q = codec::load_plan(codec::plan_json(p), gj);
  for (std::size_t i = 0; i < p.uavs.size(); ++i)
    for (std::size_t k = 0; k < p.uavs[i].parts.size(); ++k) {
      const Attitude& a = p.uavs[i].parts[k].attitude;
      const Attitude& b = q.uavs[i].parts[k].attitude;
      EXPECT_EQ(a.empty(), b.empty());
      EXPECT_EQ(a.altitude_m, b.altitude_m);
      EXPECT_EQ(a.heading_deg, b.heading_deg);
      EXPECT_EQ(a.gimbal_pitch_deg, b.gimbal_pitch_deg);
      EXPECT_EQ(a.trigger_distance_m, b.trigger_distance_m);
      ASSERT_EQ(a.roi.has_value(), b.roi.has_value());
      if (a.roi) {  // through [lon, lat]: within a millimetre
        EXPECT_NEAR(a.roi->x(), b.roi->x(), 1e-3);
        EXPECT_NEAR(a.roi->y(), b.roi->y(), 1e-3);
      }
    }
  EXPECT_EQ(codec::paths_geojson(q)["features"][f]["properties"]["attitude"], props["attitude"]);
}

TEST(PlanCodec, BadAttitudeIsRefusedNamingTheField) {
  std::size_t f = 0;
  const Plan p = plan_with_attitude(&f);
  const auto pj = codec::plan_json(p);
  const std::string at = "paths.geojson: features[" + std::to_string(f) + "].properties.attitude";
  auto refused = [&](const std::function<void(nlohmann::json&)>& edit) {
    auto gj = codec::paths_geojson(p);
    edit(gj["features"][f]["properties"]["attitude"]);
    return field_of([&] { codec::load_plan(pj, gj); });
  };
  EXPECT_EQ(refused([](auto&) {}), "(no error)");
  EXPECT_EQ(refused([](auto& a) { a["heading_deg"].erase(a["heading_deg"].size() - 1); }),
            at + ".heading_deg");
  EXPECT_EQ(refused([](auto& a) { a["heading_deg"] = 90; }), at + ".heading_deg");
  EXPECT_EQ(refused([](auto& a) { a["heading_deg"][0] = "north"; }), at + ".heading_deg[0]");
  EXPECT_EQ(refused([](auto& a) { a["heading_deg"][1] = 1000; }), at + ".heading_deg[1]");
  EXPECT_EQ(refused([](auto& a) { a["altitude_m"] = -5; }), at + ".altitude_m");
  EXPECT_EQ(refused([](auto& a) { a["altitude_m"] = "high"; }), at + ".altitude_m");
  EXPECT_EQ(refused([](auto& a) { a["gimbal_pitch_deg"] = -120; }), at + ".gimbal_pitch_deg");
  EXPECT_EQ(refused([](auto& a) { a["trigger_distance_m"] = 0; }), at + ".trigger_distance_m");
  EXPECT_EQ(refused([](auto& a) { a["roi"] = {200.0, 40.0}; }), at + ".roi");
  EXPECT_EQ(refused([](auto& a) { a["roi"] = {120.0, 40.0}; }), at + ".roi");  // > 500 km away
  EXPECT_EQ(refused([](auto& a) { a["yaw"] = 3; }), at + ".yaw");
  EXPECT_EQ(refused([](auto& a) { a = nlohmann::json::array(); }), at);
}
