// `uavcover serve --tiles FILE`: a file that is not a raster MBTiles stops the start with exit status 2
// and a message naming --tiles, before the database is opened (docs/offline-maps.md).
#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "cli/cli_support.hpp"

using namespace uavcover::testing;
namespace fs = std::filesystem;

TEST(TilesCli, AServerWithBadTilesDoesNotStart) {
  const auto dir = temp_dir("tiles-cli");
  std::mt19937 rng(11);
  std::string noise(2048, '\0');
  for (auto& c : noise) c = static_cast<char>(rng());
  std::ofstream(dir / "noise.mbtiles", std::ios::binary) << noise;
  const std::vector<std::pair<fs::path, std::string>> cases{
      {dir / "missing.mbtiles", "does not exist"},
      {dir / "noise.mbtiles", "not an SQLite database"},
      {dir, "is not a file"},
  };
  for (const auto& [file, why] : cases) {
    SCOPED_TRACE(file.string());
    const auto r = run_cli("serve --listen 127.0.0.1:0 --db 'sqlite:" + (dir / "t.db").string() +
                           "' --tiles '" + file.string() + "'");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--tiles: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(why), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("serving on"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "t.db"));  // refused before the database was opened
  }
  fs::remove_all(dir);
}
