// `uavcover serve`: the CLI (src/cli/serve_cmd.cpp) fills ServeOptions; serve() (src/server/app.cpp)
// opens the store, seeds a new database, builds the API router, starts the planning workers and runs
// the HttpServer until it is stopped (SIGINT / SIGTERM).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "server/server.hpp"
#include "uavcover/mission.hpp"

namespace uavcover::server {

struct ServeOptions {
  ServerConfig http;
  std::string db_url = "sqlite:data/uavcover.db";
  int workers = 0;  ///< planning threads; 0: the number of cores
  std::optional<std::filesystem::path> seed_dir;
  int max_queued = 100;
  int lease_ms = 10000;  ///< job lease (tests shorten it)
  int keep_plans = 0;    ///< retention: each mission's newest N done plans are kept (0: all)
  std::int64_t export_cache_bytes = std::int64_t{128} << 20;  ///< the export cache's size cap
  int export_threads = 2;                                     ///< the pool that makes exports
  /// `--tiles FILE.mbtiles`: raster map tiles served at /tiles/{z}/{x}/{y} (docs/offline-maps.md)
  std::optional<std::filesystem::path> tiles;
  /// `--max-cells`: missions whose grid needs more cells are refused (ParseOptions::max_cells)
  std::size_t max_cells = ParseOptions{}.max_cells;
  /// `--dem-dir DIR`: GeoTIFF or SRTM .hgt tiles for "terrain": {"source": "server"} (issue 31)
  std::optional<std::filesystem::path> dem_dir;
};

/// Blocks until the server is stopped. Throws InputError / OperationError.
void serve(const ServeOptions& options);

}  // namespace uavcover::server
