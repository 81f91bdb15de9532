// Importing the polygons operators have (zipped Shapefile, KML, KMZ, GeoPackage, GeoJSON, DXF) into a
// mission skeleton, with GDAL/OGR (CMake target uavcover_import; docs/import.md). Only io/ reads files;
// the server hands the upload over as bytes, read from GDAL's in-memory file system (/vsimem/).
#pragma once

#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

namespace uavcover::io {

struct ImportOptions {
  /// Read only this layer (a Shapefile's name, a KML folder, a GeoPackage table); default: every layer.
  std::optional<std::string> layer;
  /// An OGR attribute filter (e.g. `name = 'North field'`): the polygons of the features it matches
  /// are the area, every other polygon a no-fly zone. Default: the largest polygon is the area.
  std::optional<std::string> area_where;
  /// The source CRS ("EPSG:NNNN") of a file without one (DXF); a file's own CRS is never overridden.
  std::optional<std::string> crs;
  /// A mission object whose fields (spacing, camera, UAVs, ...) the skeleton takes; its area, corridor
  /// and no-fly zones are replaced. Null: spacing_m 30 and one UAV.
  nlohmann::json template_mission = nullptr;
};

struct ImportLimits {
  std::size_t max_features = 100'000;
  std::size_t max_vertices = 2'000'000;
};

/// The mission skeleton of `file` (.zip holding a Shapefile or one other supported file, .kmz, .kml,
/// .gpkg, .geojson/.json, .dxf, .shp): "name", "area", "no_fly_zones" (Features whose
/// properties.name is the source feature's name) and the template's or default fields; parse_mission
/// accepts it. Every polygon is reprojected to WGS84. Throws InputError naming the field: "file"
/// (unreadable, no polygon, an invalid geometry naming its layer and feature), "layer", "area_where",
/// "crs", or the mission field parse_mission refuses.
nlohmann::json import_mission(const std::filesystem::path& file, const ImportOptions& options = {},
                              const ImportLimits& limits = {});

/// The same for an uploaded file's bytes; `filename` only tells the format by its extension (it never
/// names a path: the bytes are read from a private /vsimem/ file).
nlohmann::json import_mission_bytes(std::string_view bytes, std::string_view filename,
                                    const ImportOptions& options = {}, const ImportLimits& limits = {});

}  // namespace uavcover::io
