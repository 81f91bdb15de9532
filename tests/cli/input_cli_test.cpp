// End-to-end: every command reads its inputs through one bounded, strict reader (issue items 1, 2, 10):
// deep nesting, endless or huge files, folders and duplicate keys exit 2 with a message naming them.
#include <gtest/gtest.h>

#include "cli/cli_support.hpp"

using namespace uavcover::testing;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

std::string path_arg(const fs::path& p) { return "'" + p.string() + "'"; }

void expect_refused(const RunResult& r, const std::string& needle) {
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(needle), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
}

}  // namespace

TEST(InputCli, DeeplyNestedGeoJsonIsRefusedNotCrashed) {
  const auto dir = temp_dir("deep");
  std::string s = R"({"type":"FeatureCollection","features":[{"type":"Feature","properties":)";
  for (int i = 0; i < 70'000; ++i) s += "{\"a\":";
  s += "1" + std::string(70'000, '}');
  s += R"(,"geometry":{"type":"LineString","coordinates":[[22.90,40.60],[22.91,40.60]]}}]})";
  std::ofstream(dir / "deep.geojson") << s;
  const auto r = run_cli("evaluate " + example("olive-grove.json").string() + " " +
                         path_arg(dir / "deep.geojson") + " --no-images --out " + path_arg(dir / "out"));
  expect_refused(r, "nested deeper than 64 levels");
  EXPECT_FALSE(fs::exists(dir / "out"));
  // and in the mission
  std::ofstream(dir / "deep.json") << std::string(70'000, '[') + std::string(70'000, ']');
  expect_refused(run_cli("plan " + path_arg(dir / "deep.json") + " --out " + path_arg(dir / "out")),
                 "mission: nested deeper");
  fs::remove_all(dir);
}

TEST(InputCli, DevicesAndFoldersAreRefusedNamingTheFile) {
  const auto dir = temp_dir("devzero");
  // /dev/zero used to be read until memory ran out
  auto r = run_cli("plan /dev/zero --out " + path_arg(dir / "out"));
  expect_refused(r, "MISSION: '/dev/zero' is not a regular file");
  r = run_cli("plan " + path_arg(dir) + " --out " + path_arg(dir / "out"));
  expect_refused(r, "MISSION: '" + dir.string() + "' is a folder, not a file");
  EXPECT_EQ(r.output.find("malformed JSON"), std::string::npos) << r.output;
  r = run_cli("evaluate " + example("olive-grove.json").string() + " /dev/zero --out " +
              path_arg(dir / "out"));
  expect_refused(r, "PATHS: '/dev/zero'");
  r = run_cli("study /dev/zero --uavs 1 --out " + path_arg(dir / "out"));
  expect_refused(r, "MISSION: '/dev/zero'");
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST(InputCli, FilesOverTheSizeLimitAreRefused) {
  const auto dir = temp_dir("huge");
  {
    // a valid mission padded with 2 MiB of spaces
    std::ofstream out(dir / "big.json");
    out << slurp(example("olive-grove.json")) << std::string(2u << 20, ' ');
  }
  const std::string plan = "plan " + path_arg(dir / "big.json") + " -q --no-images --no-evaluate --out ";
  auto r = run_cli("--max-input-mb 1 " + plan + path_arg(dir / "out"));
  expect_refused(r, "is larger than the input limit of 1 MiB");
  EXPECT_NE(r.output.find("big.json"), std::string::npos) << r.output;
  r = run_cli(plan + path_arg(dir / "out") + " --max-input-mb 1");  // global flags may follow the command
  expect_refused(r, "larger than the input limit");
  r = run_cli("--max-input-mb 0 " + plan + path_arg(dir / "out"));
  expect_refused(r, "--max-input-mb");
  // the environment variable, and the default (64 MiB) that lets the file through
  r = run_cli(plan + path_arg(dir / "out"), "UAVCOVER_MAX_INPUT_MB=1");
  expect_refused(r, "larger than the input limit of 1 MiB");
  r = run_cli(plan + path_arg(dir / "out"), "UAVCOVER_MAX_INPUT_MB=lots");
  expect_refused(r, "UAVCOVER_MAX_INPUT_MB");
  EXPECT_FALSE(fs::exists(dir / "out"));
  r = run_cli(plan + path_arg(dir / "out"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  fs::remove_all(dir);
}

TEST(InputCli, DuplicateKeysAreRefusedNamingTheKey) {
  const auto dir = temp_dir("dup");
  std::string text = slurp(example("olive-grove.json"));
  text.insert(text.find("\"name\""), "\"name\": \"first\", ");
  std::ofstream(dir / "dup.json") << text;
  const auto r = run_cli("plan " + path_arg(dir / "dup.json") + " --out " + path_arg(dir / "out"));
  expect_refused(r, "name: duplicate key \"name\" in mission");
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST(InputCli, MissionRulesHoldEndToEnd) {
  const auto dir = temp_dir("rules");
  json mission = read_json(example("olive-grove.json"));
  mission["uavs"] = json::array({{{"id", "a"}, {"share", 1e308}}, {{"id", "b"}, {"share", 1e308}}});
  std::ofstream(dir / "huge-shares.json") << mission.dump();
  auto r = run_cli("plan " + path_arg(dir / "huge-shares.json") + " -q --no-images --no-evaluate --out " +
                   path_arg(dir / "ok"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const auto& u : read_json(dir / "ok" / "plan.json")["uavs"])
    EXPECT_DOUBLE_EQ(u["share_requested"].get<double>(), 0.5);
  for (const std::string id : {".", "..", "a/b"}) {
    mission["uavs"][1]["id"] = id;
    std::ofstream(dir / "bad-id.json") << mission.dump();
    r = run_cli("plan " + path_arg(dir / "bad-id.json") + " --out " + path_arg(dir / "out"));
    expect_refused(r, "uavs[1].id: ");
  }
  mission["uavs"][1]["id"] = "b";
  mission["name"] = "bell\x07";
  std::ofstream(dir / "bad-name.json") << mission.dump();
  expect_refused(run_cli("plan " + path_arg(dir / "bad-name.json") + " --out " + path_arg(dir / "out")),
                 "name: must not contain control characters");
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}
