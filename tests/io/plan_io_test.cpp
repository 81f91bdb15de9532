// The plan directory: what plan writes, load_plan_dir reads back; bad folders are refused clearly.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "codec/plan_codec.hpp"
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
  io::write_artifacts(dir, {{"paths.geojson", "application/geo+json", codec::paths_geojson(p).dump(1) + "\n"},
                            {"plan.json", "application/json", codec::plan_json(p).dump(1) + "\n"}});
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
  // nothing at all: the folder is staged beside itself and renamed into place only when complete
  EXPECT_FALSE(fs::exists(other)) << "a partial output folder was left";
  EXPECT_FALSE(fs::exists(other.parent_path() / "escape.txt"));
  for (const auto& e : fs::directory_iterator(other.parent_path()))
    if (e.path().filename().string().starts_with(other.filename().string()))
      ADD_FAILURE() << "left behind: " << e.path();
  fs::remove_all(dir);
  fs::remove_all(other);
}

TEST(ReadTextFile, RefusesFoldersDevicesAndMissingFilesNamingThem) {
  auto expect = [](const fs::path& p, const std::string& needle) {
    try {
      io::read_text_file(p, "MISSION");
      ADD_FAILURE() << "read " << p;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "MISSION");
      EXPECT_NE(std::string(e.what()).find("'" + p.string() + "'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect("/dev/zero", "not a regular file");
  expect(fs::temp_directory_path(), "is a folder");
  expect(fs::temp_directory_path() / "uavcover-no-such-file.json", "cannot read");
}

TEST(ReadTextFile, RefusesFilesOverTheLimit) {
  const auto dir = fresh_dir("limit");
  fs::create_directories(dir);
  std::ofstream(dir / "f.json") << std::string(1000, ' ') << "{}";
  EXPECT_EQ(io::read_text_file(dir / "f.json", "F", 1002).size(), 1002u);
  try {
    io::read_text_file(dir / "f.json", "F", 1001);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("larger than the input limit of 1001 bytes"), std::string::npos)
        << e.what();
  }
  // the process-wide limit
  io::set_max_input_bytes(1001);
  EXPECT_THROW(io::read_text_file(dir / "f.json", "F"), InputError);
  io::set_max_input_bytes(io::kDefaultMaxInputBytes);
  EXPECT_EQ(io::read_text_file(dir / "f.json", "F").size(), 1002u);
  std::ofstream(dir / "empty.json").flush();
  EXPECT_EQ(io::read_text_file(dir / "empty.json", "F"), "");
  fs::remove_all(dir);
}

TEST(PlanDir, RefusesDuplicateKeysAndDeepNesting) {
  const Plan p = small_plan();
  const auto dir = fresh_dir("strict");
  write_plan_folder(p, dir);
  const std::string plan_text = uavcover::testing::slurp(dir / "plan.json");
  // a duplicate key inside the stored mission
  std::string dup = plan_text;
  dup.insert(dup.find("\"spacing_m\""), "\"spacing_m\": -5, ");
  std::ofstream(dir / "plan.json") << dup;
  try {
    io::load_plan_dir(dir);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("duplicate key \"spacing_m\" in plan.json"), std::string::npos)
        << e.what();
  }
  // deep nesting in paths.geojson
  std::ofstream(dir / "plan.json") << plan_text;
  std::ofstream(dir / "paths.geojson") << std::string(100'000, '[') << std::string(100'000, ']');
  try {
    io::load_plan_dir(dir);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "paths.geojson");
    EXPECT_NE(std::string(e.what()).find("nested deeper"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}
