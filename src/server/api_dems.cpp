// /api/v1/dems (issue 31, docs/api.md "Elevation models"): GeoTIFFs uploaded once, checked as the CLI
// checks a DEM, stored content-addressed; missions name them with "terrain": {"dem_id": N}.
#include <fmt/format.h>

#include "io/dem.hpp"
#include "server/api_internal.hpp"
#include "server/flights.hpp"
#include "uavcover/error.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::server::detail {

namespace {

nlohmann::json dem_json(const store::StoredDem& d) {
  return {{"id", d.id},     {"name", d.name}, {"sha256", d.sha256},
          {"size", d.size}, {"info", d.info}, {"created_at", iso_time(d.created_ms)}};
}

/// A name fit for messages and lists: printable ASCII, at most 200 characters.
std::string clean_name(std::string_view raw) {
  std::string out;
  for (const char c : raw.substr(0, 200)) out += (c >= 0x20 && c < 0x7f) ? c : '_';
  return out.empty() ? "dem.tif" : out;
}

// POST /dems: multipart "file" (the GeoTIFF), optional "name"
Response upload_dem(const Request& req, const ApiContext& ctx) {
  if (req.body.size() > ctx.config.max_body_bytes)
    throw HttpError(413, "body",
                    "the body is larger than " + std::to_string(ctx.config.max_body_bytes) + " bytes");
  const std::vector<FormPart> parts = parse_multipart(req.header("content-type").value_or(""), req.body);
  const FormPart* file = nullptr;
  const FormPart* name = nullptr;
  for (const auto& p : parts) {
    if (p.name == "file")
      file = &p;
    else if (p.name == "name")
      name = &p;
    else
      throw HttpError(400, p.name.substr(0, 64), "unknown part: expected \"file\" and optionally \"name\"");
  }
  if (file == nullptr)
    throw HttpError(400, "file", "missing: the upload needs a \"file\" part (the GeoTIFF)");
  if (file->body.empty()) throw HttpError(400, "file", "the GeoTIFF is empty");
  const std::string shown = clean_name(
      name != nullptr ? std::string_view(name->body) : std::string_view(file->filename.value_or("dem.tif")));
  // the CLI's checks (GDAL's GTiff driver alone, a band, georeferencing, a CRS that reaches WGS84)
  io::DemInfo info;
  try {
    info = io::inspect_dem_bytes(file->body, shown);
  } catch (const InputError& e) {
    throw HttpError(422, "file", std::string(e.what()).substr(e.field().empty() ? 0 : e.field().size() + 2));
  }
  const nlohmann::json j{
      {"width", info.width},
      {"height", info.height},
      {"crs", info.crs},
      {"bbox",
       {{"min_lon", info.west}, {"min_lat", info.south}, {"max_lon", info.east}, {"max_lat", info.north}}}};
  const auto [id, created] = ctx.store.put_dem(shown, file->body, j);
  const auto stored = ctx.store.get_dem(id);
  if (!stored) throw store::StoreError("the DEM just stored is gone");
  Response r = Response::json(created ? 201 : 200, dem_json(*stored));
  r.headers.emplace_back("Location", std::string(kDemsRoute) + "/" + std::to_string(id));
  return r;
}

// GET /plans/{id}/profile?uav=ID: the ground under a UAV's whole flight and its flight heights (AMSL),
// with the height band above ground over its coverage (the web app's ground profile)
Response profile(const Request& req, ApiContext& ctx) {
  const store::Id id = id_param(req, "id");
  const auto job = ctx.store.get_job(id);
  if (!job || job->kind != store::JobKind::Plan)
    throw store::NotFound("plan " + std::to_string(id) + " does not exist");
  if (job->state != store::JobState::Done)
    throw HttpError(409, "state",
                    "the plan is " + store::to_string(job->state) + "; its profile exists once it is done");
  const Plan plan = load_job_plan(ctx.store, *job, ctx.config.dem_dir);
  if (!plan.mission.terrain)
    throw HttpError(404, "terrain",
                    "the plan has no terrain block: its ground is flat, heights are above take-off");
  const auto q = req.query.find("uav");
  std::size_t index = plan.uavs.size();
  for (std::size_t i = 0; i < plan.uavs.size(); ++i)
    if (q == req.query.end() ? !plan.uavs[i].parts.empty() : plan.uavs[i].id == q->second) {
      index = i;
      break;
    }
  if (index == plan.uavs.size())
    throw HttpError(404, "uav",
                    q == req.query.end() ? "no UAV of the plan flies" : "the plan has no such UAV");
  const auto p = waypoints::path_profile(plan, index, 800);
  if (!p) throw HttpError(404, "terrain", "the plan's elevation model could not be read");
  nlohmann::json s = nlohmann::json::array();
  for (const auto& x : p->samples)
    s.push_back({std::round(x.s_m * 10) / 10, std::round(x.ground_m * 100) / 100,
                 std::round(x.flight_m * 100) / 100, x.coverage});
  return Response::json(200, {{"uav", p->uav},
                              {"length_m", p->length_m},
                              {"altitude_m", p->altitude_m},
                              {"tolerance_m", p->tolerance_m},
                              {"agl_min_m", p->agl_min_m},
                              {"agl_max_m", p->agl_max_m},
                              {"columns", {"s_m", "ground_m", "flight_m", "coverage"}},
                              {"samples", s}});
}

}  // namespace

void add_dem_routes(Router& router, ApiContext& ctx) {
  router.add("GET", kApi + "/plans/{id}/profile",
             guarded([&ctx](const Request& req) { return profile(req, ctx); }));
  const std::string base(kDemsRoute);
  router.add("POST", base, guarded([&ctx](const Request& req) { return upload_dem(req, ctx); }));
  router.add(
      "GET", base, guarded([&ctx](const Request&) {
        nlohmann::json items = nlohmann::json::array();
        for (const auto& d : ctx.store.list_dems(1000)) items.push_back(dem_json(d));
        return Response::json(200, {{"items", items}, {"server_tiles", ctx.config.dem_dir.has_value()}});
      }));
  router.add("GET", base + "/{id}", guarded([&ctx](const Request& req) {
               const store::Id id = id_param(req, "id");
               const auto d = ctx.store.get_dem(id);
               if (!d) throw store::NotFound("elevation model " + std::to_string(id) + " does not exist");
               return Response::json(200, dem_json(*d));
             }));
}

}  // namespace uavcover::server::detail
