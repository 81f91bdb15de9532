#include "server/api.hpp"

#include <spdlog/spdlog.h>

#include <chrono>

#include "export/formats.hpp"
#include "json/strict.hpp"
#include "server/api_internal.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/plan_outputs.hpp"

namespace uavcover::server {

namespace detail {

Handler guarded(Handler handler) {
  return [handler = std::move(handler)](const Request& req) -> Response {
    try {
      return handler(req);
    } catch (const HttpError& e) {
      Response r = Response::error(e.status, e.field, e.what());
      r.headers.insert(r.headers.end(), e.headers.begin(), e.headers.end());
      return r;
    } catch (const InputError& e) {
      return Response::error(422, e.field(), e.what());
    } catch (const store::NotFound& e) {
      return Response::error(404, "id", e.what());
    } catch (const store::Conflict& e) {
      return Response::error(409, "", e.what());
    } catch (const store::QueueFull&) {
      Response r = Response::error(503, "", "the job queue is full; try again later");
      r.headers.emplace_back("Retry-After", "5");
      return r;
    } catch (const store::StoreError& e) {
      spdlog::error("request {} {} {}: database error: {}", req.request_id, req.method, req.path, e.what());
      Response r = Response::error(503, "", "the database is unavailable; try again later");
      r.headers.emplace_back("Retry-After", "5");
      return r;
    } catch (const std::exception& e) {
      spdlog::error("request {} {} {}: internal error: {}", req.request_id, req.method, req.path, e.what());
      return Response::error(500, "", "internal error");
    } catch (...) {
      spdlog::error("request {} {} {}: unknown exception", req.request_id, req.method, req.path);
      return Response::error(500, "", "internal error");
    }
  };
}

nlohmann::json parse_body(const Request& req, const ApiContext& ctx, bool allow_empty) {
  // A body must say it is JSON: a browser sends a text/plain or a Blob body (no Content-Type) across
  // origins without a preflight, so a body read as JSON without one lets any page drive the server.
  const auto type = req.header("content-type");
  const std::string media = type ? media_type(*type) : std::string();
  if (!req.body.empty() && media != "application/json")
    throw HttpError(415, "body",
                    type ? "expected Content-Type application/json, got \"" + type->substr(0, 100) + "\""
                         : "a request body needs Content-Type: application/json");
  if (type && media != "application/json" && !(media.empty() && req.body.empty()))
    throw HttpError(415, "body",
                    "expected Content-Type application/json, got \"" + type->substr(0, 100) + "\"");
  if (req.body.size() > ctx.config.max_body_bytes)
    throw HttpError(413, "body",
                    "the body is larger than " + std::to_string(ctx.config.max_body_bytes) + " bytes");
  if (req.body.find_first_not_of(" \t\r\n") == std::string::npos) {
    if (allow_empty) return nullptr;
    throw HttpError(400, "body", "expected a JSON document, got an empty body");
  }
  try {
    return strict::parse_json(req.body, "body");
  } catch (const InputError& e) {
    throw HttpError(400, e.field().empty() ? "body" : e.field(), e.what());
  }
}

Response no_content() {
  Response r;
  r.status = 204;
  r.content_type.clear();
  return r;
}

std::int64_t id_param(const Request& req, const std::string& name, const std::string& field) {
  const auto it = req.params.find(name);
  return parse_id(it == req.params.end() ? std::string() : it->second, field);
}

}  // namespace detail

void add_api_routes(Router& router, ApiContext& ctx) {
  using detail::guarded;
  detail::add_mission_routes(router, ctx);
  detail::add_job_routes(router, ctx);
  detail::add_catalog_routes(router, ctx);
  detail::add_dem_routes(router, ctx);
  detail::add_flight_routes(router, ctx);
  detail::add_tile_routes(router, ctx);
  router.add("GET", detail::kApi + "/planners", guarded([](const Request&) {
               nlohmann::json items = nlohmann::json::array();
               for (const auto& p : available_planners())
                 items.push_back({{"name", p.name}, {"summary", p.summary}, {"schema", p.schema}});
               return Response::json(200, {{"items", items}});
             }));
  // the export format table (export/formats.hpp) and the server's export routes made from it
  router.add("GET", detail::kApi + "/formats", guarded([](const Request&) {
               return Response::json(
                   200, {{"items", exporting::formats_json()}, {"routes", usecases::export_routes_json()}});
             }));
  router.add("GET", detail::kApi + "/openapi.json", guarded([](const Request&) {
               Response r;
               r.body = openapi_document();
               return r;
             }));
}

}  // namespace uavcover::server
