// The MBTiles reader (src/io/mbtiles.cpp) over a file scripts/make-tiles makes from the example DEM at
// test time: its metadata, XYZ rows turned into the file's TMS rows, concurrent readers on a bounded
// pool, the file left as it was; and every malformed file refused naming --tiles.
#include "io/mbtiles.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <atomic>
#include <fstream>
#include <random>
#include <thread>

#include "support/files.hpp"
#include "support/terrain_mission.hpp"
#include "support/tiles.hpp"
#include "uavcover/error.hpp"

namespace uavcover {
namespace {

using testdem::TempDir;
using testing::kDemLat;
using testing::kDemLon;
using testing::kTilesMaxZoom;
using testing::tile_of;

constexpr const char* kPngMagic = "\x89PNG\r\n\x1a\n";

class MbTilesTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir("mbtiles");
    file_ = new std::filesystem::path(testing::make_example_tiles(dir_->path));
  }
  static void TearDownTestSuite() {
    delete file_;
    delete dir_;
  }
  static TempDir* dir_;
  static std::filesystem::path* file_;
};
TempDir* MbTilesTest::dir_ = nullptr;
std::filesystem::path* MbTilesTest::file_ = nullptr;

/// The tile_data of a TMS row, read with plain SQLite.
std::optional<std::string> raw_tile(const std::filesystem::path& file, int z, std::int64_t col,
                                    std::int64_t row) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open_v2(file.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* s = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(
                db, "SELECT tile_data FROM tiles WHERE zoom_level = ? AND tile_column = ? AND tile_row = ?",
                -1, &s, nullptr),
            SQLITE_OK);
  sqlite3_bind_int(s, 1, z);
  sqlite3_bind_int64(s, 2, col);
  sqlite3_bind_int64(s, 3, row);
  std::optional<std::string> out;
  if (sqlite3_step(s) == SQLITE_ROW)
    out = std::string(static_cast<const char*>(sqlite3_column_blob(s, 0)),
                      static_cast<std::size_t>(sqlite3_column_bytes(s, 0)));
  sqlite3_finalize(s);
  sqlite3_close(db);
  return out;
}

/// Runs SQL on a new database file `path`.
void make_db(const std::filesystem::path& path, const std::string& sql) {
  std::filesystem::remove(path);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  char* err = nullptr;
  const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &err);
  const std::string msg = err ? err : "";
  sqlite3_free(err);
  sqlite3_close(db);
  ASSERT_EQ(rc, SQLITE_OK) << msg;
}

/// The InputError message of opening `file`; fails when it opens or the error names another field.
std::string refusal(const std::filesystem::path& file) {
  try {
    io::MbTiles::open(file);
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--tiles");
    return e.what();
  }
  ADD_FAILURE() << file << " was accepted";
  return "";
}

TEST_F(MbTilesTest, TheExampleDemsHillshadeHasItsMetadata) {
  const auto tiles = io::MbTiles::open(*file_);
  const auto& i = tiles->info();
  EXPECT_EQ(i.format, "png");
  EXPECT_EQ(i.media_type, "image/png");
  EXPECT_EQ(i.name, "hill");
  EXPECT_EQ(i.maxzoom, kTilesMaxZoom);
  EXPECT_LT(i.minzoom, i.maxzoom);  // gdaladdo made the coarser levels
  EXPECT_GE(i.minzoom, 0);
  ASSERT_TRUE(i.bounds.has_value());
  const auto& b = *i.bounds;
  // the DEM is 1200 m square around its centre: about 0.0142 degrees of longitude, 0.0108 of latitude
  EXPECT_LT(b[0], kDemLon);
  EXPECT_GT(b[2], kDemLon);
  EXPECT_LT(b[1], kDemLat);
  EXPECT_GT(b[3], kDemLat);
  EXPECT_NEAR(b[2] - b[0], 1200.0 / (111320.0 * std::cos(kDemLat * M_PI / 180)), 0.002);
  EXPECT_NEAR(b[3] - b[1], 1200.0 / 111320.0, 0.002);
  // scripts/make-tiles adds the centre: the middle of the bounds, two levels above the finest
  ASSERT_TRUE(i.center.has_value());
  EXPECT_NEAR((*i.center)[0], (b[0] + b[2]) / 2, 1e-6);
  EXPECT_NEAR((*i.center)[1], (b[1] + b[3]) / 2, 1e-6);
  EXPECT_EQ((*i.center)[2], kTilesMaxZoom - 2);
}

