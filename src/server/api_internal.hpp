// Shared pieces of the API handlers (api*.cpp): error mapping, body parsing, small responses.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "server/api.hpp"

namespace uavcover::server::detail {

inline const std::string kApi = "/api/v1";

/// Wraps a handler so every error becomes its JSON answer: HttpError (its status and headers),
/// InputError 422, store::NotFound 404, Conflict 409, QueueFull and StoreError 503 with Retry-After,
/// anything else 500 "internal error" (logged, never shown).
Handler guarded(Handler handler);

/// The request body as JSON: a non-empty body needs Content-Type application/json (415, field
/// "content-type"; an empty one may come without), at most
/// max_body_bytes (413), strict syntax (400, field "body" or the duplicate key's path). An empty body
/// gives null when `allow_empty`, 400 otherwise.
nlohmann::json parse_body(const Request& req, const ApiContext& ctx, bool allow_empty);

/// 204 without a body.
Response no_content();

/// The path parameter `name` as a positive id (400 naming `field`).
std::int64_t id_param(const Request& req, const std::string& name, const std::string& field = "id");

/// At most this many bytes in the X-Export-Warnings header: a proxy's response header buffer (nginx's
/// proxy_buffer_size) is 4 to 8 KiB, and Boost.Beast refuses a field of 64 KiB or more.
inline constexpr std::size_t kWarningsHeaderLimit = 4096;

/// The X-Export-Warnings value of an export for UAV `uav` ("" for a plan-wide file): an ASCII JSON array
/// of the exporter's warnings, without those of other UAVs (the ones that start "uav '<other>':"), in
/// order, as many as fit kWarningsHeaderLimit bytes; when some are left off, the last entry says how many.
/// Empty when there is no warning to give.
std::string export_warnings_header(const std::vector<std::string>& warnings, const std::string& uav);

void add_mission_routes(Router& router, ApiContext& ctx);
void add_job_routes(Router& router, ApiContext& ctx);
/// Queues a job of the mission's revision with validated params: 202 with the Job JSON and its Location;
/// 503 with Retry-After when the queue is full.
Response enqueue_job(ApiContext& ctx, store::JobKind kind, store::Id mission_id, int revision,
                     const nlohmann::json& params);
void add_catalog_routes(Router& router, ApiContext& ctx);
/// /dems (issue 31): upload, list and describe elevation models (api_dems.cpp).
void add_dem_routes(Router& router, ApiContext& ctx);
void add_flight_routes(Router& router, ApiContext& ctx);
/// GET /tiles/metadata.json and /tiles/{z}/{x}/{y} (docs/offline-maps.md), from ctx.tiles.
void add_tile_routes(Router& router, ApiContext& ctx);

}  // namespace uavcover::server::detail
