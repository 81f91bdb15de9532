// Reading a digital elevation model (a GeoTIFF in any CRS) into the core's HeightGrid. The only code
// that links GDAL (CMake target uavcover_dem); the rest of uavcover sees the grid alone.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

#include "uavcover/mission.hpp"
#include "uavcover/terrain.hpp"

namespace uavcover::io {

struct DemLimits {
  /// Largest window of DEM pixels read (float32: 64 MB); a larger need is refused.
  std::size_t max_window_pixels = std::size_t{16} << 20;
  /// Largest grid handed to the core; above it the grid is made coarser than the DEM.
  std::size_t max_grid_nodes = std::size_t{4} << 20;
};

/// The ground heights of the GeoTIFF `file` over the WGS84 box [west, east] x [south, north]: a grid at
/// about the DEM's resolution, each node sampled bilinearly from the DEM's pixels (transformed from
/// WGS84 to the DEM's CRS with OGRCoordinateTransformation). Reads only the window of pixels the box
/// needs. Throws InputError naming terrain.dem when the file is not a GeoTIFF, has no CRS or
/// georeferencing, when the window exceeds the limits, or when a node has no height (outside the
/// raster, nodata, NaN), with the longitude/latitude extent that is missing.
HeightGrid read_dem(const std::filesystem::path& file, double west, double south, double east, double north,
                    const DemLimits& limits = {});

/// The same from a GeoTIFF held in memory (a DEM stored in the server, issue 31): `name` names it in
/// messages. Read in place, not copied.
HeightGrid read_dem_bytes(std::string_view bytes, const std::string& name, double west, double south,
                          double east, double north, const DemLimits& limits = {});

/// The same from a folder of GeoTIFF (geographic CRS) or SRTM .hgt tiles (`serve --dem-dir`, issue 31):
/// the tiles that overlap the box joined into one virtual mosaic (GDALBuildVRT), then read as one DEM.
/// Refuses naming terrain.dem when no tile covers the box, or a part of it has no height.
HeightGrid read_dem_dir(const std::filesystem::path& dir, double west, double south, double east,
                        double north, const DemLimits& limits = {});

/// What POST /api/v1/dems checks of an uploaded GeoTIFF before storing it: GDAL's GTiff driver reads it,
/// it has a band, a geotransform and a CRS that transforms to WGS84. Throws InputError naming
/// terrain.dem with the reason.
struct DemInfo {
  int width = 0, height = 0;
  double west = 0, south = 0, east = 0, north = 0;  ///< its corners' extent in WGS84
  std::string crs;                                  ///< the CRS's name
};
DemInfo inspect_dem_bytes(std::string_view bytes, const std::string& name);

/// The WGS84 box a mission needs heights over: the area, the no-fly zones and the given starts, plus a
/// margin of max(50 m, 2 line spacings).
struct TerrainBox {
  double west = 0, south = 0, east = 0, north = 0;
};
TerrainBox terrain_box(const Mission& mission);

/// Reads mission.terrain's DEM (a relative name is resolved against `base_dir`, the mission file's
/// folder) over the mission's extent: the area, the no-fly zones and the given starts, plus a margin of
/// max(50 m, 2 line spacings). Sets mission.terrain->grid; does nothing without a terrain block.
/// Refuses (terrain.dem) a block naming a stored DEM or the server's tiles: only the server has them.
void load_terrain(Mission& mission, const std::filesystem::path& base_dir, const DemLimits& limits = {});

/// The server's two sources (issue 31): a stored GeoTIFF's bytes, or the tile folder of --dem-dir.
/// Each sets mission.terrain->grid over terrain_box(); nothing without a terrain block.
void load_terrain_bytes(Mission& mission, std::string_view bytes, const std::string& name,
                        const DemLimits& limits = {});
void load_terrain_dir(Mission& mission, const std::filesystem::path& dir, const DemLimits& limits = {});

}  // namespace uavcover::io
