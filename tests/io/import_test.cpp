// The vector importer (src/io/import.cpp) on files GDAL's own tools write at test time: a zipped
// Shapefile in Greek Grid (EPSG:2100), a KML, a KMZ, a GeoPackage in UTM 34N, a GeoJSON and a DXF;
// reprojection, names, the area picked by size or by attribute, and the refusals naming the field.
#include "io/import.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "support/errors.hpp"
#include "support/vector_files.hpp"
#include "uavcover/error.hpp"
#include "uavcover/mission.hpp"

namespace uavcover {
namespace {

using testing::field_of;
using testvec::TempDir;

// The largest vertex distance (degrees) between the imported ring and the GeoJSON's, in any order.
double ring_error(const nlohmann::json& ring, const std::vector<std::pair<double, double>>& expected) {
  double worst = 0;
  for (const auto& p : ring) {
    double best = 1e9;
    for (const auto& [lon, lat] : expected)
      best = std::min(best, std::hypot(p[0].get<double>() - lon, p[1].get<double>() - lat));
    worst = std::max(worst, best);
  }
  return worst;
}

const std::vector<std::pair<double, double>> kNorthField = {
    {22.90, 40.60}, {22.912, 40.60}, {22.912, 40.607}, {22.90, 40.607}};
const std::vector<std::pair<double, double>> kPylon = {
    {22.905, 40.603}, {22.906, 40.603}, {22.906, 40.604}, {22.905, 40.604}};

// The skeleton of kFeatures: the largest polygon (North field) is the area, the others zones by name,
// within `tolerance` degrees of the source after reprojection; parse_mission accepts it.
void expect_fields(const nlohmann::json& m, double tolerance, bool names = true) {
  if (names) {
    EXPECT_EQ(m["name"], "North field");
  }
  ASSERT_EQ(m["area"]["type"], "Polygon");
  EXPECT_LT(ring_error(m["area"]["coordinates"][0], kNorthField), tolerance);
  ASSERT_EQ(m["no_fly_zones"].size(), 2U);  // the point bounds nothing
  const nlohmann::json* pylon = nullptr;
  for (const auto& z : m["no_fly_zones"]) {
    EXPECT_EQ(z["type"], "Feature");
    if (!names || z["properties"].value("name", "") == "Pylon") pylon = &z;
  }
  ASSERT_NE(pylon, nullptr);
  if (names) {
    EXPECT_LT(ring_error((*pylon)["geometry"]["coordinates"][0], kPylon), tolerance);
  }
  const Mission parsed = parse_mission(m.dump());
  EXPECT_EQ(parsed.no_fly_zones.size(), 2U);
  EXPECT_EQ(m["uavs"], 1);
  EXPECT_EQ(m["spacing_m"], 30);
}

TEST(Import, ZippedShapefileInGreekGridIsReprojectedToWgs84) {
  TempDir dir("shp");
  const auto zip = testvec::zipped_shapefile(dir.path, 2100);
  // the Shapefile really is projected: eastings and northings in metres
  ASSERT_NE(testvec::read_bytes(zip.parent_path() / "fields" / "src_fields.prj").find("Greek_Grid"),
            std::string::npos);
  expect_fields(io::import_mission(zip), 1e-6);  // 1e-6 degrees: about 0.1 m
}

TEST(Import, ZippedShapefileInUtmFromBytes) {
  TempDir dir("shp_utm");
  const auto zip = testvec::zipped_shapefile(dir.path, 32634);
  expect_fields(io::import_mission_bytes(testvec::read_bytes(zip), "fields.zip"), 1e-6);
}

TEST(Import, KmlAndKmzKeepTheirNames) {
  TempDir dir("kml");
  expect_fields(io::import_mission(testvec::ogr2ogr(dir.path, "fields.kml", "-f KML")), 1e-9);
  const auto kmz = testvec::kmz(dir.path);
  expect_fields(io::import_mission(kmz), 1e-9);
  expect_fields(io::import_mission_bytes(testvec::read_bytes(kmz), "fields.kmz"), 1e-9);
}

TEST(Import, GeoPackageInUtmFromBytesAndFile) {
  TempDir dir("gpkg");
  const auto gpkg = testvec::ogr2ogr(dir.path, "fields.gpkg", "-f GPKG -t_srs EPSG:32634 -nln parcels");
  expect_fields(io::import_mission(gpkg), 1e-6);
  expect_fields(io::import_mission_bytes(testvec::read_bytes(gpkg), "fields.gpkg"), 1e-6);
}

TEST(Import, GeoJsonAsIs) {
  TempDir dir("geojson");
  expect_fields(io::import_mission(testvec::write_text(dir.path / "f.geojson", testvec::kFeatures)), 1e-9);
}

TEST(Import, DxfHasNoCrsSoOneIsNamed) {
  TempDir dir("dxf");
  const auto dxf = testvec::ogr2ogr(dir.path, "fields.dxf", "-f DXF -t_srs EPSG:2100");
  EXPECT_EQ(field_of([&] { io::import_mission(dxf); }), "crs");  // Greek Grid metres are no longitudes
  io::ImportOptions opt;
  opt.crs = "EPSG:2100";
  expect_fields(io::import_mission(dxf, opt), 1e-6, /*names=*/false);  // DXF keeps no attributes
  opt.crs = "EPSG:99999999";
  EXPECT_EQ(field_of([&] { io::import_mission(dxf, opt); }), "crs");
  opt.crs = "/etc/passwd";
  EXPECT_EQ(field_of([&] { io::import_mission(dxf, opt); }), "crs");
}

TEST(Import, AreaPickedByAttributeAndLayer) {
  TempDir dir("where");
  const auto gpkg = testvec::ogr2ogr(dir.path, "fields.gpkg", "-f GPKG -nln parcels");
  io::ImportOptions opt;
  opt.layer = "parcels";
  opt.area_where = "name = 'Barn'";
  const nlohmann::json m = io::import_mission(gpkg, opt);
  EXPECT_EQ(m["name"], "Barn");
  // North field around the barn is no zone of it; the pylon outside it is
  ASSERT_EQ(m["no_fly_zones"].size(), 1U);
  EXPECT_EQ(m["no_fly_zones"][0]["properties"]["name"], "Pylon");
  // two features matched: a MultiPolygon area
  opt.area_where = "kind = 'nfz'";
  opt.template_mission = {{"uavs", 3},
                          {"spacing_m", 12},
                          {"planner", "boustrophedon"},
                          {"name", "x"},
                          {"corridor", {{"width_m", 5}}}};
  const nlohmann::json two = io::import_mission(gpkg, opt);
  EXPECT_EQ(two["area"]["type"], "MultiPolygon");
  EXPECT_EQ(two["area"]["coordinates"].size(), 2U);
  EXPECT_EQ(two["uavs"], 3);  // from the template
  EXPECT_EQ(two["spacing_m"], 12);
  EXPECT_EQ(two["planner"], "boustrophedon");
  EXPECT_FALSE(two.contains("corridor"));
  EXPECT_EQ(two["name"], "Pylon");  // the first matching feature's name
  opt.template_mission = nullptr;

  opt.area_where = "name = 'Nowhere'";
  EXPECT_EQ(field_of([&] { io::import_mission(gpkg, opt); }), "area_where");
  opt.area_where = "name ==== 'x'";
  EXPECT_EQ(field_of([&] { io::import_mission(gpkg, opt); }), "area_where");
  opt.area_where.reset();
  opt.layer = "roads";
  try {
    io::import_mission(gpkg, opt);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "layer");
    EXPECT_NE(std::string(e.what()).find("'parcels'"), std::string::npos) << e.what();
  }
}

TEST(Import, InvalidGeometryIsRefusedNamingTheFeature) {
  TempDir dir("invalid");
  const auto gpkg = testvec::ogr2ogr(dir.path, "bad.gpkg", "-f GPKG -nln parcels", testvec::kBowTie);
  try {
    io::import_mission(gpkg);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "file");
    const std::string what = e.what();
    EXPECT_NE(what.find("layer 'parcels', feature 2 ('Twisted')"), std::string::npos) << what;
    EXPECT_NE(what.find("invalid geometry"), std::string::npos) << what;
  }
}

