// The catalogs: /api/v1/uavs and /api/v1/cameras (create, list, read, replace, delete), with every
// field validated (422 naming it).
#include <cmath>

#include "server/api_internal.hpp"
#include "uavcover/error.hpp"

namespace uavcover::server::detail {
namespace {

constexpr std::size_t kMaxName = 200;

struct NumberField {
  const char* name;
  double min;
  double max;
  bool min_inclusive;
  bool max_inclusive;
  bool required;
  bool integer;
};

// UAV: speed (0, 50] m/s, acceleration (0, 50] m/s², endurance (0, 1440] min, cost [0, 1000] EUR/min.
const std::vector<NumberField> kUavFields{
    {"speed_mps", 0, 50, false, true, true, false},
    {"max_accel_mps2", 0, 50, false, true, true, false},
    {"endurance_min", 0, 1440, false, true, true, false},
    {"cost_per_min_eur", 0, 1000, true, true, true, false},
};
// Camera: sensor (0, 100] mm, focal length (0, 1000] mm, image width (0, 100000] px, HFOV (0, 180) deg.
const std::vector<NumberField> kCameraFields{
    {"sensor_width_mm", 0, 100, false, true, true, false},
    {"focal_length_mm", 0, 1000, false, true, true, false},
    {"image_width_px", 0, 100000, false, true, true, true},
    {"hfov_deg", 0, 180, false, false, true, false},
};

std::string bound_text(const NumberField& f) {
  auto num = [](double v) {
    std::string s = std::to_string(v);
    s.erase(s.find_last_not_of('0') + 1);
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
  };
  return std::string(f.min_inclusive ? "[" : "(") + num(f.min) + ", " + num(f.max) +
         (f.max_inclusive ? "]" : ")");
}

const char* kind_name(store::CatalogKind kind) { return kind == store::CatalogKind::Uav ? "UAV" : "camera"; }

/// Validates a catalog entry body: returns {name, data without the name}. InputError naming the field.
std::pair<std::string, nlohmann::json> validate_entry(store::CatalogKind kind, const nlohmann::json& body,
                                                      ApiContext& ctx) {
  if (!body.is_object())
    throw InputError("", "expected a JSON object with the " + std::string(kind_name(kind)) + "'s fields");
  const auto& fields = kind == store::CatalogKind::Uav ? kUavFields : kCameraFields;
  for (const auto& [key, value] : body.items()) {
    bool known = key == "name" || (kind == store::CatalogKind::Uav && key == "camera_id");
    for (const auto& f : fields) known = known || key == f.name;
    if (!known) throw InputError(key.substr(0, 100), "unknown field");
  }
  const auto name_it = body.find("name");
  if (name_it == body.end()) throw InputError("name", "required");
  if (!name_it->is_string()) throw InputError("name", "expected a string");
  const std::string name = name_it->get<std::string>();
  if (name.find_first_not_of(" \t\r\n") == std::string::npos) throw InputError("name", "must not be empty");
  if (name.size() > kMaxName) throw InputError("name", "at most " + std::to_string(kMaxName) + " characters");
  for (const char c : name)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      throw InputError("name", "must not hold control characters (tabs, line breaks, escapes)");
  nlohmann::json data = nlohmann::json::object();
  for (const auto& f : fields) {
    const auto it = body.find(f.name);
    if (it == body.end()) {
      if (f.required) throw InputError(f.name, "required");
      continue;
    }
    if (!it->is_number()) throw InputError(f.name, "expected a number");
    if (f.integer && !it->is_number_integer()) throw InputError(f.name, "expected an integer");
    const double v = it->get<double>();
    const bool ok = std::isfinite(v) && (f.min_inclusive ? v >= f.min : v > f.min) &&
                    (f.max_inclusive ? v <= f.max : v < f.max);
    if (!ok) throw InputError(f.name, "must be in " + bound_text(f));
    data[f.name] = *it;
  }
  if (kind == store::CatalogKind::Uav) {
    if (const auto it = body.find("camera_id"); it != body.end() && !it->is_null()) {
      if (!it->is_number_integer() || it->get<std::int64_t>() <= 0)
        throw InputError("camera_id", "expected a positive integer camera id");
      const auto id = it->get<std::int64_t>();
      if (!ctx.store.get_entry(store::CatalogKind::Camera, id))
        throw InputError("camera_id", "no camera " + std::to_string(id));
      data["camera_id"] = id;
    }
  }
  return {name, data};
}

nlohmann::json entry_json(const store::CatalogEntry& e) {
  nlohmann::json j = e.data.is_object() ? e.data : nlohmann::json::object();
  j["id"] = e.id;
  j["name"] = e.name;
  j["updated"] = iso_time(e.updated_ms);
  return j;
}

store::CatalogEntry get_or_404(ApiContext& ctx, store::CatalogKind kind, store::Id id) {
  auto e = ctx.store.get_entry(kind, id);
  if (!e) throw HttpError(404, "id", std::string("no ") + kind_name(kind) + " " + std::to_string(id));
  return *std::move(e);
}

}  // namespace

void add_catalog_routes(Router& router, ApiContext& ctx) {
  for (const store::CatalogKind kind : {store::CatalogKind::Uav, store::CatalogKind::Camera}) {
    const std::string base = kApi + (kind == store::CatalogKind::Uav ? "/uavs" : "/cameras");
    router.add("POST", base, guarded([&ctx, kind, base](const Request& req) {
                 const auto [name, data] = validate_entry(kind, parse_body(req, ctx, false), ctx);
                 store::Id id = 0;
                 try {
                   id = ctx.store.create_entry(kind, name, data);
                 } catch (const store::Conflict& e) {
                   throw HttpError(409, "camera_id", e.what());  // its camera deleted meanwhile
                 }
                 Response r = Response::json(201, {{"id", id}});
                 r.headers.emplace_back("Location", base + "/" + std::to_string(id));
                 return r;
               }));
    router.add("GET", base, guarded([&ctx, kind](const Request&) {
                 nlohmann::json items = nlohmann::json::array();
                 for (const auto& e : ctx.store.list_entries(kind)) items.push_back(entry_json(e));
                 return Response::json(200, {{"items", items}});
               }));
    router.add("GET", base + "/{id}", guarded([&ctx, kind](const Request& req) {
                 return Response::json(200, entry_json(get_or_404(ctx, kind, id_param(req, "id"))));
               }));
    router.add("PUT", base + "/{id}", guarded([&ctx, kind](const Request& req) {
                 const store::Id id = id_param(req, "id");
                 get_or_404(ctx, kind, id);
                 const auto [name, data] = validate_entry(kind, parse_body(req, ctx, false), ctx);
                 try {
                   ctx.store.update_entry(kind, id, name, data);
                 } catch (const store::NotFound&) {
                   throw HttpError(404, "id",
                                   std::string("no ") + kind_name(kind) + " " + std::to_string(id));
                 } catch (const store::Conflict& e) {
                   throw HttpError(409, "camera_id", e.what());  // its camera deleted meanwhile
                 }
                 return Response::json(200, entry_json(get_or_404(ctx, kind, id)));
               }));
    router.add("DELETE", base + "/{id}", guarded([&ctx, kind](const Request& req) {
                 const store::Id id = id_param(req, "id");
                 try {
                   // one transaction: refused (Conflict) while a UAV carries the camera (store/backends.hpp)
                   ctx.store.delete_entry(kind, id);
                 } catch (const store::NotFound&) {
                   throw HttpError(404, "id",
                                   std::string("no ") + kind_name(kind) + " " + std::to_string(id));
                 } catch (const store::Conflict& e) {
                   throw HttpError(409, "id", e.what());
                 }
                 return no_content();
               }));
  }
}

}  // namespace uavcover::server::detail
