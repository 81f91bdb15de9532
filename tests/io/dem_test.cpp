// The DEM reader (src/io/dem.cpp): GeoTIFF hills in WGS84 and UTM read into the core's grid, and every
// bad DEM refused as terrain.dem with what is wrong.
#include "io/dem.hpp"

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include "support/dem.hpp"
#include "support/terrain_mission.hpp"
#include "uavcover/error.hpp"

namespace uavcover {
namespace {

using testdem::Hill;
using testdem::kOrigin;
using testdem::TempDir;

// The grid matches the hill at random points of the mission's area (bilinear over 4 m pixels: within
// 0.5 m on a hill whose slope reaches 0.6), and its highest node is the summit.
void expect_hill(const HeightGrid& g, const Hill& hill) {
  const geodesy::LocalFrame f(kOrigin);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(-150, 150), uy(-100, 100);
  double worst = 0;
  for (int k = 0; k < 2000; ++k) {
    const double x = ux(rng), y = uy(rng);
    worst = std::max(worst, std::fabs(g.at(f.to_wgs84({x, y})) - hill(x, y)));
  }
  EXPECT_LT(worst, 0.5);
  EXPECT_NEAR(g.max_m, hill.base + hill.peak, 0.5);
  EXPECT_GT(g.step_m, 2.0);
  EXPECT_LT(g.step_m, 6.0);
}

TEST(Dem, ReadsAGeographicHill) {
  TempDir dir("dem_geo");
  const Hill hill;
  testdem::write_hill(dir.path / "hill.tif", geodesy::LocalFrame(kOrigin), hill);
  Mission m = parse_mission(testdem::mission_text("hill.tif"));
  io::load_terrain(m, dir.path);
  ASSERT_TRUE(m.terrain && m.terrain->grid);
  EXPECT_TRUE(std::filesystem::path(m.terrain->dem).is_absolute());  // plan.json can find it again
  expect_hill(*m.terrain->grid, hill);
}

TEST(Dem, ReadsAProjectedUtmHill) {
  TempDir dir("dem_utm");
  const Hill hill{200, 60, 60, 30, -20};
  testdem::DemSpec spec;
  spec.epsg = 32632;  // UTM zone 32N: easting/northing in metres
  testdem::write_hill(dir.path / "utm.tif", geodesy::LocalFrame(kOrigin), hill, spec);
  Mission m = parse_mission(testdem::mission_text("utm.tif"));
  io::load_terrain(m, dir.path);
  expect_hill(*m.terrain->grid, hill);
}

TEST(Dem, WithoutATerrainBlockNothingIsRead) {
  Mission m = parse_mission(testdem::mission_text("x.tif"));
  m.terrain.reset();
  io::load_terrain(m, "/nonexistent");
  EXPECT_FALSE(m.terrain.has_value());
}

// The refusal's field and message
std::string refusal(const std::string& dem, const std::filesystem::path& base, double area_dx = 0,
                    io::DemLimits limits = {}) {
  Mission m = parse_mission(testdem::mission_text(dem, "follow", 1.0, area_dx));
  try {
    io::load_terrain(m, base, limits);
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "terrain.dem");
    return e.what();
  }
  ADD_FAILURE() << "not refused: " << dem;
  return "";
}

TEST(Dem, ADemMissingTheAreaIsRefusedWithTheMissingExtent) {
  TempDir dir("dem_miss");
  testdem::write_hill(dir.path / "hill.tif", geodesy::LocalFrame(kOrigin), Hill{});
  // the area moved 400 m east: its east part (and margin) lies beyond the raster's east edge at +400 m
  const std::string msg = refusal("hill.tif", dir.path, 400);
  EXPECT_NE(msg.find("does not cover the mission"), std::string::npos) << msg;
  // the missing extent starts at the raster's east edge (local x = 400 m)
  const LonLat edge = geodesy::LocalFrame(kOrigin).to_wgs84({400, 0});
  const auto at = msg.find("no ground heights for longitude ");
  ASSERT_NE(at, std::string::npos) << msg;
  const double west = std::stod(msg.substr(at + 32));
  EXPECT_NEAR(west, edge.lon, 0.0002) << msg;  // within a grid step (4 m ~ 0.00005°)
  EXPECT_NE(msg.find("the DEM covers longitude"), std::string::npos) << msg;
}

TEST(Dem, BadFilesAreRefusedNamingTheProblem) {
  TempDir dir("dem_bad");
  const geodesy::LocalFrame f(kOrigin);
  std::ofstream(dir.path / "text.tif") << "this is not a GeoTIFF\n";
  EXPECT_NE(refusal("text.tif", dir.path).find("is not a GeoTIFF"), std::string::npos);
  EXPECT_NE(refusal("missing.tif", dir.path).find("no such file"), std::string::npos);
  std::filesystem::create_directory(dir.path / "folder.tif");
  EXPECT_NE(refusal("folder.tif", dir.path).find("not a regular file"), std::string::npos);
  EXPECT_NE(refusal("/dev/zero", dir.path).find("not a regular file"), std::string::npos);

  testdem::DemSpec no_crs;
  no_crs.write_crs = false;
  testdem::write_hill(dir.path / "nocrs.tif", f, Hill{}, no_crs);
  EXPECT_NE(refusal("nocrs.tif", dir.path).find("has no coordinate reference system"), std::string::npos);

  // NaN heights inside the area, no nodata value: refused with where they are
  testdem::DemSpec nan;
  nan.hole = [](double x, double y) { return std::hypot(x - 50, y - 20) < 15; };
  testdem::write_hill(dir.path / "nan.tif", f, Hill{}, nan);
  const std::string msg = refusal("nan.tif", dir.path);
  EXPECT_NE(msg.find("NaN"), std::string::npos) << msg;
  const LonLat hole = f.to_wgs84({50, 20});
  const auto at = msg.find("longitude ");
  ASSERT_NE(at, std::string::npos);
  EXPECT_NEAR(std::stod(msg.substr(at + 10)), hole.lon, 0.0003) << msg;

  // nodata (-9999) under the area: a void in the DEM, refused as no data
  testdem::DemSpec voids;
  voids.nodata = -9999;
  voids.hole_value = -9999;
  voids.hole = [](double x, double y) { return std::hypot(x + 60, y) < 10; };
  testdem::write_hill(dir.path / "void.tif", f, Hill{}, voids);
  EXPECT_NE(refusal("void.tif", dir.path).find("has no data (nodata value -9999)"), std::string::npos);
}

TEST(Dem, AHugeRasterIsReadOnlyThroughABoundedWindow) {
  TempDir dir("dem_huge");
  // a sparse 200 000 x 200 000 GeoTIFF (tiny on disk) with 5 mm pixels over the area: the window the
  // mission needs is ~ 100 000 x 80 000 pixels, refused before any pixel is read
  GDALAllRegister();
  const geodesy::LocalFrame f(kOrigin);
  OGRSpatialReference srs;
  srs.importFromEPSG(32632);
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  OGRSpatialReference wgs;
  wgs.SetWellKnownGeogCS("WGS84");
  wgs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> ct(OGRCreateCoordinateTransformation(&wgs, &srs));
  LonLat sw = f.to_wgs84({-500, -500});
  double x = sw.lon, y = sw.lat;
  ct->Transform(1, &x, &y);
  const char* opts[] = {"TILED=YES",      "BLOCKXSIZE=4096", "BLOCKYSIZE=4096",
                        "SPARSE_OK=TRUE", "BIGTIFF=YES",     nullptr};
  GDALDataset* ds = GetGDALDriverManager()->GetDriverByName("GTiff")->Create(
      (dir.path / "huge.tif").c_str(), 200000, 200000, 1, GDT_Float32, const_cast<char**>(opts));
  ASSERT_NE(ds, nullptr);
  double gt[6] = {x, 0.005, 0, y + 1000, 0, -0.005};
  ds->SetGeoTransform(gt);
  ds->SetSpatialRef(&srs);
  GDALClose(ds);
  EXPECT_LT(std::filesystem::file_size(dir.path / "huge.tif"), std::uintmax_t{1} << 20);
  const std::string msg = refusal("huge.tif", dir.path);
  EXPECT_NE(msg.find("more than the limit of 16777216 pixels"), std::string::npos) << msg;
  // a smaller limit refuses a normal DEM likewise; a larger grid limit is not needed for it
  testdem::write_hill(dir.path / "hill.tif", f, Hill{});
  io::DemLimits small;
  small.max_window_pixels = 1000;
  EXPECT_NE(refusal("hill.tif", dir.path, 0, small).find("more than the limit of 1000 pixels"),
            std::string::npos);
}

TEST(Dem, AGridLimitCoarsensTheGridInsteadOfRefusing) {
  TempDir dir("dem_coarse");
  testdem::write_hill(dir.path / "hill.tif", geodesy::LocalFrame(kOrigin), Hill{});
  Mission m = parse_mission(testdem::mission_text("hill.tif"));
  io::DemLimits limits;
  limits.max_grid_nodes = 400;
  io::load_terrain(m, dir.path, limits);
  const HeightGrid& g = *m.terrain->grid;
  EXPECT_LE(static_cast<std::size_t>(g.cols) * static_cast<std::size_t>(g.rows), 400u);
  EXPECT_GT(g.step_m, 15.0);
}

}  // namespace
}  // namespace uavcover
