// Reading other tools' paths: GeoJSON LineStrings per UAV; bad GeoJSON is refused naming the field.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "evaluation/evaluate.hpp"
#include "uavcover/error.hpp"

using namespace uavcover;
using evaluation::parse_paths_geojson;
namespace fs = std::filesystem;

namespace {

const geodesy::LocalFrame kFrame(LonLat{24.41, 40.93});

std::string field_of(const std::string& text) {
  try {
    parse_paths_geojson(text, kFrame);
  } catch (const InputError& e) {
    return e.field();
  }
  return "<accepted>";
}

}  // namespace

TEST(PathsGeoJson, GroupsLinesByUavAndKind) {
  const std::string text = R"({"type":"FeatureCollection","features":[
    {"type":"Feature","properties":{"role":"area"},"geometry":{"type":"Polygon","coordinates":[[[24.4,40.9],[24.5,40.9],[24.5,41.0],[24.4,40.9]]]}},
    {"type":"Feature","properties":{"uav":"a","kind":"transit"},"geometry":{"type":"LineString","coordinates":[[24.41,40.93],[24.411,40.93]]}},
    {"type":"Feature","properties":{"uav":"a","kind":"coverage"},"geometry":{"type":"LineString","coordinates":[[24.411,40.93],[24.412,40.93],[24.411,40.93]]}},
    {"type":"Feature","properties":{"uav":"b"},"geometry":{"type":"MultiLineString","coordinates":[[[24.41,40.93],[24.41,40.931]],[[24.42,40.93],[24.42,40.931]]]}}
  ]})";
  const auto p = parse_paths_geojson(text, kFrame);
  ASSERT_EQ(p.uav_ids, (std::vector<std::string>{"a", "b"}));
  ASSERT_EQ(p.flights[0].size(), 2u);
  EXPECT_EQ(p.flights[0][0].kind, PartKind::Transit);
  EXPECT_EQ(p.flights[0][1].kind, PartKind::Coverage);
  EXPECT_EQ(p.flights[0][1].local.size(), 3u);
  EXPECT_NEAR(p.flights[0][0].local[0].x(), 0.0, 1e-6);
  EXPECT_NEAR(p.flights[0][0].local[1].x(), 84.4, 0.5);  // 0.001 deg of longitude at 40.93 N
  EXPECT_EQ(p.flights[1].size(), 2u);
}

TEST(PathsGeoJson, LinesWithoutUavAreSeparateUavs) {
  const std::string text = R"({"type":"FeatureCollection","features":[
    {"type":"Feature","properties":{},"geometry":{"type":"LineString","coordinates":[[24.41,40.93],[24.411,40.93]]}},
    {"type":"Feature","geometry":{"type":"LineString","coordinates":[[24.41,40.93],[24.411,40.93]]}}]})";
  const auto p = parse_paths_geojson(text, kFrame);
  EXPECT_EQ(p.uav_ids.size(), 2u);
  EXPECT_EQ(p.uav_ids[0], "uav-1");
  EXPECT_EQ(p.uav_ids[1], "uav-2");
}

TEST(PathsGeoJson, RefusesBadInputNamingTheField) {
  EXPECT_EQ(field_of("not json"), "paths");
  EXPECT_EQ(field_of("[]"), "type");
  EXPECT_EQ(field_of(R"({"type":"Polygon","coordinates":[]})"), "type");
  EXPECT_EQ(field_of(R"({"type":"FeatureCollection"})"), "features");
  EXPECT_EQ(field_of(R"({"type":"FeatureCollection","features":[]})"), "features");
  EXPECT_EQ(field_of(R"({"type":"FeatureCollection","features":[{"type":"Feature"}]})"),
            "features[0].geometry");
  EXPECT_EQ(
      field_of(
          R"({"type":"FeatureCollection","features":[{"type":"Feature","geometry":{"type":"LineString"}}]})"),
      "features[0].geometry.coordinates");
  EXPECT_EQ(
      field_of(
          R"({"type":"FeatureCollection","features":[{"type":"Feature","geometry":{"type":"LineString","coordinates":[[24.4,40.9]]}}]})"),
      "features[0].geometry.coordinates");
  EXPECT_EQ(
      field_of(
          R"({"type":"FeatureCollection","features":[{"type":"Feature","geometry":{"type":"LineString","coordinates":[[24.4,40.9],[24.4,"x"]]}}]})"),
      "features[0].geometry.coordinates[1]");
  EXPECT_EQ(
      field_of(
          R"({"type":"FeatureCollection","features":[{"type":"Feature","geometry":{"type":"LineString","coordinates":[[24.4,40.9],[24.4,95]]}}]})"),
      "features[0].geometry.coordinates[1]");
  EXPECT_EQ(
      field_of(
          R"({"type":"FeatureCollection","features":[{"type":"Feature","properties":{"kind":"hover"},"geometry":{"type":"LineString","coordinates":[[24.4,40.9],[24.41,40.9]]}}]})"),
      "features[0].properties.kind");
  EXPECT_EQ(
      field_of(
          R"({"type":"FeatureCollection","features":[{"type":"Feature","properties":{"uav":[1]},"geometry":{"type":"LineString","coordinates":[[24.4,40.9],[24.41,40.9]]}}]})"),
      "features[0].properties.uav");
}

