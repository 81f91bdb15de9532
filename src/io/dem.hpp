// Reading a digital elevation model (a GeoTIFF in any CRS) into the core's HeightGrid. The only code
// that links GDAL (CMake target uavcover_dem); the rest of uavcover sees the grid alone.
#pragma once

#include <cstddef>
#include <filesystem>

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

/// Reads mission.terrain's DEM (a relative name is resolved against `base_dir`, the mission file's
/// folder) over the mission's extent: the area, the no-fly zones and the given starts, plus a margin of
/// max(50 m, 2 line spacings). Sets mission.terrain->grid; does nothing without a terrain block.
void load_terrain(Mission& mission, const std::filesystem::path& base_dir, const DemLimits& limits = {});

}  // namespace uavcover::io