TEST_F(MbTilesTest, XyzRowsAreTheFilesTmsRowsFlipped) {
  const auto tiles = io::MbTiles::open(*file_);
  const auto& i = tiles->info();
  for (int z = i.minzoom; z <= i.maxzoom; ++z) {
    const auto [x, y] = tile_of(kDemLon, kDemLat, z);
    const std::int64_t n = std::int64_t{1} << z;
    const auto got = tiles->tile(z, x, y);
    ASSERT_TRUE(got.has_value()) << "zoom " << z;
    EXPECT_EQ(got->rfind(kPngMagic, 0), 0U) << "zoom " << z;
    // the bytes are the file's row 2^z - 1 - y (TMS, from the south)
    EXPECT_EQ(got, raw_tile(*file_, z, x, n - 1 - y)) << "zoom " << z;
    // the unflipped row is in the southern hemisphere, where the file has nothing
    EXPECT_FALSE(tiles->tile(z, x, n - 1 - y).has_value()) << "zoom " << z;
    // nor far east of the DEM
    EXPECT_FALSE(tiles->tile(z, std::min(n - 1, x + 10), y).has_value()) << "zoom " << z;
  }
  // the coarsest level holds the whole DEM in tiles, the finest more of them
  EXPECT_FALSE(tiles->tile(i.maxzoom + 1, 0, 0).has_value());
  EXPECT_FALSE(tiles->tile(31, 0, 0).has_value());
  EXPECT_FALSE(tiles->tile(-1, 0, 0).has_value());
  EXPECT_FALSE(tiles->tile(3, 8, 0).has_value());
  EXPECT_FALSE(tiles->tile(3, 0, -1).has_value());
}

TEST_F(MbTilesTest, ConcurrentReadersShareABoundedPool) {
  const auto tiles = io::MbTiles::open(*file_, "--tiles", 2);
  const int z = kTilesMaxZoom;
  const auto [x, y] = tile_of(kDemLon, kDemLat, z);
  std::vector<std::pair<std::int64_t, std::int64_t>> cells;
  std::vector<std::optional<std::string>> expected;
  for (int dx = -3; dx <= 3; ++dx)
    for (int dy = -3; dy <= 3; ++dy) {
      cells.emplace_back(x + dx, y + dy);
      expected.push_back(raw_tile(*file_, z, x + dx, (std::int64_t{1} << z) - 1 - (y + dy)));
    }
  std::atomic<int> wrong{0}, found{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t)
    threads.emplace_back([&, t] {
      for (int k = 0; k < 200; ++k) {
        const std::size_t c = static_cast<std::size_t>(t * 31 + k * 7) % cells.size();
        const auto got = tiles->tile(z, cells[c].first, cells[c].second);
        if (got != expected[c]) ++wrong;
        if (got) ++found;
      }
    });
  for (auto& th : threads) th.join();
  EXPECT_EQ(wrong.load(), 0);
  EXPECT_GT(found.load(), 0);
}

TEST_F(MbTilesTest, TheFileIsOnlyRead) {
  const auto before = testing::slurp(*file_);
  const auto mtime = std::filesystem::last_write_time(*file_);
  {
    const auto tiles = io::MbTiles::open(*file_);
    const auto [x, y] = tile_of(kDemLon, kDemLat, kTilesMaxZoom);
    EXPECT_TRUE(tiles->tile(kTilesMaxZoom, x, y).has_value());
  }
  EXPECT_EQ(testing::slurp(*file_), before);
  EXPECT_EQ(std::filesystem::last_write_time(*file_), mtime);
  for (const char* tail : {"-journal", "-wal", "-shm"})
    EXPECT_FALSE(std::filesystem::exists(file_->string() + tail)) << tail;
}