TEST(Import, BadFilesAreRefusedAsFile) {
  TempDir dir("bad");
  EXPECT_EQ(field_of([&] { io::import_mission(dir.path / "missing.kml"); }), "file");
  EXPECT_EQ(field_of([&] { io::import_mission(testvec::write_text(dir.path / "x.kml", "<kml><oops")); }),
            "file");
  EXPECT_EQ(field_of([&] { io::import_mission_bytes("PK\x03\x04 not really", "x.zip"); }), "file");
  EXPECT_EQ(field_of([&] { io::import_mission_bytes("{}", "x.exe"); }), "file");
  EXPECT_EQ(field_of([&] { io::import_mission_bytes("", "x.kml"); }), "file");
  // points only: nothing bounds an area
  EXPECT_EQ(field_of([&] {
              io::import_mission_bytes(
                  R"({"type":"Feature","properties":{},"geometry":{"type":"Point","coordinates":[1,2]}})",
                  "p.geojson");
            }),
            "file");
  // a zip without anything to import
  testvec::write_text(dir.path / "readme.txt", "hello");
  testvec::run("cd '" + dir.path.string() + "' && zip -q other.zip readme.txt");
  EXPECT_EQ(field_of([&] { io::import_mission(dir.path / "other.zip"); }), "file");
  // a template that is no mission object
  io::ImportOptions opt;
  opt.template_mission = nlohmann::json::array();
  EXPECT_EQ(field_of([&] { io::import_mission_bytes(testvec::kFeatures, "f.geojson", opt); }), "template");
  // a template field parse_mission refuses is named as the mission's field
  opt.template_mission = {{"spacing_m", -3}};
  EXPECT_EQ(field_of([&] { io::import_mission_bytes(testvec::kFeatures, "f.geojson", opt); }), "spacing_m");
}

TEST(Import, LimitsAreEnforced) {
  io::ImportLimits limits;
  limits.max_features = 2;
  EXPECT_EQ(field_of([&] { io::import_mission_bytes(testvec::kFeatures, "f.geojson", {}, limits); }), "file");
  limits = {};
  limits.max_vertices = 8;
  EXPECT_EQ(field_of([&] { io::import_mission_bytes(testvec::kFeatures, "f.geojson", {}, limits); }), "file");
}

}  // namespace
}  // namespace uavcover
