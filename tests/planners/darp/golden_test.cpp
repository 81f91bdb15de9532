// DARP through the planner interface gives byte-identical paths.geojson to the DARP-only engine it
// replaced (references written at commit 96406b1; see tests/data/darp-golden/README.md).
#include <gtest/gtest.h>

#include <filesystem>

#include "codec/plan_codec.hpp"
#include "io/plan_io.hpp"
#include "support/files.hpp"
#include "uavcover/uavcover.hpp"

using namespace uavcover;
namespace fs = std::filesystem;

namespace {

const fs::path kGolden = fs::path(UAVCOVER_SOURCE_DIR) / "tests" / "data" / "darp-golden";

class DarpGolden : public ::testing::TestWithParam<std::pair<std::string, std::string>> {};

TEST_P(DarpGolden, PathsAreByteIdenticalToThePreInterfaceEngine) {
  const auto& [mission_file, golden] = GetParam();
  const Mission m = parse_mission(uavcover::testing::slurp(fs::path(UAVCOVER_SOURCE_DIR) / mission_file));
  ASSERT_EQ(m.planner, "darp");
  const Plan p = plan(m);
  const std::string expected = uavcover::testing::slurp(kGolden / golden);
  ASSERT_FALSE(expected.empty()) << golden;
  EXPECT_TRUE(codec::paths_geojson(p).dump(1) + "\n" == expected)
      << mission_file << " differs from " << golden;
}

INSTANTIATE_TEST_SUITE_P(
    Missions, DarpGolden,
    ::testing::Values(
        std::pair{"bench/data/apostolidis2022/roi01.json", "roi01.paths.geojson"},
        std::pair{"bench/data/apostolidis2022/roi05.json", "roi05.paths.geojson"},
        std::pair{"bench/data/apostolidis2022/roi09.json", "roi09.paths.geojson"},
        std::pair{"bench/data/apostolidis2022/roi14.json", "roi14.paths.geojson"},
        std::pair{"bench/data/apostolidis2022/roi18.json", "roi18.paths.geojson"},
        std::pair{"tests/data/darp-golden/roi09-coverage.mission.json", "roi09-coverage.paths.geojson"},
        std::pair{"examples/olive-grove.json", "olive-grove.paths.geojson"},
        std::pair{"bench/data/mondinelli2025/rectangle_3uav.json", "rectangle_3uav.paths.geojson"}));

}  // namespace
