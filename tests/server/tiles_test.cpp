// GET /tiles/metadata.json and /tiles/{z}/{x}/{y} (docs/offline-maps.md) over an MBTiles file made at
// test time from the example DEM by scripts/make-tiles: tiles with their media type and Cache-Control,
// 404 for absent ones, 400 naming z, x or y for bad coordinates; and a server without tiles.
#include "support/tiles.hpp"
#include "io/mbtiles.hpp"
#include "server/api_fixture.hpp"

namespace uavcover::server::testing {
namespace {

using uavcover::testing::kDemLat;
using uavcover::testing::kDemLon;
using uavcover::testing::kTilesMaxZoom;
using uavcover::testing::tile_of;

class TilesApi : public ApiTest {
 protected:
  static void SetUpTestSuite() {
    dir_tiles_ = new std::filesystem::path(fresh_dir("tiles"));
    tiles_ = new std::shared_ptr<io::MbTiles>(
        io::MbTiles::open(uavcover::testing::make_example_tiles(*dir_tiles_)));
  }
  static void TearDownTestSuite() {
    delete tiles_;
    std::filesystem::remove_all(*dir_tiles_);
    delete dir_tiles_;
  }
  void with_tiles() { ctx_->tiles = tiles_->get(); }

  static std::filesystem::path* dir_tiles_;
  static std::shared_ptr<io::MbTiles>* tiles_;
};
std::filesystem::path* TilesApi::dir_tiles_ = nullptr;
std::shared_ptr<io::MbTiles>* TilesApi::tiles_ = nullptr;

TEST_P(TilesApi, TilesAreServedWithTheirTypeAndCacheControl) {
  with_tiles();
  const auto [x, y] = tile_of(kDemLon, kDemLat, kTilesMaxZoom);
  const std::string path =
      "/tiles/" + std::to_string(kTilesMaxZoom) + "/" + std::to_string(x) + "/" + std::to_string(y);
  const Answer a = call("GET", path);
  ASSERT_EQ(a.status, 200) << a.body;
  EXPECT_EQ(a.content_type, "image/png");
  EXPECT_EQ(a.body.rfind("\x89PNG\r\n\x1a\n", 0), 0U);
  EXPECT_EQ(a.body, *(*tiles_)->tile(kTilesMaxZoom, x, y));
  EXPECT_EQ(a.header("Cache-Control"), "max-age=86400");
  // the format's suffix names the same tile
  const Answer png = call("GET", path + ".png");
  EXPECT_EQ(png.status, 200);
  EXPECT_EQ(png.body, a.body);
  // another suffix does not
  const Answer jpg = call("GET", path + ".jpg");
  EXPECT_EQ(jpg.status, 400);
  EXPECT_EQ(jpg.error_field(), "y");
  // a tile the file lacks (the unflipped row, in the southern hemisphere): 404 as JSON
  const Answer absent = call("GET", "/tiles/" + std::to_string(kTilesMaxZoom) + "/" + std::to_string(x) +
                                        "/" + std::to_string((std::int64_t{1} << kTilesMaxZoom) - 1 - y));
  EXPECT_EQ(absent.status, 404);
  EXPECT_EQ(absent.content_type, "application/json");
  EXPECT_TRUE(absent.json().at("error").contains("message"));
  EXPECT_EQ(call("GET", "/tiles/30/0/0").status, 404);  // the deepest zoom asked of: absent, not wrong
}

TEST_P(TilesApi, BadCoordinatesAreRefusedNamingTheField) {
  with_tiles();
  const std::vector<std::pair<std::string, std::string>> cases{
      {"/tiles/31/0/0", "z"},          {"/tiles/-1/0/0", "z"},          {"/tiles/a/0/0", "z"},
      {"/tiles/1e1/0/0", "z"},         {"/tiles/99999999999/0/0", "z"}, {"/tiles/3/8/0", "x"},
      {"/tiles/3/-1/0", "x"},          {"/tiles/3/0x1/0", "x"},         {"/tiles/3/0/8", "y"},
      {"/tiles/3/0/8.png", "y"},       {"/tiles/3/0/+1", "y"},          {"/tiles/3/0/1.gif", "y"},
      {"/tiles/3/0/.png", "y"},        {"/tiles/0/1/0", "x"},           {"/tiles/30/1073741824/0", "x"},
      {"/tiles/30/0/1073741824", "y"},
  };
  for (const auto& [path, field] : cases) {
    const Answer a = call("GET", path);
    EXPECT_EQ(a.status, 400) << path << ": " << a.body;
    EXPECT_EQ(a.error_field(), field) << path;
  }
  EXPECT_EQ(call("GET", "/tiles/30/1073741823/1073741823").status, 404);  // the last tile of zoom 30
  EXPECT_EQ(call("GET", "/tiles/3/0").status, 404);                       // no such route
  EXPECT_EQ(call("POST", "/tiles/3/0/0").status, 405);
}

TEST_P(TilesApi, MetadataSaysWhereTheTilesAre) {
  with_tiles();
  const Answer a = call("GET", "/tiles/metadata.json");
  ASSERT_EQ(a.status, 200);
  const auto j = a.json();
  EXPECT_EQ(j.at("available"), true);
  EXPECT_EQ(j.at("url"), "/tiles/{z}/{x}/{y}");
  EXPECT_EQ(j.at("format"), "png");
  EXPECT_EQ(j.at("maxzoom"), kTilesMaxZoom);
  EXPECT_EQ(j.at("minzoom"), (*tiles_)->info().minzoom);
  const auto b = j.at("bounds").get<std::vector<double>>();
  ASSERT_EQ(b.size(), 4U);
  EXPECT_LT(b[0], kDemLon);
  EXPECT_GT(b[2], kDemLon);
  EXPECT_LT(b[1], kDemLat);
  EXPECT_GT(b[3], kDemLat);
  const auto c = j.at("center").get<std::vector<double>>();
  ASSERT_EQ(c.size(), 3U);
  EXPECT_TRUE(b[0] < c[0] && c[0] < b[2] && b[1] < c[1] && c[1] < b[3]);
}

TEST_P(TilesApi, WithoutTilesTheMetadataSaysSoAndTilesAre404) {
  const Answer m = call("GET", "/tiles/metadata.json");
  ASSERT_EQ(m.status, 200);
  EXPECT_EQ(m.json(), (nlohmann::json{{"available", false}}));
  const Answer t = call("GET", "/tiles/3/4/3");
  EXPECT_EQ(t.status, 404);
  EXPECT_NE(t.json().at("error").at("message").get<std::string>().find("--tiles"), std::string::npos);
  EXPECT_EQ(call("GET", "/tiles/31/0/0").error_field(), "z");  // still checked
}

// the routes do not touch the store: one backend is enough
INSTANTIATE_TEST_SUITE_P(Sqlite, TilesApi, ::testing::Values(std::string("sqlite:")), backend_name);

}  // namespace
}  // namespace uavcover::server::testing
