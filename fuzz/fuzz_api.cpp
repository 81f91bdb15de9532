// libFuzzer target: the REST API layer (ids, query parameters, catalog bodies, job parameters,
// revisions, paging) over a real SQLite store in memory, dispatched through the Router as the
// transport does. Every answer must be a JSON body (an artifact's own media type, or none for 204),
// never a 500 (an unhandled exception) nor a 503 other than "the job queue is full" (the in-memory
// database does not fail), and every error must be {"error": {"field": string, "message": string}}.
//
// Input: byte 0 picks the method and the Content-Type; then the request target up to the first '\n'
// ("/api/v1/missions?name=x&limit=3"; "/api/v1/" is prepended when it does not start with '/'), decoded
// by the transport's decode_target(); the rest is the body.
// The store holds the seeded catalogs, mission 1 (two UAVs, alpha and bravo), a done plan (job 1) with
// the plan a real plan job of it stores (planned once per process with the facade and
// usecases::plan_outputs), a done study (job 2), and an export service: GET /plans/1/exports/{format} makes
// the exports of the stored plan on request, as the server does. Requests change it (missions are created,
// jobs queued), so it is opened afresh every kRunsPerStore inputs: memory stays bounded and ids stay small.
#include <spdlog/spdlog.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "server/api.hpp"
#include "server/exports.hpp"
#include "server/flights.hpp"
#include "server/http.hpp"
#include "store/store.hpp"
#include "uavcover/mission.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/jobs.hpp"
#include "usecases/plan_outputs.hpp"

namespace {

using uavcover::server::Request;
using uavcover::server::Response;
namespace store = uavcover::store;

constexpr int kRunsPerStore = 500;
constexpr int kMaxQueued = 4;

const char* const kMission = R"({
  "name": "North olive grove",
  "area": {"type": "Polygon", "coordinates": [[[22.9000, 40.6000], [22.9120, 40.6000], [22.9145, 40.6040],
    [22.9110, 40.6085], [22.9030, 40.6080], [22.8990, 40.6040], [22.9000, 40.6000]]]},
  "no_fly_zones": [{"type": "Polygon", "coordinates": [[[22.9050, 40.6030], [22.9065, 40.6030],
    [22.9065, 40.6042], [22.9050, 40.6042], [22.9050, 40.6030]]]}],
  "camera": {"altitude_m": 50, "hfov_deg": 73.4, "overlap": 0.5},
  "uavs": [
    {"id": "alpha", "start": [22.8995, 40.6005], "share": 0.5, "speed_mps": 5, "max_accel_mps2": 2, "endurance_min": 25},
    {"id": "bravo", "start": [22.9125, 40.6002], "share": 0.5, "speed_mps": 6, "max_accel_mps2": 2.5, "endurance_min": 30}
  ],
  "planner": "darp",
  "seed": 42
})";

[[noreturn]] void fail(const Request& req, const Response& res, const char* what) {
  std::fprintf(stderr, "invariant broken: %s\n%s %s -> %d %s\n%.2000s\n", what, req.method.c_str(),
               req.path.c_str(), res.status, res.content_type.c_str(), res.body.c_str());
  std::abort();
}

/// Runs a job to completion in the store the way a worker would, with the given result and artifacts.
void finish(store::Store& s, store::JobKind kind, const nlohmann::json& params, const nlohmann::json& result,
            const uavcover::Artifacts& artifacts) {
  store::NewJob job;
  job.kind = kind;
  job.mission_id = 1;
  job.revision = 1;
  job.params = params;
  const store::Id id = s.enqueue(job, 100);
  const auto claimed = s.claim_job("fuzz", std::chrono::minutes(10), 3);
  if (!claimed || claimed->id != id ||
      !s.finish_job(id, "fuzz", store::JobState::Done, result, nullptr, artifacts))
    std::abort();
}

/// The plan job of the mission, planned once per process: the stored plan (plan.json, paths.geojson)
/// that a worker's plan job stores and the exports are made from, with the job's result fields the API
/// reads. No pictures (Cairo's font cache is never freed, which LeakSanitizer reports).
const uavcover::usecases::JobResult& planned() {
  static const uavcover::usecases::JobResult result = [] {
    const uavcover::Plan p = uavcover::plan(uavcover::parse_mission(kMission));
    uavcover::usecases::OutputOptions oo;
    oo.images = false;
    uavcover::usecases::JobResult r;
    r.artifacts = uavcover::usecases::plan_outputs(p, oo).artifacts;
    nlohmann::json uavs = nlohmann::json::array();
    for (const auto& u : p.uavs) uavs.push_back({{"id", u.id}});
    r.result = {{"planner", p.planner},
                {"complete", p.complete},
                {"uavs", std::move(uavs)},
                {"metrics", {{"coverage", 1.0}}},
                {"warnings", p.warnings}};
    return r;
  }();
  return result;
}

