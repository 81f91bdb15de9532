// `export` on a tampered plan folder: exit 2, a message naming the field, and no output folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "cli/cli_support.hpp"

using namespace uavcover::testing;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

void write_json(const fs::path& p, const json& j) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << j.dump();
}

/// The first LineString feature of paths.geojson.
json& first_line(json& gj) {
  for (auto& f : gj["features"])
    if (f["geometry"]["type"] == "LineString") return f;
  throw std::runtime_error("no LineString");
}

class TamperedPlan : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    planned_ = new fs::path(temp_dir("tamper-src"));
    const auto r =
        run_cli("plan " + example("olive-grove.json").string() + " --out " + planned_->string() + " --quiet");
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*planned_);
    delete planned_;
  }

  /// Copies the plan, applies `tamper` to plan.json and paths.geojson, exports it; expects exit 2, `field`
  /// in the message and no output folder.
  void expect_refused(const std::string& name, const std::function<void(json& plan, json& paths)>& tamper,
                      const std::string& field) {
    const fs::path dir = temp_dir("tamper-" + name);
    fs::copy(*planned_, dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
    json pj = read_json(dir / "plan.json"), gj = read_json(dir / "paths.geojson");
    tamper(pj, gj);
    write_json(dir / "plan.json", pj);
    write_json(dir / "paths.geojson", gj);
    const fs::path out = dir / "out";
    const auto r = run_cli("export " + dir.string() + " --format qgc,trajectory --out " + out.string());
    EXPECT_EQ(r.exit_code, 2) << name << ": " << r.output;
    EXPECT_NE(r.output.find(field), std::string::npos) << name << ": " << r.output;
    EXPECT_FALSE(fs::exists(out)) << name;
    fs::remove_all(dir);
  }

  static fs::path* planned_;
};

fs::path* TamperedPlan::planned_ = nullptr;

TEST_F(TamperedPlan, LineStringWithNoPoint) {
  expect_refused(
      "empty-line", [](json&, json& gj) { first_line(gj)["geometry"]["coordinates"] = json::array(); },
      "geometry");
}

TEST_F(TamperedPlan, LineStringWithOnePoint) {
  expect_refused(
      "one-point",
      [](json&, json& gj) {
        auto& c = first_line(gj)["geometry"]["coordinates"];
        c = json::array({c[0]});
      },
      "geometry");
}

TEST_F(TamperedPlan, LatitudeOf95) {
  expect_refused(
      "lat95", [](json&, json& gj) { first_line(gj)["geometry"]["coordinates"][0][1] = 95.0; },
      "coordinates");
}

TEST_F(TamperedPlan, LongitudeOf1e308) {
  expect_refused(
      "lon1e308", [](json&, json& gj) { first_line(gj)["geometry"]["coordinates"][0][0] = 1e308; },
      "coordinates");
}

TEST_F(TamperedPlan, StartAtLatitude91) {
  expect_refused(
      "start91", [](json& pj, json&) { pj["uavs"][0]["start"][1] = 91.0; }, "start");
}

TEST_F(TamperedPlan, StartFarAway) {  // about 10 000 km south of the olive grove
  expect_refused(
      "start-far",
      [](json& pj, json&) { pj["uavs"][0]["start"][1] = pj["uavs"][0]["start"][1].get<double>() - 89.9; },
      "start");
}

TEST_F(TamperedPlan, UnknownKind) {
  expect_refused(
      "kind", [](json&, json& gj) { first_line(gj)["properties"]["kind"] = "teleport"; }, "kind");
}

TEST_F(TamperedPlan, UnknownUav) {
  expect_refused(
      "uav", [](json&, json& gj) { first_line(gj)["properties"]["uav"] = "ghost"; }, "uav");
}

TEST_F(TamperedPlan, SelfIntersectingRegion) {
  expect_refused(
      "region",
      [](json& pj, json&) {
        auto& ring = pj["uavs"][0]["region"]["coordinates"][0][0];
        std::swap(ring[1], ring[2]);  // a bow tie
      },
      "region");
}

}  // namespace