TEST(MbTiles, MalformedFilesAreRefusedNamingTiles) {
  TempDir dir("mbtiles_bad");
  const auto& d = dir.path;
  EXPECT_NE(refusal(d / "missing.mbtiles").find("does not exist"), std::string::npos);
  EXPECT_NE(refusal(d).find("is not a file"), std::string::npos);

  std::mt19937 rng(7);
  std::string noise(4096, '\0');
  for (auto& c : noise) c = static_cast<char>(rng());
  std::ofstream(d / "noise.mbtiles", std::ios::binary) << noise;
  EXPECT_NE(refusal(d / "noise.mbtiles").find("not an SQLite database"), std::string::npos);
  std::ofstream(d / "text.mbtiles") << "SQLite format 3 but not really, just text\n";
  EXPECT_NE(refusal(d / "text.mbtiles").find("not an SQLite database"), std::string::npos);

  std::ofstream(d / "empty.mbtiles").flush();  // SQLite reads an empty file as an empty database
  EXPECT_NE(refusal(d / "empty.mbtiles").find("no table tiles"), std::string::npos);

  const std::string tiles_table =
      "CREATE TABLE tiles (zoom_level INTEGER, tile_column INTEGER, tile_row INTEGER, tile_data BLOB);";
  const std::string metadata_table = "CREATE TABLE metadata (name TEXT, value TEXT);";
  const std::string a_png_tile = "INSERT INTO tiles VALUES (3, 4, 4, X'89504E470D0A1A0A0000');";
  make_db(d / "no_tiles_table.mbtiles", metadata_table + "INSERT INTO metadata VALUES ('format', 'png');");
  EXPECT_NE(refusal(d / "no_tiles_table.mbtiles").find("no table tiles"), std::string::npos);
  make_db(d / "no_metadata.mbtiles", tiles_table + a_png_tile);
  EXPECT_NE(refusal(d / "no_metadata.mbtiles").find("no table metadata"), std::string::npos);
  make_db(d / "bad_columns.mbtiles",
          metadata_table + "CREATE TABLE tiles (z INTEGER, x INTEGER, y INTEGER, data BLOB);");
  EXPECT_NE(refusal(d / "bad_columns.mbtiles").find("no table tiles"), std::string::npos);
  make_db(d / "vector.mbtiles",
          metadata_table + tiles_table + a_png_tile + "INSERT INTO metadata VALUES ('format', 'pbf');");
  EXPECT_NE(refusal(d / "vector.mbtiles").find("not a raster format"), std::string::npos);
  make_db(d / "no_rows.mbtiles",
          metadata_table + tiles_table + "INSERT INTO metadata VALUES ('format', 'png');");
  EXPECT_NE(refusal(d / "no_rows.mbtiles").find("holds no tiles"), std::string::npos);
  make_db(d / "unknown.mbtiles",
          metadata_table + tiles_table + "INSERT INTO tiles VALUES (3, 4, 4, X'0102');");
  EXPECT_NE(refusal(d / "unknown.mbtiles").find("no metadata 'format'"), std::string::npos);
  make_db(d / "zoom.mbtiles", metadata_table + tiles_table + a_png_tile +
                                  "INSERT INTO metadata VALUES ('format', 'png'), ('maxzoom', '40');");
  EXPECT_NE(refusal(d / "zoom.mbtiles").find("zoom levels"), std::string::npos);
}

TEST(MbTiles, TheTilesBytesOverruleAWrongRasterFormat) {
  TempDir dir("mbtiles_wrong_format");
  const auto file = dir.path / "webp.mbtiles";
  make_db(file,
          "CREATE TABLE metadata (name TEXT, value TEXT);"
          "CREATE TABLE tiles (zoom_level INTEGER, tile_column INTEGER, tile_row INTEGER, tile_data BLOB);"
          "INSERT INTO metadata VALUES ('format', 'png');"  // as GDAL 3.6 writes it for WebP tiles
          "INSERT INTO tiles VALUES (1, 0, 0, X'52494646000000005745425056503820');");
  const auto tiles = io::MbTiles::open(file);
  EXPECT_EQ(tiles->info().format, "webp");
  EXPECT_EQ(tiles->info().media_type, "image/webp");
}

TEST(MbTiles, WithoutFormatOrZoomMetadataTheTilesTell) {
  TempDir dir("mbtiles_sniff");
  const auto file = dir.path / "sniff.mbtiles";
  make_db(file,
          "CREATE TABLE metadata (name TEXT, value TEXT);"
          "CREATE TABLE tiles (zoom_level INTEGER, tile_column INTEGER, tile_row INTEGER, tile_data BLOB);"
          "INSERT INTO metadata VALUES ('bounds', 'not numbers');"
          "INSERT INTO tiles VALUES (2, 1, 2, X'FFD8FFE000'), (5, 3, 4, X'FFD8FFE001');");
  const auto tiles = io::MbTiles::open(file);
  EXPECT_EQ(tiles->info().format, "jpg");
  EXPECT_EQ(tiles->info().media_type, "image/jpeg");
  EXPECT_EQ(tiles->info().minzoom, 2);
  EXPECT_EQ(tiles->info().maxzoom, 5);
  EXPECT_FALSE(tiles->info().bounds.has_value());  // malformed bounds are left out
  EXPECT_EQ(tiles->info().name, "sniff");
  // XYZ (2, 1, 1) is TMS row 4 - 1 - 1 = 2
  EXPECT_EQ(tiles->tile(2, 1, 1), std::string("\xFF\xD8\xFF\xE0\x00", 5));
  EXPECT_EQ(tiles->tile(5, 3, 32 - 1 - 4), std::string("\xFF\xD8\xFF\xE0\x01", 5));
  EXPECT_FALSE(tiles->tile(2, 1, 2).has_value());
}

}  // namespace
}  // namespace uavcover
