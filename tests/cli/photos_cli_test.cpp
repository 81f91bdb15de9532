// `uavcover photos` and `uavcover refly --photos` (issue 32, docs/photos.md): a folder of geotagged JPEGs
// (GDAL + exiv2) over a planned field; the coverage map, the gaps, and the refly planned from them.
#include <gtest/gtest.h>

#include "cli/cli_support.hpp"
#include "geodesy/local_frame.hpp"
#include "support/photos.hpp"

namespace uavcover::testing {
namespace {

/// Nadir photos every 30 m east and 20 m north over the thesis rectangle (100 m x 200 m from its
/// south-west corner), 30 m up, 24 mm equivalent (45 m x 30 m footprints), less the four around (55, 100).
void write_photos(const std::filesystem::path& dir, bool hole) {
  std::filesystem::create_directories(dir);
  const geodesy::LocalFrame frame({9.15, 45.39});
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 10; ++j) {
      const double x = 10.0 + 30.0 * i, y = 10.0 + 20.0 * j;
      if (hole && (i == 1 || i == 2) && (j == 4 || j == 5)) continue;
      const PhotoSpec s = nadir_photo(frame.to_wgs84(Point(x, y)), 30.0);
      write_bytes(dir / ("DJI_" + std::to_string(100 + i * 10 + j) + ".JPG"), photo_jpeg(s));
    }
}

TEST(PhotosCli, CoverageMapGapsAndTheReflyFromPhotos) {
  const auto dir = temp_dir("photos-cli");
  const auto mission = std::filesystem::path(UAVCOVER_BENCH_DATA) / "mondinelli2025" / "rectangle_3uav.json";
  const auto planned = dir / "plan";
  RunResult r = run_cli("-q plan '" + mission.string() + "' --out '" + planned.string() + "' --no-images");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto photos = dir / "photos";
  write_photos(photos, true);

  const auto out = dir / "seen";
  r = run_cli("photos '" + photos.string() + "' --plan '" + planned.string() + "' --out '" + out.string() +
              "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("36 photo(s)"), std::string::npos) << r.output;
  const auto summary = read_json(out / "photos.json");
  EXPECT_EQ(summary["photos"], 36);
  EXPECT_NEAR(summary["poc"].get<double>(), 1.0 - 1350.0 / 20000.0, 0.01);
  EXPECT_GT(summary["gaps_m2"].get<double>(), 1350.0);
  const auto fc = read_json(out / "photos.geojson");
  EXPECT_EQ(fc["features"].size(), 37u);
  EXPECT_TRUE(std::filesystem::exists(out / "photo-coverage.png"));

  // the refly of what no photo saw
  const auto refly = dir / "refly";
  r = run_cli("-q refly '" + planned.string() + "' --photos '" + photos.string() + "' --out '" +
              refly.string() + "' --uav red --no-images");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto plan = read_json(refly / "plan.json");
  EXPECT_EQ(plan["uavs"].size(), 1u);
  EXPECT_NE(plan["mission"]["name"].get<std::string>().find("(refly)"), std::string::npos);

  // every photo there: nothing to refly (exit 2, the area named)
  const auto full = dir / "full";
  write_photos(full, false);
  r = run_cli("-q refly '" + planned.string() + "' --photos '" + full.string() + "' --out '" +
              (dir / "none").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("area"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "none"));

  // the options: --flown and --photos exclude each other, one is needed; a bad photo is named
  r = run_cli("refly '" + planned.string() + "' --photos '" + photos.string() +
              "' --flown x.geojson --out '" + (dir / "x").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = run_cli("refly '" + planned.string() + "' --out '" + (dir / "x").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--flown"), std::string::npos) << r.output;
  write_bytes(photos / "broken.jpg", "not a jpeg");
  r = run_cli("photos '" + photos.string() + "' --plan '" + planned.string() + "' --out '" +
              (dir / "y").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("broken.jpg"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "y"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace uavcover::testing
