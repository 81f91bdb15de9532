// Terrain: the ground heights of a digital elevation model (DEM) over the mission's extent, as a plain
// value the core samples (docs/photogrammetry.md, "Terrain following"). Only src/io/dem.cpp reads DEM
// files (with GDAL); everything else sees this grid.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "uavcover/geometry.hpp"

namespace uavcover {

/// Ground heights (metres above mean sea level, the DEM's vertical datum) on a regular WGS84 grid:
/// node (c, r) lies at longitude lon0 + c * dlon, latitude lat0 + r * dlat. Sampled bilinearly.
struct HeightGrid {
  double lon0 = 0.0, lat0 = 0.0;  ///< south-west node
  double dlon = 0.0, dlat = 0.0;  ///< node spacing in degrees (> 0)
  int cols = 0, rows = 0;         ///< >= 2 each
  std::vector<float> heights;     ///< row-major from the south row, cols * rows finite values
  double step_m = 0.0;            ///< node spacing in metres (the smaller of the two directions)
  double max_m = 0.0;             ///< the highest node
  std::string source;             ///< what was read (file and window), for messages and plan.json

  /// Bilinear ground height at p; positions outside the grid take the nearest edge's height.
  [[nodiscard]] double at(LonLat p) const;
  [[nodiscard]] bool contains(LonLat p) const;
};

/// The mission's `terrain` block (docs/mission-format.md).
struct Terrain {
  std::string dem;              ///< the GeoTIFF, as given (the CLI resolves it against the mission's folder)
  long long dem_id = 0;         ///< the server: a DEM stored with POST /api/v1/dems (issue 31); 0: none
  std::string source;           ///< "server": the tiles of `serve --dem-dir` (issue 31); empty: dem or dem_id
  std::string mode = "follow";  ///< "follow": constant height above ground; "off": heights as without a DEM
  double tolerance_m = 1.0;     ///< follow: largest deviation of the flown height above ground along a leg
  /// Climb and descent limits while following (issue 31): vertical speeds in m/s, or a grade (metres of
  /// height per metre flown); empty: none. Where the ground is steeper the UAV slows down on that leg.
  std::optional<double> max_climb_mps;
  std::optional<double> max_descent_mps;
  std::optional<double> max_grade;
  /// Filled by io::load_terrain() (src/io/dem.hpp); missing until the DEM is read. Not serialised.
  std::shared_ptr<const HeightGrid> grid;

  [[nodiscard]] bool follow() const { return mode == "follow"; }
};

}  // namespace uavcover
