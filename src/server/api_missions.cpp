// /api/v1/missions: create, list (name, bbox, paging), read (latest or a revision), revise, delete.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "io/import.hpp"
#include "json/strict.hpp"
#include "server/api_internal.hpp"
#include "server/terrain_source.hpp"
#include "uavcover/error.hpp"
#include "uavcover/mission.hpp"
#include "usecases/jobs.hpp"

namespace uavcover::server {
namespace detail {
namespace {

/// Longest `name` filter accepted.
constexpr std::size_t kMaxNameFilter = 200;

nlohmann::json bbox_json(const store::Bbox& b) { return {b.min_lon, b.min_lat, b.max_lon, b.max_lat}; }

nlohmann::json summary_json(const store::MissionSummary& m) {
  return {{"id", m.id},
          {"name", m.name},
          {"revision", m.revision},
          {"created", iso_time(m.created_ms)},
          {"updated", iso_time(m.updated_ms)},
          {"bbox", bbox_json(m.bbox)}};
}

/// A stored JSON text back as JSON (stored by this server, so it parses; null if it somehow does not).
nlohmann::json stored_json(const std::string& text) {
  return nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
}

nlohmann::json mission_json(const store::MissionRevision& m) {
  return {{"id", m.mission_id},
          {"name", m.name},
          {"revision", m.revision},
          {"latest_revision", m.latest_revision},
          {"created", iso_time(m.created_ms)},
          {"updated", iso_time(m.revised_ms)},
          {"bbox", bbox_json(m.bbox)},
          {"mission", stored_json(m.document)},
          {"source", stored_json(m.source)}};
}

store::Bbox area_bbox(const Mission& mission) {
  store::Bbox b{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const auto& poly : mission.area)
    for (const auto& ring : poly)
      for (const auto& p : ring) {
        b.min_lon = std::min(b.min_lon, p.lon);
        b.min_lat = std::min(b.min_lat, p.lat);
        b.max_lon = std::max(b.max_lon, p.lon);
        b.max_lat = std::max(b.max_lat, p.lat);
      }
  if (!std::isfinite(b.min_lon)) return {};
  return b;
}

store::NewRevision new_revision(const Request& req, ApiContext& ctx) {
  return prepare_mission(parse_body(req, ctx, false), ctx.store, ctx.config.parse, ctx.config.dem_dir);
}

double parse_number(const std::string& text, const std::string& field) {
  double v = 0;
  const char* end = text.data() + text.size();
  const auto [p, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || p != end || !std::isfinite(v))
    throw HttpError(400, field, "expected a number, got \"" + text.substr(0, 40) + "\"");
  return v;
}

store::Bbox parse_bbox(const std::string& text) {
  std::vector<double> v;
  std::size_t pos = 0;
  while (v.size() < 5) {
    const std::size_t comma = std::min(text.find(',', pos), text.size());
    v.push_back(parse_number(text.substr(pos, comma - pos), "bbox"));
    if (comma == text.size()) break;
    pos = comma + 1;
  }
  if (v.size() != 4) throw HttpError(400, "bbox", "expected minlon,minlat,maxlon,maxlat (four numbers)");
  const store::Bbox b{v[0], v[1], v[2], v[3]};
  if (b.min_lon < -180 || b.max_lon > 180 || b.min_lat < -90 || b.max_lat > 90)
    throw HttpError(400, "bbox", "longitudes must be in [-180, 180] and latitudes in [-90, 90]");
  if (b.min_lon > b.max_lon || b.min_lat > b.max_lat)
    throw HttpError(400, "bbox", "expected minlon <= maxlon and minlat <= maxlat");
  return b;
}

int parse_limit(const std::string& text) {
  int v = 0;
  const char* end = text.data() + text.size();
  const auto [p, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || p != end || v < 1 || v > 1000)
    throw HttpError(400, "limit", "expected an integer in [1, 1000], got \"" + text.substr(0, 40) + "\"");
  return v;
}

store::MissionQuery parse_query(const Request& req) {
  store::MissionQuery q;
  if (const auto it = req.query.find("name"); it != req.query.end() && !it->second.empty()) {
    if (it->second.size() > kMaxNameFilter)
      throw HttpError(400, "name", "at most " + std::to_string(kMaxNameFilter) + " characters");
    q.name_contains = it->second;
  }
  if (const auto it = req.query.find("bbox"); it != req.query.end()) q.intersects = parse_bbox(it->second);
  if (const auto it = req.query.find("limit"); it != req.query.end()) q.limit = parse_limit(it->second);
  if (const auto it = req.query.find("cursor"); it != req.query.end() && !it->second.empty())
    q.after = parse_id(it->second, "cursor");
  return q;
}

store::MissionRevision get_or_404(ApiContext& ctx, store::Id id, std::optional<int> revision = {}) {
  auto m = ctx.store.get_mission(id, revision);
  if (!m) {
    if (revision && ctx.store.get_mission(id))
      throw HttpError(404, "revision",
                      "mission " + std::to_string(id) + " has no revision " + std::to_string(*revision));
    throw HttpError(404, "id", "no mission " + std::to_string(id));
  }
  return *std::move(m);
}

// POST /missions/import: a multipart upload ("file", optional "options" JSON) -> the mission skeleton.
Response import_upload(const Request& req, const ApiContext& ctx) {
  if (req.body.size() > ctx.config.max_body_bytes)
    throw HttpError(413, "body",
                    "the body is larger than " + std::to_string(ctx.config.max_body_bytes) + " bytes");
  const auto type = req.header("content-type");
  const std::vector<FormPart> parts = parse_multipart(type.value_or(""), req.body);
  const FormPart* file = nullptr;
  const FormPart* options = nullptr;
  for (const auto& p : parts) {
    if (p.name == "file")
      file = &p;
    else if (p.name == "options")
      options = &p;
    else
      throw HttpError(400, p.name.substr(0, 64),
                      "unknown part: expected \"file\" and optionally \"options\"");
  }
  if (file == nullptr) throw HttpError(400, "file", "missing: the upload needs a \"file\" part");
  if (!file->filename || file->filename->empty())
    throw HttpError(400, "file", "the part needs a filename (its extension tells the format)");
  io::ImportOptions opt;
  if (options != nullptr) {
    nlohmann::json o;
    try {
      o = strict::parse_json(options->body, "options");
    } catch (const InputError& e) {
      throw HttpError(400, e.field().empty() ? "options" : e.field(), e.what());
    }
    if (!o.is_object()) throw HttpError(400, "options", "expected a JSON object");
    for (const auto& [key, value] : o.items()) {
      const std::string field = "options." + key.substr(0, 64);
      if (key == "template") {
        if (!value.is_object()) throw HttpError(400, field, "expected a mission object");
        opt.template_mission = value;
        continue;
      }
      if (key != "layer" && key != "area_where" && key != "crs")
        throw HttpError(400, field, "unknown option: expected layer, area_where, crs or template");
      if (!value.is_string() || value.get<std::string>().empty() || value.get<std::string>().size() > 1000)
        throw HttpError(400, field, "expected a string of 1 to 1000 characters");
      (key == "layer"        ? opt.layer
       : key == "area_where" ? opt.area_where
                             : opt.crs) = value.get<std::string>();
    }
  }
  return Response::json(200, io::import_mission_bytes(file->body, *file->filename, opt));
}

}  // namespace

void add_mission_routes(Router& router, ApiContext& ctx) {
  const std::string base = kApi + "/missions";
  router.add("POST", base, guarded([&ctx, base](const Request& req) {
               const store::Id id = ctx.store.create_mission(new_revision(req, ctx));
               Response r = Response::json(201, {{"id", id}, {"revision", 1}});
               r.headers.emplace_back("Location", base + "/" + std::to_string(id));
               return r;
             }));
  // a mission checked and normalised without storing it: the web app shows spacing, GSD and footprint
  // as the operator types, computed by the library, and the field-named error of a bad value
  router.add(
      "POST", base + "/validate", guarded([&ctx](const Request& req) {
        const Mission m =
            resolve_mission(parse_body(req, ctx, false), ctx.store, ctx.config.parse, ctx.config.dem_dir);
        auto opt = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(); };
        return Response::json(200, {{"mission", stored_json(mission_to_json(m))},
                                    {"spacing_m", m.spacing_m},
                                    {"gsd_m", opt(m.gsd_m)},
                                    {"footprint_m", opt(m.footprint_m)},
                                    {"altitude_m", m.altitude_m},
                                    {"altitude_source", m.altitude_source},
                                    {"bbox", bbox_json(area_bbox(m))}});
      }));
  // a mission skeleton from an uploaded vector file (docs/import.md); not stored: the client stores
  // it as any other mission. Runs on the handler pool like every router route.
  router.add("POST", std::string(kImportRoute),
             guarded([&ctx](const Request& req) { return import_upload(req, ctx); }));
  router.add("GET", base, guarded([&ctx](const Request& req) {
               const store::MissionPage page = ctx.store.list_missions(parse_query(req));
               nlohmann::json items = nlohmann::json::array();
               for (const auto& m : page.items) items.push_back(summary_json(m));
               nlohmann::json next = nullptr;
               if (page.next_after) next = *page.next_after;
               return Response::json(200, {{"items", items}, {"next_cursor", next}});
             }));
  router.add("GET", base + "/{id}", guarded([&ctx](const Request& req) {
               return Response::json(200, mission_json(get_or_404(ctx, id_param(req, "id"))));
             }));
  router.add("PUT", base + "/{id}", guarded([&ctx](const Request& req) {
               const store::Id id = id_param(req, "id");
               const store::NewRevision rev = new_revision(req, ctx);
               int revision = 0;
               try {
                 revision = ctx.store.add_revision(id, rev);
               } catch (const store::NotFound&) {
                 throw HttpError(404, "id", "no mission " + std::to_string(id));
               }
               return Response::json(200, {{"id", id}, {"revision", revision}});
             }));
  router.add("GET", base + "/{id}/revisions/{n}", guarded([&ctx](const Request& req) {
               const store::Id id = id_param(req, "id");
               const std::int64_t n = id_param(req, "n", "revision");
               if (n > std::numeric_limits<int>::max())
                 throw HttpError(404, "revision",
                                 "mission " + std::to_string(id) + " has no revision " + std::to_string(n));
               return Response::json(200, mission_json(get_or_404(ctx, id, static_cast<int>(n))));
             }));
  router.add("DELETE", base + "/{id}", guarded([&ctx](const Request& req) {
               const store::Id id = id_param(req, "id");
               try {
                 ctx.store.delete_mission(id);
               } catch (const store::NotFound&) {
                 throw HttpError(404, "id", "no mission " + std::to_string(id));
               } catch (const store::Conflict&) {
                 throw HttpError(409, "id",
                                 "mission " + std::to_string(id) +
                                     " has queued or running jobs; cancel them or wait until they end");
               }
               return no_content();
             }));
}

}  // namespace detail

