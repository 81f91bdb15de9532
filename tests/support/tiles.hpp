// An MBTiles file made at test time by scripts/make-tiles from the example DEM (examples/hill-dem.tif,
// its hillshade; docs/offline-maps.md), never a checked-in binary. Needs the GDAL tools (gdal-bin).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>

namespace uavcover::testing {

inline constexpr double kDemLon = 22.906;  // the example DEM's centre (scripts/make-example-dem)
inline constexpr double kDemLat = 40.6035;
inline constexpr int kTilesMaxZoom = 16;

/// Writes `dir`/hill.mbtiles with scripts/make-tiles (the DEM's hillshade, zoom .. 16); the test fails
/// when the script does.
inline std::filesystem::path make_example_tiles(const std::filesystem::path& dir) {
  const std::filesystem::path src(UAVCOVER_SOURCE_DIR);
  const auto out = dir / "hill.mbtiles";
  const std::string cmd = "python3 '" + (src / "scripts" / "make-tiles").string() + "' '" +
                          (src / "examples" / "hill-dem.tif").string() + "' '" + out.string() +
                          "' --hillshade --z-factor 3 --max-zoom " + std::to_string(kTilesMaxZoom) +
                          " >/dev/null";
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(rc, 0) << cmd;
  EXPECT_TRUE(std::filesystem::exists(out)) << cmd;
  return out;
}

/// The XYZ tile (x, y counted from the north) holding lon/lat at zoom z (Web Mercator).
inline std::pair<std::int64_t, std::int64_t> tile_of(double lon, double lat, int z) {
  const double n = std::ldexp(1.0, z);
  const double r = lat * M_PI / 180.0;
  const auto x = static_cast<std::int64_t>(std::floor((lon + 180.0) / 360.0 * n));
  const auto y = static_cast<std::int64_t>(std::floor((1.0 - std::asinh(std::tan(r)) / M_PI) / 2.0 * n));
  return {x, y};
}

}  // namespace uavcover::testing
