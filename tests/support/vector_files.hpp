// Vector files made at test time with GDAL's own tools (ogr2ogr) and zip from a GeoJSON written here:
// an area "North field" with a no-fly zone "Pylon" inside it, a second zone "Barn" and a point (which
// bounds nothing), in WGS84; the tests convert them to Shapefile, KML, KMZ, GeoPackage and DXF.
#pragma once

#include <fmt/format.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include "support/files.hpp"

namespace uavcover::testvec {

namespace fs = std::filesystem;

using TempDir = testing::TempDir;  // one fixture for every test (support/files.hpp)

inline constexpr const char* kFeatures = R"({"type": "FeatureCollection", "features": [
 {"type": "Feature", "properties": {"name": "North field", "kind": "area"},
  "geometry": {"type": "Polygon", "coordinates": [[[22.90, 40.60], [22.912, 40.60], [22.912, 40.607], [22.90, 40.607], [22.90, 40.60]]]}},
 {"type": "Feature", "properties": {"name": "Pylon", "kind": "nfz"},
  "geometry": {"type": "Polygon", "coordinates": [[[22.905, 40.603], [22.906, 40.603], [22.906, 40.604], [22.905, 40.604], [22.905, 40.603]]]}},
 {"type": "Feature", "properties": {"name": "Barn", "kind": "nfz"},
  "geometry": {"type": "Polygon", "coordinates": [[[22.909, 40.605], [22.910, 40.605], [22.910, 40.606], [22.909, 40.606], [22.909, 40.605]]]}},
 {"type": "Feature", "properties": {"name": "Well", "kind": "point"},
  "geometry": {"type": "Point", "coordinates": [22.901, 40.601]}}
]})";

/// A bow tie: its ring crosses itself.
inline constexpr const char* kBowTie = R"({"type": "FeatureCollection", "features": [
 {"type": "Feature", "properties": {"name": "Good"},
  "geometry": {"type": "Polygon", "coordinates": [[[22.90, 40.60], [22.91, 40.60], [22.91, 40.61], [22.90, 40.61], [22.90, 40.60]]]}},
 {"type": "Feature", "properties": {"name": "Twisted"},
  "geometry": {"type": "Polygon", "coordinates": [[[22.92, 40.60], [22.93, 40.61], [22.93, 40.60], [22.92, 40.61], [22.92, 40.60]]]}}
]})";

inline void run(const std::string& cmd) {
  if (std::system((cmd + " >/dev/null 2>&1").c_str()) != 0) throw std::runtime_error("failed: " + cmd);
}

inline fs::path write_text(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

inline std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// `dir/name` made by ogr2ogr from `geojson` (`args`: driver, target CRS, ...).
inline fs::path ogr2ogr(const fs::path& dir, const std::string& name, const std::string& args,
                        const std::string& geojson = kFeatures) {
  const fs::path src = write_text(dir / ("src_" + name + ".geojson"), geojson);
  const fs::path out = dir / name;
  run(fmt::format("ogr2ogr {} '{}' '{}'", args, out.string(), src.string()));
  return out;
}

/// A zipped Shapefile (in `epsg`) of the polygons (a Shapefile holds one geometry type).
inline fs::path zipped_shapefile(const fs::path& dir, int epsg, const std::string& geojson = kFeatures) {
  const fs::path shp = ogr2ogr(dir, "fields", fmt::format("-skipfailures -t_srs EPSG:{}", epsg), geojson);
  const fs::path zip = dir / "fields.zip";
  run(fmt::format("cd '{}' && zip -q -j '{}' *", shp.string(), zip.string()));
  return zip;
}

/// A KMZ: the KML ogr2ogr writes, zipped as doc.kml.
inline fs::path kmz(const fs::path& dir) {
  const fs::path kml = ogr2ogr(dir, "doc.kml", "-f KML");
  const fs::path out = dir / "fields.kmz";
  run(fmt::format("cd '{}' && zip -q '{}' doc.kml", dir.string(), out.string()));
  return out;
}

}  // namespace uavcover::testvec