struct World {
  std::unique_ptr<store::Store> store;
  std::unique_ptr<uavcover::server::FlightManager> flights;
  std::unique_ptr<uavcover::server::ExportService> exports;
  std::unique_ptr<uavcover::server::ApiContext> ctx;
  std::unique_ptr<uavcover::server::Router> router;

  World() {
    store = store::open_store("sqlite::memory:");
    // flights are looked up, never started: no live flight (max_live 0), so no socket is opened
    uavcover::server::FlightLimits limits;
    limits.max_live = 0;
    flights = std::make_unique<uavcover::server::FlightManager>(*store, limits);
    uavcover::server::ExportConfig export_config;
    export_config.threads = 1;
    exports = std::make_unique<uavcover::server::ExportService>(*store, export_config);
    ctx = std::make_unique<uavcover::server::ApiContext>(
        uavcover::server::ApiContext{*store, uavcover::server::ApiConfig{}, flights.get(), exports.get()});
    ctx->config.max_queued = kMaxQueued;
    ctx->config.max_body_bytes = 64 * 1024;
    router = std::make_unique<uavcover::server::Router>();
    uavcover::server::add_api_routes(*router, *ctx);
    const auto doc = nlohmann::json::parse(kMission);
    if (store->create_mission(uavcover::server::prepare_mission(doc, *store)) != 1) std::abort();
    const auto& plan = planned();
    finish(*store, store::JobKind::Plan, {{"planner", "darp"}, {"seed", 42}}, plan.result, plan.artifacts);
    finish(*store, store::JobKind::Study, {{"uavs", "1..2"}}, {{"metrics", {}}},
           {{"study.json", "application/json", "{}"}});
  }
};

void check(const Request& req, const Response& res) {
  if (res.status == 500) fail(req, res, "500: an unhandled exception");
  if (res.status < 200 || res.status > 599) fail(req, res, "status out of range");
  if (res.status == 503 && res.body.find("queue is full") == std::string::npos)
    fail(req, res, "503 other than a full queue: the in-memory store failed");
  if (res.status == 204) {
    if (!res.body.empty()) fail(req, res, "204 with a body");
    return;
  }
  if (res.content_type != "application/json") {
    // an artifact's bytes, with its stored media type
    if (res.status != 200 || res.content_type.empty())
      fail(req, res, "a non-JSON answer that is not an artifact");
    return;
  }
  const auto body = nlohmann::json::parse(res.body, nullptr, false);
  if (body.is_discarded()) fail(req, res, "the body is not JSON");
  if (res.status >= 400) {
    const auto error = body.is_object() ? body.find("error") : body.end();
    if (error == body.end() || !error->is_object() || !error->contains("field") ||
        !error->contains("message") || !(*error)["field"].is_string() || !(*error)["message"].is_string() ||
        (*error)["message"].get<std::string>().empty())
      fail(req, res, "an error body other than {\"error\": {\"field\": string, \"message\": string}}");
  }
  for (const auto& [name, value] : res.headers)
    if (value.find_first_of(std::string_view("\r\n\0", 3)) != std::string::npos)
      fail(req, res, "a header value with CR, LF or NUL");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // FUZZ_API_VERBOSE: the server's own log too (what an unhandled exception was)
  spdlog::set_level(std::getenv("FUZZ_API_VERBOSE") != nullptr ? spdlog::level::info : spdlog::level::off);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static std::unique_ptr<World> world;
  static int runs = 0;
  if (!world || ++runs % kRunsPerStore == 0) {
    world.reset();
    world = std::make_unique<World>();
  }
  if (size == 0) return 0;
  static const std::array<const char*, 5> kMethods{"GET", "POST", "PUT", "DELETE", "PATCH"};
  static const std::array<const char*, 5> kTypes{"", "application/json", "Application/JSON; charset=utf-8",
                                                 "text/plain", "multipart/form-data; boundary=b"};
  Request req;
  req.method = kMethods[data[0] % kMethods.size()];
  if (const char* type = kTypes[(data[0] / kMethods.size()) % kTypes.size()]; *type)
    req.headers["content-type"] = type;
  req.request_id = "fuzz";
  const std::string_view rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  const auto newline = rest.find('\n');
  std::string target(rest.substr(0, newline));
  if (newline != std::string_view::npos) req.body = std::string(rest.substr(newline + 1));
  if (!target.starts_with('/')) target.insert(0, "/api/v1/");
  try {
    uavcover::server::decode_target(target, req);  // the transport's own decoding
  } catch (const uavcover::server::HttpError&) {
    return 0;  // 400, answered by the transport
  }

  auto match = world->router->match(req.method, req.path);
  if (match.handler == nullptr) return 0;  // 404 or 405, answered by the transport
  req.params = std::move(match.params);
  const Response res = (*match.handler)(req);
  static const bool verbose = std::getenv("FUZZ_API_VERBOSE") != nullptr;  // corpus upkeep
  if (verbose)
    std::fprintf(stderr, "%s %s -> %d %.200s\n", req.method.c_str(), req.path.c_str(), res.status,
                 res.body.c_str());
  check(req, res);
  return 0;
}
