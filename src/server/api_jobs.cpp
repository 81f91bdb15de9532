// Jobs: POST /missions/{id}/{plans,studies,comparisons}, GET/DELETE /{plans,studies,comparisons}/{id}
// and the artifacts of finished jobs.
#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "server/api_internal.hpp"
#include "server/exports.hpp"
#include "server/worker.hpp"
#include "uavcover/error.hpp"
#include "uavcover/mission.hpp"
#include "uavcover/vehicle.hpp"
#include "usecases/jobs.hpp"
#include "usecases/plan_outputs.hpp"

namespace uavcover::server {

std::string job_collection(store::JobKind kind) {
  switch (kind) {
    case store::JobKind::Plan:
      return "plans";
    case store::JobKind::Study:
      return "studies";
    case store::JobKind::Comparison:
      return "comparisons";
  }
  return "plans";
}

namespace detail {

std::string export_warnings_header(const std::vector<std::string>& warnings, const std::string& uav) {
  auto ascii = [](const nlohmann::json& j) { return j.dump(-1, ' ', true); };
  std::vector<std::string> mine;
  for (const auto& w : warnings) {
    // "uav '<id>': ..." is one UAV's; a request for another UAV's file leaves it out
    if (!uav.empty() && w.starts_with("uav '") && !w.starts_with("uav '" + uav + "':")) continue;
    mine.push_back(w);
  }
  if (mine.empty()) return {};
  std::string all = ascii(mine);
  if (all.size() <= kWarningsHeaderLimit) return all;
  auto note = [&](std::size_t left) {
    return fmt::format("{} more warnings left off (uavcover export prints them all)", left);
  };
  // the first warnings that fit with the note after them
  nlohmann::json kept = nlohmann::json::array();
  std::size_t used = 2 + ascii(note(mine.size())).size();  // "[" "]" and the note
  std::size_t k = 0;
  for (; k < mine.size(); ++k) {
    const std::size_t add = ascii(mine[k]).size() + 1;  // and a comma
    if (used + add > kWarningsHeaderLimit) break;
    used += add;
    kept.push_back(mine[k]);
  }
  kept.push_back(note(mine.size() - k));
  return ascii(kept);
}

namespace {

const std::array<std::string, 5> kImages{"plan.png", "plan.svg", "heatmap.png", "heatmap-overlay.png",
                                         "histogram.png"};
const std::array<std::string, 3> kPlanFiles{"plan.json", "paths.geojson", "evaluation.json"};
const std::array<std::string, 2> kStudyFiles{"study.json", "study.png"};
const std::array<std::string, 3> kCompareFiles{"compare.json", "compare.md", "compare.png"};

template <std::size_t N>
bool contains(const std::array<std::string, N>& list, const std::string& s) {
  return std::find(list.begin(), list.end(), s) != list.end();
}

std::vector<std::string> artifact_names(const store::Job& job) {
  std::vector<std::string> names;
  names.reserve(job.artifacts.size());
  for (const auto& a : job.artifacts) names.push_back(a.name);
  return names;
}

/// The UAV ids of a plan result ("uavs": [{"id": ...}]).
std::vector<std::string> result_uavs(const store::Job& job) {
  std::vector<std::string> ids;
  const auto it = job.result.find("uavs");
  if (it == job.result.end() || !it->is_array()) return ids;
  for (const auto& u : *it)
    if (u.is_object() && u.contains("id") && u["id"].is_string()) ids.push_back(u["id"].get<std::string>());
  return ids;
}

/// The URL serving an artifact of a job, or null when no route serves it.
nlohmann::json artifact_url(const store::Job& job, const std::string& name,
                            const std::vector<std::string>& names, const std::vector<std::string>& uavs) {
  const std::string base = kApi + "/" + job_collection(job.kind) + "/" + std::to_string(job.id);
  switch (job.kind) {
    case store::JobKind::Plan:
      if (contains(kPlanFiles, name)) return base + "/" + name;
      if (contains(kImages, name)) return base + "/images/" + name;
      for (const auto& route : usecases::export_routes()) {
        const std::string& format = route.name;
        if (usecases::export_artifact_name(names, format, "") == name) return base + "/exports/" + format;
        for (const auto& uav : uavs)
          if (usecases::export_artifact_name(names, format, uav) == name)
            return base + "/exports/" + format + "?uav=" + uav;
      }
      return nullptr;
    case store::JobKind::Study:
      if (contains(kStudyFiles, name)) return base + "/" + name;
      return nullptr;
    case store::JobKind::Comparison:
      if (contains(kCompareFiles, name)) return base + "/" + name;
      return nullptr;
  }
  return nullptr;
}

/// The job of the collection's kind (404 for an unknown id or one of another kind).
store::Job get_job_or_404(ApiContext& ctx, store::Id id, store::JobKind kind) {
  auto job = ctx.store.get_job(id);
  if (!job || job->kind != kind)
    throw HttpError(404, "id", "no " + store::to_string(kind) + " job " + std::to_string(id));
  return *std::move(job);
}

Response file_response(Artifact&& artifact, const std::string& name, bool attachment);

/// A finished job's artifact (409 while the job is not done, 404 when it has no such artifact).
Response artifact_response(ApiContext& ctx, const store::Job& job, const std::string& name, bool attachment) {
  if (job.state != store::JobState::Done)
    throw HttpError(409, "state",
                    "the job is " + store::to_string(job.state) + "; its artifacts exist once it is done");
  auto artifact = ctx.store.get_artifact(job.id, name);
  if (!artifact) throw HttpError(404, "artifact", "the job has no artifact " + name);
  return file_response(std::move(*artifact), name, attachment);
}

Response file_response(Artifact&& artifact_in, const std::string& name, bool attachment) {
  auto artifact = std::optional<Artifact>(std::move(artifact_in));
  Response r;
  r.content_type = artifact->media_type.empty() ? "application/octet-stream" : artifact->media_type;
  r.body = std::move(artifact->bytes);
  if (attachment) {
    // "export/alpha.plan" -> alpha.plan, "trajectory/alpha.csv" -> trajectory_alpha.csv
    std::string file = name.starts_with("export/") ? name.substr(7) : name;
    for (auto& c : file)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-') c = '_';
    if (file.empty() || file.front() == '.') file.insert(0, "_");
    r.headers.emplace_back("Content-Disposition", "attachment; filename=\"" + file + "\"");
  }
  return r;
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
  return out;
}

/// A yes/no query option: absent or "false"/"0" is false, "true"/"1" true; anything else is a 400 naming it.
bool flag_param(const Request& req, const std::string& name) {
  const auto it = req.query.find(name);
  if (it == req.query.end() || it->second == "false" || it->second == "0") return false;
  if (it->second == "true" || it->second == "1") return true;
  throw HttpError(400, name, "expected true or false, got \"" + it->second.substr(0, 40) + "\"");
}

/// A number query option in [lo, hi] (`hi_open`: below hi), written plainly; absent: none; anything else
/// is a 400 naming it.
std::optional<double> number_param(const Request& req, const std::string& name, double lo, double hi,
                                   bool hi_open = false) {
  const auto it = req.query.find(name);
  if (it == req.query.end()) return std::nullopt;
  const std::string& text = it->second;
  double v = 0;
  const char* end = text.data() + text.size();
  const auto [p, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || p != end || !std::isfinite(v) || v < lo || v > hi ||
      (hi_open && v == hi))
    throw HttpError(400, name,
                    fmt::format("expected a number in [{}, {}{}, got \"{}\"", lo, hi, hi_open ? ")" : "]",
                                text.substr(0, 40)));
  return v;
}

/// The client's export options of GET /plans/{id}/exports/{format} (issue 31): ?autopilot=px4|ardupilot|
/// dji|litchi, ?terrain_frame=true (ArduPilot's terrain frame), ?split_capacity=true (the UAV's missions
/// cut to the profile's item capacity, served as one zip).
usecases::ExportVariant export_variant(const Request& req) {
  usecases::ExportVariant v;
  if (const auto it = req.query.find("autopilot"); it != req.query.end()) {
    if (vehicle_profile(it->second) == nullptr)
      throw HttpError(400, "autopilot",
                      "unknown autopilot \"" + it->second.substr(0, 40) + "\"; expected one of " +
                          vehicle_profile_names());
    v.autopilot = it->second;
  }
  v.terrain_frame = flag_param(req, "terrain_frame");
  v.split_capacity = flag_param(req, "split_capacity");
  // the trajectory method (issue 33): the CLI's --trajectory-method, --order, --v-mean, --v-min, --a-min
  if (const auto it = req.query.find("method"); it != req.query.end()) {
    try {
      v.trajectory.method = trajectory::parse_method(it->second);
    } catch (const InputError& e) {
      throw HttpError(400, "method", std::string(e.what()).substr(8));
    }
  }
  if (const auto order = number_param(req, "order", 3, 7)) {
    if (*order != 3 && *order != 5 && *order != 7)
      throw HttpError(400, "order",
                      "expected 3, 5 or 7, got \"" + req.query.at("order").substr(0, 40) + "\"");
    v.trajectory.order = static_cast<int>(*order);
  }
  if (const auto x = number_param(req, "v_mean", 0, 1000)) v.trajectory.v_mean = *x;
  if (const auto x = number_param(req, "v_min", -1000, 0, true)) v.trajectory.v_min = *x;
  if (const auto x = number_param(req, "a_min", -1000, 0, true)) v.trajectory.a_min = *x;
  return v;
}

Response export_response(ApiContext& ctx, const Request& req) {
  const store::Job job = get_job_or_404(ctx, id_param(req, "id"), store::JobKind::Plan);
  const std::string format = req.params.at("format");
  if (usecases::find_export_route(format) == nullptr)
    throw HttpError(404, "format",
                    "unknown export format \"" + format.substr(0, 40) + "\"; expected one of " +
                        usecases::export_route_list());
  if (job.state != store::JobState::Done)
    throw HttpError(409, "state",
                    "the job is " + store::to_string(job.state) + "; its artifacts exist once it is done");
  const auto uav_it = req.query.find("uav");
  const std::string uav = uav_it == req.query.end() ? std::string() : uav_it->second;
  // made from the stored plan on first request, then cached (docs/cache.md)
  if (ctx.exports == nullptr) throw HttpError(501, "format", "this server makes no exports");
  const std::string source = usecases::export_source_format(format);
  const usecases::ExportVariant variant = export_variant(req);
  const auto entry = ctx.exports->get(job, source, variant);
  // a plan job stored before exports were made on request has no plan to make them from
  if (!entry)
    throw HttpError(
        404, "artifact",
        "plan " + std::to_string(job.id) + " has no stored plan.json and paths.geojson to export");
  if (!entry->refused.empty()) {
    // a refusal of the client's own option names it: 422 (else the plan has no such export)
    const std::string& f = entry->refused_field;
    const bool trajectory_option = (f == "order" || f == "v_mean" || f == "v_min" || f == "a_min") &&
                                   variant.trajectory.method != trajectory::Method::FilletLines;
    if ((f == "autopilot" && !variant.autopilot.empty()) || (f == "terrain_frame" && variant.terrain_frame) ||
        trajectory_option)
      throw HttpError(422, f, entry->refused);
    throw HttpError(404, "format", "the plan has no " + format + " export: " + entry->refused);
  }
  const auto& names = entry->names;
  if (const auto name = usecases::export_artifact_name(names, format, uav)) {
    auto file = ctx.exports->read(*entry, job, source, *name, variant);
    if (!file) throw HttpError(404, "artifact", "the job has no artifact " + *name);
    Response r = file_response(std::move(*file), *name, true);
    // the exporter's warnings (clamped speeds, skipped UAVs, separation hazards), ASCII JSON
    if (std::string w = export_warnings_header(entry->warnings, uav); !w.empty())
      r.headers.emplace_back("X-Export-Warnings", std::move(w));
    return r;
  }
  std::vector<std::string> flying;
  for (const auto& id : result_uavs(job))
    if (usecases::export_artifact_name(names, format, id)) flying.push_back(id);
  if (flying.empty()) throw HttpError(404, "format", "the plan has no " + format + " export");
  if (uav.empty())
    throw HttpError(422, "uav", "the plan has several flying UAVs; give one of: " + join(flying));
  throw HttpError(404, "uav",
                  "no " + format + " export for UAV \"" + uav.substr(0, 100) +
                      "\"; the plan's flying UAVs: " + join(flying));
}

/// `limit` of a job listing: an integer in [1, 100], 20 when absent.
int list_limit(const Request& req) {
  const auto it = req.query.find("limit");
  if (it == req.query.end()) return 20;
  const std::string& text = it->second;
  int v = 0;
  const char* end = text.data() + text.size();
  const auto [p, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || p != end || v < 1 || v > 100)
    throw HttpError(400, "limit", "expected an integer in [1, 100], got \"" + text.substr(0, 40) + "\"");
  return v;
}

/// A job in a mission's listing: what picking one needs, without the result's details.
nlohmann::json job_summary_json(const store::Job& job) {
  const nlohmann::json full = job_json(job, false);
  nlohmann::json planner = nullptr;
  if (const auto it = job.params.find("planner"); it != job.params.end() && it->is_string()) planner = *it;
  return {{"id", job.id},
          {"kind", full["kind"]},
          {"mission_id", job.mission_id},
          {"revision", job.revision},
          {"state", full["state"]},
          {"planner", planner},
          {"params", job.params},
          {"created", full["created"]},
          {"finished", full["finished"]},
          {"metrics", full["metrics"]},
          {"warnings", full["warnings"]},
          {"error", job.error}};
}

}  // namespace
}  // namespace detail

nlohmann::json job_json(const store::Job& job, bool with_artifacts) {
  auto nullable_time = [](std::int64_t ms) -> nlohmann::json {
    if (ms > 0) return iso_time(ms);
    return nullptr;
  };
  nlohmann::json result = job.result.is_object() ? job.result : nlohmann::json::object();
  nlohmann::json warnings = nlohmann::json::array();
  nlohmann::json metrics = nlohmann::json::object();
  if (auto it = result.find("warnings"); it != result.end()) {
    if (it->is_array()) warnings = *it;
    result.erase(it);
  }
  if (auto it = result.find("metrics"); it != result.end()) {
    if (it->is_object()) metrics = *it;
    result.erase(it);
  }
  nlohmann::json j = {{"id", job.id},
                      {"kind", store::to_string(job.kind)},
                      {"mission_id", job.mission_id},
                      {"revision", job.revision},
                      {"state", store::to_string(job.state)},
                      {"progress", job.progress},
                      {"stage", job.stage},
                      {"attempts", job.attempts},
                      {"cancel_requested", job.cancel_requested},
                      {"params", job.params},
                      {"created", nullable_time(job.created_ms)},
                      {"started", nullable_time(job.started_ms)},
                      {"finished", nullable_time(job.finished_ms)},
                      {"result", result},
                      {"warnings", warnings},
                      {"metrics", metrics},
                      {"error", job.error}};
  if (with_artifacts) {
    const auto names = detail::artifact_names(job);
    const auto uavs = detail::result_uavs(job);
    nlohmann::json artifacts = nlohmann::json::array();
    for (const auto& a : job.artifacts)
      artifacts.push_back({{"name", a.name},
                           {"media_type", a.media_type},
                           {"size", a.size},
                           {"url", detail::artifact_url(job, a.name, names, uavs)}});
    j["artifacts"] = std::move(artifacts);
  }
  return j;
}

namespace {

/// A planner's own threads (smt's planner_params.threads) are bounded by the server's planning threads.
void check_planner_threads(const nlohmann::json& params, int max) {
  const auto pp = params.find("planner_params");
  if (pp == params.end() || !pp->is_object()) return;
  const auto threads = pp->find("threads");
  if (threads == pp->end() || !threads->is_number_integer() || threads->get<std::int64_t>() <= max) return;
  throw InputError("planner_params.threads", "at most " + std::to_string(max) +
                                                 " on this server (its planning threads, --workers), got " +
                                                 std::to_string(threads->get<std::int64_t>()));
}

}  // namespace

namespace detail {

Response enqueue_job(ApiContext& ctx, store::JobKind kind, store::Id mission_id, int revision,
                     const nlohmann::json& params) {
  store::NewJob job;
  job.kind = kind;
  job.mission_id = mission_id;
  job.revision = revision;
  job.params = params;
  store::Id id = 0;
  try {
    id = ctx.store.enqueue(job, ctx.config.max_queued);
  } catch (const store::QueueFull&) {
    HttpError e(
        503, "",
        "the job queue is full (" + std::to_string(ctx.config.max_queued) + " queued jobs); try again later");
    e.headers.emplace_back("Retry-After", "5");
    throw e;
  }
  const auto stored = ctx.store.get_job(id);
  if (!stored) throw store::StoreError("job " + std::to_string(id) + " vanished after enqueue");
  Response r = Response::json(202, job_json(*stored));
  r.headers.emplace_back("Location", kApi + "/" + job_collection(kind) + "/" + std::to_string(id));
  return r;
}

void add_job_routes(Router& router, ApiContext& ctx) {
  for (const store::JobKind kind :
       {store::JobKind::Plan, store::JobKind::Study, store::JobKind::Comparison}) {
    const std::string collection = job_collection(kind);
    router.add("POST", kApi + "/missions/{id}/" + collection,
               guarded([&ctx, kind, collection](const Request& req) {
                 const store::Id mission_id = id_param(req, "id");
                 const nlohmann::json body = parse_body(req, ctx, true);
                 const auto rev = ctx.store.get_mission(mission_id);
                 if (!rev) throw HttpError(404, "id", "no mission " + std::to_string(mission_id));
                 const Mission mission = parse_mission(rev->document, ctx.config.parse);
                 const nlohmann::json params = usecases::validate_job_params(job_type(kind), mission, body);
                 check_planner_threads(params, ctx.config.planner_threads);
                 return enqueue_job(ctx, kind, mission_id, rev->revision, params);
               }));
    router.add("GET", kApi + "/missions/{id}/" + collection, guarded([&ctx, kind](const Request& req) {
                 const store::Id mission_id = id_param(req, "id");
                 const int limit = list_limit(req);
                 if (!ctx.store.get_mission(mission_id))
                   throw HttpError(404, "id", "no mission " + std::to_string(mission_id));
                 nlohmann::json items = nlohmann::json::array();
                 for (const auto& job : ctx.store.list_jobs(mission_id, kind, limit))
                   items.push_back(job_summary_json(job));
                 return Response::json(200, {{"items", items}});
               }));
    const std::string base = kApi + "/" + collection + "/{id}";
    router.add("GET", base, guarded([&ctx, kind](const Request& req) {
                 return Response::json(200, job_json(get_job_or_404(ctx, id_param(req, "id"), kind)));
               }));
    router.add("DELETE", base, guarded([&ctx, kind](const Request& req) {
                 const store::Id id = id_param(req, "id");
                 const store::Job job = get_job_or_404(ctx, id, kind);
                 if (!store::terminal(job.state)) {
                   // queued or running: cancelled (it ends cancelled in whichever stage it is)
                   ctx.store.request_cancel(id);
                   return Response::json(200, job_json(get_job_or_404(ctx, id, kind)));
                 }
                 // finished: deleted with its artifacts and cached exports (never one a flight uses)
                 try {
                   ctx.store.delete_job(id);
                 } catch (const store::Conflict& e) {
                   throw HttpError(409, "id", e.what());
                 }
                 return no_content();
               }));
    auto file_route = [&](const std::string& name, const std::string& path) {
      router.add("GET", path, guarded([&ctx, kind, name](const Request& req) {
                   const store::Job job = get_job_or_404(ctx, id_param(req, "id"), kind);
                   return artifact_response(ctx, job, name, false);
                 }));
    };
    switch (kind) {
      case store::JobKind::Plan:
        for (const auto& f : kPlanFiles) file_route(f, base + "/" + f);
        router.add(
            "GET", base + "/images/{name}", guarded([&ctx](const Request& req) {
              const store::Job job = get_job_or_404(ctx, id_param(req, "id"), store::JobKind::Plan);
              const std::string name = req.params.at("name");
              if (!contains(kImages, name))
                throw HttpError(
                    404, "name",
                    "unknown image \"" + name.substr(0, 40) +
                        "\"; expected plan.png, plan.svg, heatmap.png, heatmap-overlay.png or histogram.png");
              return artifact_response(ctx, job, name, false);
            }));
        router.add("GET", base + "/exports/{format}",
                   guarded([&ctx](const Request& req) { return export_response(ctx, req); }));
        break;
      case store::JobKind::Study:
        for (const auto& f : kStudyFiles) file_route(f, base + "/" + f);
        break;
      case store::JobKind::Comparison:
        for (const auto& f : kCompareFiles) file_route(f, base + "/" + f);
        break;
    }
  }
}

}  // namespace detail
}  // namespace uavcover::server