Mission resolve_mission(const nlohmann::json& document, store::Store& store, const ParseOptions& options,
                        const DemDir& dem_dir) {
  auto lookup = [&store](store::CatalogKind kind) {
    return [&store, kind](long long id) -> std::optional<nlohmann::json> {
      if (id <= 0) return std::nullopt;
      const auto entry = store.get_entry(kind, id);
      if (!entry) return std::nullopt;
      return entry->data;
    };
  };
  const nlohmann::json resolved = usecases::resolve_catalog_refs(document, lookup(store::CatalogKind::Uav),
                                                                 lookup(store::CatalogKind::Camera));
  Mission mission = parse_mission(resolved.dump(), options);
  // terrain (issue 31): a stored DEM (dem_id) or the server's tiles; never a path on the server's disk
  check_server_terrain(mission, store, dem_dir);
  return mission;
}

store::NewRevision prepare_mission(const nlohmann::json& document, store::Store& store,
                                   const ParseOptions& options, const DemDir& dem_dir) {
  const Mission mission = resolve_mission(document, store, options, dem_dir);
  store::NewRevision rev;
  rev.name = mission.name;
  rev.document = mission_to_json(mission);
  rev.source = document.dump();
  rev.bbox = detail::area_bbox(mission);
  return rev;
}

}  // namespace uavcover::server
