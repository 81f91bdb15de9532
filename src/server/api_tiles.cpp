// The map's tiles without internet (docs/offline-maps.md): GET /tiles/metadata.json says whether the
// server has tiles (`uavcover serve --tiles FILE.mbtiles`) and where, GET /tiles/{z}/{x}/{y} serves one
// from the MBTiles file. They run on the handler pool like every routed request, never on an I/O thread.
#include <cstdint>
#include <string>

#include "io/mbtiles.hpp"
#include "server/api_internal.hpp"

namespace uavcover::server::detail {

namespace {

constexpr int kMaxZoom = 30;
constexpr const char* kTilesCache = "max-age=86400";  // private caches, and shared ones without a token

/// A path segment as a whole decimal number below `limit`; 400 naming `field` otherwise.
std::int64_t coordinate(const std::string& text, const std::string& field, std::int64_t limit,
                        const std::string& why) {
  const bool digits =
      !text.empty() && text.size() <= 10 && text.find_first_not_of("0123456789") == std::string::npos;
  if (!digits)
    throw HttpError(400, field,
                    field + " must be a whole decimal number, got \"" + text.substr(0, 40) + "\"");
  const std::int64_t v = std::stoll(text);
  if (v >= limit) throw HttpError(400, field, field + " must be " + why + ", got " + text);
  return v;
}

/// The tile format a ".png", ".jpg", ".jpeg" or ".webp" suffix names; empty for none of them.
std::string suffix_format(const std::string& ext) {
  if (ext == "png") return "png";
  if (ext == "jpg" || ext == "jpeg") return "jpg";
  if (ext == "webp") return "webp";
  return "";
}

}  // namespace

void add_tile_routes(Router& router, ApiContext& ctx) {
  router.add("GET", "/tiles/metadata.json", guarded([&ctx](const Request&) {
               nlohmann::json out{{"available", ctx.tiles != nullptr}};
               if (ctx.tiles != nullptr) {
                 const auto& i = ctx.tiles->info();
                 out["url"] = "/tiles/{z}/{x}/{y}";
                 out["name"] = i.name;
                 out["description"] = i.description;
                 out["attribution"] = i.attribution;
                 out["format"] = i.format;
                 out["media_type"] = i.media_type;
                 out["minzoom"] = i.minzoom;
                 out["maxzoom"] = i.maxzoom;
                 out["bounds"] = i.bounds ? nlohmann::json(*i.bounds) : nlohmann::json(nullptr);
                 out["center"] = i.center ? nlohmann::json(*i.center) : nlohmann::json(nullptr);
               }
               Response r = Response::json(200, out);
               r.headers.emplace_back("Cache-Control", "no-cache");
               return r;
             }));
  router.add("GET", "/tiles/{z}/{x}/{y}", guarded([&ctx](const Request& req) {
               const std::int64_t z =
                   coordinate(req.params.at("z"), "z", kMaxZoom + 1, "at most " + std::to_string(kMaxZoom));
               const std::int64_t n = std::int64_t{1} << z;
               const std::string range = "less than 2^z = " + std::to_string(n);
               const std::int64_t x = coordinate(req.params.at("x"), "x", n, range);
               std::string y_text = req.params.at("y");
               if (const auto dot = y_text.find('.'); dot != std::string::npos) {
                 const std::string ext = y_text.substr(dot + 1);
                 const std::string asked = suffix_format(ext);
                 const std::string have = ctx.tiles != nullptr ? ctx.tiles->info().format : asked;
                 if (asked.empty() || asked != have)
                   throw HttpError(400, "y",
                                   "the suffix \"." + ext.substr(0, 20) + "\" is not the tiles' format" +
                                       (have.empty() ? std::string() : " (" + have + ")") +
                                       ": ask /tiles/{z}/{x}/{y} or /tiles/{z}/{x}/{y}." +
                                       (have.empty() ? std::string("png") : have));
                 y_text.resize(dot);
               }
               const std::int64_t y = coordinate(y_text, "y", n, range);
               if (ctx.tiles == nullptr)
                 throw HttpError(404, "",
                                 "this server has no map tiles (uavcover serve --tiles FILE.mbtiles)");
               auto bytes = ctx.tiles->tile(static_cast<int>(z), x, y);
               if (!bytes)
                 throw HttpError(404, "",
                                 "no tile " + std::to_string(z) + "/" + std::to_string(x) + "/" +
                                     std::to_string(y) + " in the map tiles");
               Response r;
               r.content_type = ctx.tiles->info().media_type;
               r.body = std::move(*bytes);
               r.headers.emplace_back("Cache-Control", kTilesCache);
               r.headers.emplace_back("X-Content-Type-Options", "nosniff");
               return r;
             }));
}

}  // namespace uavcover::server::detail
