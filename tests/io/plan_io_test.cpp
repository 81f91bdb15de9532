// The plan directory: what plan writes, load_plan_dir reads back; bad folders are refused clearly.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "io/plan_io.hpp"
#include "support/files.hpp"
#include "uavcover/uavcover.hpp"

using namespace uavcover;
namespace fs = std::filesystem;

namespace {

Plan small_plan() {
  const Mission m = parse_mission(R"({
    "area": {"type": "Polygon", "coordinates": [[[22.90, 40.60], [22.906, 40.60], [22.906, 40.604], [22.90, 40.604]]]},
    "no_fly_zones": [{"type": "Polygon", "coordinates": [[[22.902, 40.601], [22.903, 40.601], [22.903, 40.602], [22.902, 40.602]]]}],
    "spacing_m": 30, "uavs": [{"id": "a", "start": [22.8995, 40.5995]}, {"id": "b", "share": 0.7}], "seed": 4})");
  return plan(m);
}

void write_plan_folder(const Plan& p, const fs::path& dir) {
  io::write_artifacts(dir, {{"paths.geojson", "application/geo+json", io::paths_geojson(p).dump(1) + "\n"},
                            {"plan.json", "application/json", io::plan_json(p).dump(1) + "\n"}});
}

fs::path fresh_dir(const std::string& name) {
  const auto d = fs::temp_directory_path() / ("uavcover-io-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

}  // namespace

TEST(PlanDir, WriteThenLoadGivesTheSamePlan) {
  const Plan p = small_plan();
  const auto dir = fresh_dir("roundtrip");
  write_plan_folder(p, dir);
  const Plan q = io::load_plan_dir(dir);
  EXPECT_EQ(q.mission.name, p.mission.name);
  EXPECT_EQ(q.mission.seed, p.mission.seed);
  EXPECT_NEAR(q.origin.lon, p.origin.lon, 1e-12);
  EXPECT_EQ(q.planner, p.planner);
  EXPECT_EQ(q.diagnostics, p.diagnostics);
  ASSERT_EQ(q.uavs.size(), p.uavs.size());
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    EXPECT_EQ(q.uavs[i].id, p.uavs[i].id);
    EXPECT_EQ(q.uavs[i].turns, p.uavs[i].turns);
    EXPECT_EQ(q.uavs[i].region, p.uavs[i].region);
    EXPECT_NEAR(bg::area(q.uavs[i].region_local), bg::area(p.uavs[i].region_local), 1e-3);
    EXPECT_EQ(q.uavs[i].diagnostics, p.uavs[i].diagnostics);
    EXPECT_EQ(q.mission.uavs[i].start_resolved, p.mission.uavs[i].start_resolved);
    ASSERT_EQ(q.uavs[i].parts.size(), p.uavs[i].parts.size());
    for (std::size_t k = 0; k < p.uavs[i].parts.size(); ++k) {
      const auto& a = p.uavs[i].parts[k];
      const auto& b = q.uavs[i].parts[k];
      EXPECT_EQ(a.kind, b.kind);
      ASSERT_EQ(a.local.size(), b.local.size());
      for (std::size_t v = 0; v < a.local.size(); ++v) {
        EXPECT_EQ(a.wgs84[v], b.wgs84[v]);                      // WGS84 written exactly
        EXPECT_LT(bg::distance(a.local[v], b.local[v]), 1e-6);  // local frame rebuilt from it
      }
    }
  }
  fs::remove_all(dir);
}

TEST(PlanDir, GeoJsonFollowsRfc7946) {
  const auto gj = io::paths_geojson(small_plan());
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

TEST(PlanDir, BadFoldersAreRefusedNamingTheProblem) {
  const auto dir = fresh_dir("bad");
  try {
    io::load_plan_dir(dir);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("plan.json"), std::string::npos) << e.what();
  }
  const Plan p = small_plan();
  write_plan_folder(p, dir);
  std::ofstream(dir / "paths.geojson")
      << R"({"type": "FeatureCollection", "features": [{"properties": {"uav": "zz"}}]})";
  EXPECT_THROW(io::load_plan_dir(dir), InputError);
  std::ofstream(dir / "plan.json") << "{\"mission\": 1e999}";
  EXPECT_THROW(io::load_plan_dir(dir), InputError);
  fs::remove_all(dir);
}

TEST(WriteArtifacts, WritesEverythingOrNothing) {
  const auto dir = fresh_dir("artifacts");
  const auto files =
      io::write_artifacts(dir, {{"a.txt", "text/plain", "one"}, {"sub/b.txt", "text/plain", "two"}});
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(uavcover::testing::slurp(dir / "sub" / "b.txt"), "two");
  // a name that would leave the folder is refused before anything is written
  const auto other = fresh_dir("artifacts-bad");
  EXPECT_THROW(
      io::write_artifacts(other, {{"ok.txt", "text/plain", "x"}, {"../escape.txt", "text/plain", "y"}}),
      OperationError);
  EXPECT_FALSE(fs::exists(other / "ok.txt"));
  EXPECT_FALSE(fs::exists(other.parent_path() / "escape.txt"));
  for (const auto& e : fs::directory_iterator(other)) ADD_FAILURE() << "left behind: " << e.path();
  fs::remove_all(dir);
  fs::remove_all(other);
}
