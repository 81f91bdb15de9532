// A mission over the synthetic hill of tests/support/dem.hpp: a 300 m x 200 m rectangle centred on the
// frame's origin, a camera at 40 m, two UAVs starting south of it, and a terrain block naming `dem`.
#pragma once

#include <fmt/format.h>

#include <unistd.h>
#include <filesystem>
#include <string>

#include "geodesy/local_frame.hpp"
#include "support/dem.hpp"
#include "support/files.hpp"
#include "uavcover/mission.hpp"

namespace uavcover::testdem {

inline const LonLat kOrigin{8.5455, 47.3977};

using TempDir = testing::TempDir;  // one fixture for every test (support/files.hpp)

inline std::string lonlat(const geodesy::LocalFrame& f, double x, double y) {
  const LonLat p = f.to_wgs84({x, y});
  return fmt::format("[{:.9f}, {:.9f}]", p.lon, p.lat);
}

/// Mission JSON text; `area_dx` shifts the area east (metres) to move it off the DEM.
inline std::string mission_text(const std::string& dem, const std::string& mode = "follow",
                                double tolerance = 1.0, double area_dx = 0.0,
                                const std::string& planner = "boustrophedon") {
  const geodesy::LocalFrame f(kOrigin);
  const double x0 = -150 + area_dx, x1 = 150 + area_dx;
  return fmt::format(
      R"({{"version": 1, "name": "hill",
  "area": {{"type": "Polygon", "coordinates": [[{}, {}, {}, {}, {}]]}},
  "camera": {{"altitude_m": 40, "hfov_deg": 60, "overlap": 0.2}},
  "uavs": [{{"id": "a", "start": {}}}, {{"id": "b", "start": {}}}],
  "planner": "{}", "seed": 7,
  "terrain": {{"dem": "{}", "mode": "{}", "tolerance_m": {}}}}})",
      lonlat(f, x0, -100), lonlat(f, x1, -100), lonlat(f, x1, 100), lonlat(f, x0, 100), lonlat(f, x0, -100),
      lonlat(f, x0 - 20, -130), lonlat(f, x1 + 20, -130), planner, dem, mode, tolerance);
}

}  // namespace uavcover::testdem
