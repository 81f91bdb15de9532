// The REST API of docs/api.md under /api/v1, as Router handlers over the store and the job use
// cases: missions with revisions, plan/study/comparison jobs and their artifacts, the UAV and camera
// catalogs, the planners and the OpenAPI document. Independent of the transport (Boost.Beast).
#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "json/iso_time.hpp"
#include "server/http.hpp"
#include "server/terrain_source.hpp"
#include "store/store.hpp"
#include "uavcover/mission.hpp"

namespace uavcover::server {

struct ApiConfig {
  int max_queued = 100;                                ///< jobs queued at most (503 beyond)
  std::size_t max_body_bytes = std::size_t{10} << 20;  ///< 413 beyond (the transport checks too)
  /// The server's planning threads (--workers): a plan may ask for at most this many threads of its
  /// own (smt's planner_params.threads; 422 beyond), so one job cannot start a hundred threads.
  int planner_threads = 64;
  /// Missions whose grid needs more cells than ParseOptions::max_cells are refused (422 naming the field;
  /// `serve --max-cells`): every route that parses a mission uses these options.
  ParseOptions parse = {};
  /// `serve --dem-dir`: GeoTIFF or SRTM .hgt tiles for missions with "terrain": {"source": "server"}.
  DemDir dem_dir = {};
};

class FlightManager;
class ExportService;
}  // namespace uavcover::server
namespace uavcover::io {
class MbTiles;
}  // namespace uavcover::io
namespace uavcover::server {

struct ApiContext {
  store::Store& store;
  ApiConfig config;
  FlightManager* flights;  ///< the live flights (src/server/flights.hpp); null: the flight routes answer 503
  /// Exports made on demand (src/server/exports.hpp); null: the export routes answer 503.
  ExportService* exports = nullptr;
  /// The map tiles of `uavcover serve --tiles FILE.mbtiles` (src/io/mbtiles.hpp); null: /tiles/metadata.json
  /// says none are available and /tiles/{z}/{x}/{y} answers 404.
  const io::MbTiles* tiles = nullptr;
};

/// Registers every /api/v1 route of docs/api.md and the /tiles routes on `router`. Handlers answer every
/// error as the JSON error body themselves (HttpError, store errors, InputError); `ctx` must outlive the
/// router.
void add_api_routes(Router& router, ApiContext& ctx);

/// A submitted mission document made ready to store: catalog references resolved through the store's
/// catalogs, parsed and normalised by the CLI's parser (InputError naming the field), its area's
/// bounding box; `source` is the document as given.
/// A terrain block must name a stored DEM (dem_id) or the server's tiles (`dem_dir`; terrain_source.hpp).
store::NewRevision prepare_mission(const nlohmann::json& document, store::Store& store,
                                   const ParseOptions& options = {}, const DemDir& dem_dir = {});
/// The same document resolved and parsed only (POST /missions/validate).
uavcover::Mission resolve_mission(const nlohmann::json& document, store::Store& store,
                                  const ParseOptions& options = {}, const DemDir& dem_dir = {});

/// "2026-11-26T01:02:03.456Z" from Unix milliseconds (json/iso_time.hpp).
using uavcover::iso_time;

/// The Job JSON of docs/api.md; with `with_artifacts` false the "artifacts" member is left out (events).
nlohmann::json job_json(const store::Job& job, bool with_artifacts = true);

/// The API path prefix of a job kind: "plans", "studies" or "comparisons".
std::string job_collection(store::JobKind kind);

/// The embedded OpenAPI 3 document (src/server/openapi.json).
const std::string& openapi_document();

}  // namespace uavcover::server