TEST(EvaluateCommand, WritesEvaluationJsonAndPictures) {
  const fs::path dir = fs::temp_directory_path() / ("uavcover_eval_cli_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string bench = std::string(UAVCOVER_BENCH_DATA) + "/apostolidis2022/";
  const std::string cmd = std::string(UAVCOVER_CLI) + " -q evaluate " + bench + "roi01.json " + bench +
                          "paper_paths/roi01-optimal.geojson --out " + dir.string();
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream in(dir / "evaluation.json");
  const auto j = nlohmann::json::parse(in);
  for (const char* k :
       {"poc", "pooc", "max_scans", "turns", "length_m", "flight_time_min", "total_time_min", "cost_eur"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_NEAR(j["poc"].get<double>(), 1.0, 0.01);
  EXPECT_EQ(j["turns"].get<int>(), 30);
  ASSERT_EQ(j["uavs"].size(), 1u);
  EXPECT_EQ(j["uavs"][0]["id"], "uav-1");
  EXPECT_GT(fs::file_size(dir / "heatmap.png"), 1000u);
  EXPECT_GT(fs::file_size(dir / "histogram.png"), 1000u);
  EXPECT_GT(fs::file_size(dir / "paths.png"), 1000u);
  fs::remove_all(dir);
}

TEST(EvaluateCommand, RefusesBadGeoJsonWithExitCode2) {
  const fs::path dir = fs::temp_directory_path() / ("uavcover_eval_cli_bad_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  {
    std::ofstream(dir / "bad.geojson")
        << R"({"type":"FeatureCollection","features":[{"type":"Feature","geometry":{"type":"LineString","coordinates":[[24.4,40.9]]}}]})";
  }
  const std::string cmd = std::string(UAVCOVER_CLI) + " evaluate " + UAVCOVER_BENCH_DATA +
                          "/apostolidis2022/roi01.json " + (dir / "bad.geojson").string() + " --out " +
                          (dir / "out").string() + " 2> " + (dir / "err.txt").string();
  const int rc = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(rc));
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  std::ifstream err(dir / "err.txt");
  const std::string msg((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
  EXPECT_NE(msg.find("features[0].geometry.coordinates"), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(dir / "out" / "evaluation.json"));
  fs::remove_all(dir);
}

TEST(PathsGeoJson, FuzzFoundNumberOverflowIsRefused) {
  // found by fuzz_paths_geojson: a number too large for a double escaped as json out_of_range
  EXPECT_EQ(field_of(R"({"type": "FeatureCollection", "x": 0.5E3821, "features": []})"), "paths");
}

namespace {

// A FeatureCollection with one valid LineString whose properties nest `depth` objects.
std::string deep_properties(std::size_t depth) {
  std::string s = R"({"type":"FeatureCollection","features":[{"type":"Feature","properties":)";
  for (std::size_t i = 0; i < depth; ++i) s += "{\"a\":";
  s += "1" + std::string(depth, '}');
  s += R"(,"geometry":{"type":"LineString","coordinates":[[24.41,40.93],[24.412,40.93]]}}]})";
  return s;
}

}  // namespace

TEST(PathsGeoJson, DeeplyNestedPropertiesAreRefusedNotCrashed) {
  // 70 000 nested objects in a feature's properties overflowed the stack (a recursive copy)
  const std::string text = deep_properties(70'000);
  try {
    parse_paths_geojson(text, kFrame);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "paths");
    EXPECT_NE(std::string(e.what()).find("nested deeper than 64 levels"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("features[0].properties.a"), std::string::npos) << e.what();
  }
  // moderate nesting in properties is harmless and ignored
  EXPECT_EQ(parse_paths_geojson(deep_properties(50), kFrame).flights.size(), 1u);
}

TEST(PathsGeoJson, DuplicateKeysAreRefused) {
  EXPECT_EQ(
      field_of(
          R"({"type":"FeatureCollection","features":[{"type":"Feature","properties":{"uav":"a","uav":"b"},"geometry":{"type":"LineString","coordinates":[[24.41,40.93],[24.412,40.93]]}}]})"),
      "features[0].properties.uav");
}
