// Flights (docs/flights.md): POST/GET /plans/{id}/flights, GET/DELETE /flights/{id}, commands, and the
// flight log as pages, CSV and GeoJSON. The live flights are the FlightManager's.
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <map>

#include "io/exif.hpp"
#include "server/api_internal.hpp"
#include "server/flights.hpp"
#include "uavcover/error.hpp"
#include "usecases/jobs.hpp"
#include "usecases/photos.hpp"
#include "usecases/refly.hpp"

namespace uavcover::server::detail {
namespace {

using nlohmann::json;

/// Photos in one POST /photos/tags (the app sends its photos in batches of this many).
constexpr std::size_t kMaxPhotoParts = 200;

/// Records an export (CSV, GeoJSON) reads at most.
constexpr std::int64_t kMaxExportRecords = 200000;

FlightManager& manager(ApiContext& ctx) {
  if (ctx.flights == nullptr) throw HttpError(503, "", "this server does not follow flights");
  return *ctx.flights;
}

/// The flight's plan job (404 naming id when the flight or its plan is gone).
store::Job flight_plan_job(ApiContext& ctx, store::Id id) {
  const auto row = ctx.store.get_flight(id);
  if (!row) throw HttpError(404, "id", "no flight " + std::to_string(id));
  auto job = ctx.store.get_job(row->plan_id);
  if (!job) throw HttpError(404, "id", "the flight's plan " + std::to_string(row->plan_id) + " is gone");
  return std::move(*job);
}

/// The photos' coverage over the flight's plan from a body's "photos" (POST /photos/tags' items) and
/// optional "takeoff_alt_m"; both keys are taken out of `body`.
usecases::PhotoCoverage photos_of_body(json& body, const Plan& plan) {
  const auto list = body.find("photos");
  if (list == body.end() || !list->is_array() || list->empty())
    throw InputError("photos", "expected the photos' tags (the items of POST /api/v1/photos/tags)");
  if (list->size() > io::kMaxPhotos) throw InputError("photos", fmt::format("more than {}", io::kMaxPhotos));
  std::vector<io::PhotoTags> tags;
  tags.reserve(list->size());
  for (std::size_t i = 0; i < list->size(); ++i)
    tags.push_back(io::photo_tags_from_json((*list)[i], fmt::format("photos[{}]", i)));
  usecases::PhotoOptions po;
  if (const auto t = body.find("takeoff_alt_m"); t != body.end()) {
    if (!t->is_number() || !(t->get<double>() >= -1000.0 && t->get<double>() <= 10000.0))
      throw InputError("takeoff_alt_m", "expected the take-off's height above sea level in [-1000, 10000] m");
    po.takeoff_altitude_m = t->get<double>();
    body.erase("takeoff_alt_m");
  }
  body.erase("photos");
  return usecases::photo_coverage(plan, tags, po);
}

/// An integer query parameter in [lo, hi], `fallback` when absent; 400 naming it otherwise.
std::int64_t query_int(const Request& req, const std::string& name, std::int64_t fallback, std::int64_t lo,
                       std::int64_t hi) {
  const auto it = req.query.find(name);
  if (it == req.query.end()) return fallback;
  const std::string& text = it->second;
  std::int64_t v = 0;
  const char* end = text.data() + text.size();
  const auto [p, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || p != end || v < lo || v > hi)
    throw HttpError(400, name,
                    fmt::format("expected an integer in [{}, {}], got \"{}\"", lo, hi, text.substr(0, 40)));
  return v;
}

store::Job plan_job(ApiContext& ctx, store::Id id) {
  auto job = ctx.store.get_job(id);
  if (!job || job->kind != store::JobKind::Plan)
    throw HttpError(404, "id", "no plan job " + std::to_string(id));
  return *std::move(job);
}

json flight_or_404(ApiContext& ctx, store::Id id) {
  auto f = manager(ctx).get(id);
  if (!f) throw HttpError(404, "id", "no flight " + std::to_string(id));
  return *std::move(f);
}

json record_json(const store::FlightLogRecord& r) {
  return {{"seq", r.seq}, {"t", iso_time(r.t_ms)}, {"uav", r.uav}, {"kind", r.kind}, {"data", r.data}};
}

/// Every record of the flight's log (at most kMaxExportRecords), in order; 404 for an unknown flight.
std::vector<store::FlightLogRecord> whole_log(ApiContext& ctx, store::Id id) {
  if (!ctx.store.get_flight(id)) throw HttpError(404, "id", "no flight " + std::to_string(id));
  std::vector<store::FlightLogRecord> out;
  std::int64_t after = 0;
  while (static_cast<std::int64_t>(out.size()) < kMaxExportRecords) {
    auto page = ctx.store.read_flight_log(id, after, 10000);
    for (auto& r : page.items) out.push_back(std::move(r));
    if (!page.next_after) break;
    after = *page.next_after;
  }
  return out;
}

Response attachment(std::string body, const std::string& type, const std::string& file) {
  Response r;
  r.content_type = type;
  r.body = std::move(body);
  r.headers.emplace_back("Content-Disposition", "attachment; filename=\"" + file + "\"");
  return r;
}

/// RFC 4180 field: quoted when it holds a comma, quote or line break.
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string out = "\"";
  for (const char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string number_or_empty(const json& data, const char* key) {
  const auto it = data.find(key);
  if (it == data.end() || !it->is_number()) return "";
  return fmt::format("{}", it->get<double>());
}

std::string log_csv(const std::vector<store::FlightLogRecord>& log) {
  std::string out = "seq,time,uav,kind,lon,lat,alt_m,speed_mps,battery_pct,data\n";
  for (const auto& r : log) {
    const bool object = r.data.is_object();
    const json none = json::object();
    const json& d = object ? r.data : none;
    out += fmt::format("{},{},{},{},{},{},{},{},{},{}\n", r.seq, iso_time(r.t_ms), csv_field(r.uav),
                       csv_field(r.kind), number_or_empty(d, "lon"), number_or_empty(d, "lat"),
                       number_or_empty(d, "alt_m"), number_or_empty(d, "speed_mps"),
                       number_or_empty(d, "battery_pct"),
                       csv_field(r.data.dump(-1, ' ', false, json::error_handler_t::replace)));
  }
  return out;
}

/// Telemetry as one LineString per UAV ([lon, lat, alt_m]); every other record as a Point where its UAV
/// last was (flight-wide records, or before the first position: geometry null).
json log_geojson(const std::vector<store::FlightLogRecord>& log) {
  std::map<std::string, json> tracks;
  std::map<std::string, json> last;
  json events = json::array();
  for (const auto& r : log) {
    if (r.kind == "telemetry" && r.data.is_object() && r.data.contains("lon") && r.data.contains("lat") &&
        r.data["lon"].is_number() && r.data["lat"].is_number()) {
      const json p = {r.data["lon"], r.data["lat"],
                      r.data.contains("alt_m") && r.data["alt_m"].is_number() ? r.data["alt_m"] : json(0.0)};
      auto& t = tracks[r.uav];
      if (t.is_null()) t = json::array();
      t.push_back(p);
      last[r.uav] = p;
      continue;
    }
    if (r.kind == "telemetry") continue;
    const auto at = last.find(r.uav);
    events.push_back(
        {{"type", "Feature"},
         {"geometry",
          at == last.end() ? json(nullptr) : json{{"type", "Point"}, {"coordinates", at->second}}},
         {"properties",
          {{"seq", r.seq}, {"t", iso_time(r.t_ms)}, {"uav", r.uav}, {"kind", r.kind}, {"data", r.data}}}});
  }
  json features = json::array();
  for (auto& [uav, coords] : tracks) {
    if (coords.size() < 2) coords.push_back(coords.front());  // a LineString needs two positions
    features.push_back({{"type", "Feature"},
                        {"geometry", {{"type", "LineString"}, {"coordinates", coords}}},
                        {"properties", {{"uav", uav}, {"kind", "track"}, {"positions", coords.size()}}}});
  }
  for (auto& e : events) features.push_back(std::move(e));
  return {{"type", "FeatureCollection"}, {"features", features}};
}

}  // namespace

void add_flight_routes(Router& router, ApiContext& ctx) {
  router.add("POST", kApi + "/plans/{id}/flights", guarded([&ctx](const Request& req) {
               const store::Job job = plan_job(ctx, id_param(req, "id"));
               if (job.state != store::JobState::Done)
                 throw HttpError(409, "state",
                                 "the plan is " + store::to_string(job.state) + "; only a done plan flies");
               const json body = parse_body(req, ctx, false);
               const json flight = manager(ctx).create(job, body);
               Response r = Response::json(201, flight);
               r.headers.emplace_back("Location",
                                      kApi + "/flights/" + std::to_string(flight.at("id").get<store::Id>()));
               return r;
             }));
  router.add("GET", kApi + "/plans/{id}/flights", guarded([&ctx](const Request& req) {
               const store::Job job = plan_job(ctx, id_param(req, "id"));
               const auto limit = static_cast<int>(query_int(req, "limit", 100, 1, 1000));
               json items = json::array();
               for (const auto& row : ctx.store.list_flights(job.id, limit)) {
                 auto f = manager(ctx).get(row.id);
                 if (!f) continue;  // deleted meanwhile
                 if (auto it = f->find("uavs"); it != f->end() && it->is_array())
                   for (auto& u : *it)
                     if (u.is_object()) u.erase("waypoints");  // the listing leaves them out
                 items.push_back(std::move(*f));
               }
               return Response::json(200, {{"items", items}});
             }));
  // A mission's flights that have not ended (not done or aborted), of any of its plans, newest first: a
  // client finds the aircraft in the air whatever plan it shows (issue 29). Live state from memory.
  router.add("GET", kApi + "/missions/{id}/flights", guarded([&ctx](const Request& req) {
               const store::Id mission = id_param(req, "id");
               if (!ctx.store.get_mission(mission))
                 throw HttpError(404, "id", "no mission " + std::to_string(mission));
               std::vector<store::Id> ids;
               for (const auto& row : ctx.store.list_active_flights())
                 if (row.mission_id == mission) ids.push_back(row.id);
               std::sort(ids.rbegin(), ids.rend());
               json items = json::array();
               for (const store::Id id : ids) {
                 auto f = manager(ctx).get(id);
                 if (!f) continue;  // deleted meanwhile
                 const std::string state = f->value("state", "");
                 if (state == "done" || state == "aborted") continue;  // ended since it was listed
                 if (auto it = f->find("uavs"); it != f->end() && it->is_array())
                   for (auto& u : *it)
                     if (u.is_object()) u.erase("waypoints");  // as GET /plans/{id}/flights
                 items.push_back(std::move(*f));
               }
               return Response::json(200, {{"items", items}});
             }));
  const std::string base = kApi + "/flights/{id}";
  router.add("GET", base, guarded([&ctx](const Request& req) {
               return Response::json(200, flight_or_404(ctx, id_param(req, "id")));
             }));
  router.add("DELETE", base, guarded([&ctx](const Request& req) {
               return Response::json(200, manager(ctx).remove(id_param(req, "id")));
             }));
  router.add("POST", base + "/commands", guarded([&ctx](const Request& req) {
               const store::Id id = id_param(req, "id");
               const json body = parse_body(req, ctx, false);
               return Response::json(202, manager(ctx).command(id, body));
             }));
  router.add("GET", base + "/log", guarded([&ctx](const Request& req) {
               const store::Id id = id_param(req, "id");
               const std::int64_t after = query_int(req, "after", 0, 0, std::int64_t{1} << 53);
               const auto limit = static_cast<int>(query_int(req, "limit", 100, 1, 1000));
               if (!ctx.store.get_flight(id)) throw HttpError(404, "id", "no flight " + std::to_string(id));
               const auto page = ctx.store.read_flight_log(id, after, limit);
               json items = json::array();
               for (const auto& r : page.items) items.push_back(record_json(r));
               return Response::json(
                   200, {{"items", items},
                         {"next_after", page.next_after ? json(*page.next_after) : json(nullptr)}});
             }));
  router.add("GET", base + "/coverage", guarded([&ctx](const Request& req) {
               return Response::json(200, manager(ctx).coverage(id_param(req, "id"))->summary);
             }));
  router.add("GET", base + "/coverage.png", guarded([&ctx](const Request& req) {
               Response r;
               r.content_type = "image/png";
               r.body = manager(ctx).coverage(id_param(req, "id"))->png;
               return r;
             }));
  router.add("GET", base + "/log.csv", guarded([&ctx](const Request& req) {
               const store::Id id = id_param(req, "id");
               return attachment(log_csv(whole_log(ctx, id)), "text/csv",
                                 "flight-" + std::to_string(id) + "-log.csv");
             }));
  // refly the gaps (docs/refly.md): a plan job of the flight's mission for what the tracks left unscanned
  router.add("POST", base + "/refly", guarded([&ctx](const Request& req) {
               const store::Id id = id_param(req, "id");
               json params = parse_body(req, ctx, true);
               if (params.is_null()) params = json::object();
               if (!params.is_object()) throw InputError("body", "expected a JSON object");
               const store::Job job = flight_plan_job(ctx, id);
               std::vector<std::string> uavs;
               if (const auto u = params.find("uavs"); u != params.end()) {
                 if (!u->is_array()) throw InputError("uavs", "expected a list of UAV ids");
                 for (std::size_t i = 0; i < u->size(); ++i) {
                   if (!(*u)[i].is_string())
                     throw InputError(fmt::format("uavs[{}]", i), "expected a UAV id");
                   uavs.push_back((*u)[i].get<std::string>());
                 }
                 params.erase("uavs");
               }
               const Plan flown = load_job_plan(ctx.store, job, ctx.config.dem_dir);
               // the gaps from the photos' footprints when the body gives them (docs/photos.md), else
               // from the flight's tracks
               const bool from_photos = params.contains("photos");
               const auto gaps = from_photos ? photos_of_body(params, flown).gaps
                                             : usecases::coverage_gaps(flown, manager(ctx).tracks(id));
               const Mission refly = usecases::refly_mission(flown, gaps, uavs);
               params = usecases::validate_job_params(usecases::JobType::Plan, refly, params);
               params["refly"] = {{"flight_id", id},
                                  {"source", from_photos ? "photos" : "tracks"},
                                  {"flown_poc", gaps.flown_poc},
                                  {"gaps_m2", gaps.area_m2},
                                  {"mission", json::parse(mission_to_json(refly, -1))}};
               return enqueue_job(ctx, store::JobKind::Plan, job.mission_id, job.revision, params);
             }));
  // the photos' tags (docs/photos.md), read with exiv2 on the handler pool: each part "photos" is a JPEG, or
  // its first bytes (the app sends the head of each file: the tags come before the image data)
  router.add(
      "POST", std::string(kPhotoTagsRoute), guarded([&ctx](const Request& req) {
        if (req.body.size() > ctx.config.max_body_bytes)
          throw HttpError(413, "body",
                          "the body is larger than " + std::to_string(ctx.config.max_body_bytes) + " bytes");
        MultipartLimits limits;
        limits.max_parts = kMaxPhotoParts;
        limits.repeatable = "photos";
        const auto parts = parse_multipart(req.header("content-type").value_or(""), req.body, limits);
        json items = json::array();
        for (std::size_t i = 0; i < parts.size(); ++i) {
          const FormPart& p = parts[i];
          if (p.name != "photos")
            throw HttpError(400, p.name.substr(0, 64), "unknown part: expected \"photos\" (one per file)");
          const std::string name =
              p.filename && !p.filename->empty() ? p.filename->substr(0, 255) : fmt::format("photos[{}]", i);
          items.push_back(io::to_json(io::read_photo_tags(
              reinterpret_cast<const std::uint8_t*>(p.body.data()), p.body.size(), name)));
        }
        if (items.empty()) throw HttpError(400, "photos", "no \"photos\" part");
        return Response::json(200, {{"items", std::move(items)}});
      }));
  // what the photos saw (docs/photos.md): footprints, coverage and gaps over the flight's plan
  router.add("POST", base + "/photos", guarded([&ctx](const Request& req) {
               const store::Id id = id_param(req, "id");
               json body = parse_body(req, ctx, false);
               if (!body.is_object()) throw InputError("body", "expected a JSON object {\"photos\": [...]}");
               const Plan plan = load_job_plan(ctx.store, flight_plan_job(ctx, id), ctx.config.dem_dir);
               const usecases::PhotoCoverage c = photos_of_body(body, plan);
               if (!body.empty())
                 throw InputError(body.begin().key().substr(0, 64),
                                  "unknown field: expected photos, takeoff_alt_m");
               json out = usecases::photo_summary(c);
               out["flight_id"] = id;
               out["geojson"] = json::parse(usecases::photos_geojson(c));
               return Response::json(200, out);
             }));
  router.add("GET", base + "/log.geojson", guarded([&ctx](const Request& req) {
               const store::Id id = id_param(req, "id");
               return attachment(
                   log_geojson(whole_log(ctx, id)).dump(-1, ' ', false, json::error_handler_t::replace),
                   "application/geo+json", "flight-" + std::to_string(id) + "-log.geojson");
             }));
}

}  // namespace uavcover::server::detail
