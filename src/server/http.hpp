// The server's own small HTTP value types, so API handlers stay independent of Boost.Beast: the
// transport (server.cpp) turns Beast messages into Request and Response into Beast messages.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace uavcover::server {

struct Request {
  std::string method;                          ///< "GET", "POST", ...
  std::string path;                            ///< decoded path without the query, e.g. "/api/v1/missions/3"
  std::map<std::string, std::string> query;    ///< decoded query parameters (last one wins)
  std::map<std::string, std::string> headers;  ///< lower-case names
  std::string body;
  std::string request_id;
  /// Path parameters captured by the route pattern ("{id}" -> params["id"]).
  std::map<std::string, std::string> params;

  [[nodiscard]] std::optional<std::string> header(const std::string& lower_name) const {
    const auto it = headers.find(lower_name);
    if (it == headers.end()) return std::nullopt;
    return it->second;
  }
};

struct Response {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;  ///< extra headers (Location, Retry-After, ...)

  static Response json(int status, const nlohmann::json& body);
  /// {"error": {"field": field, "message": message}}
  static Response error(int status, const std::string& field, const std::string& message);
};

/// An error a handler throws to answer with status and a field-named message.
struct HttpError : std::runtime_error {
  HttpError(int status, std::string field, const std::string& message)
      : std::runtime_error(message), status(status), field(std::move(field)) {}
  int status;
  std::string field;
  std::vector<std::pair<std::string, std::string>> headers;  ///< e.g. Retry-After
};

using Handler = std::function<Response(const Request&)>;

/// Routes by method and path pattern; "{name}" matches one path segment into Request::params.
/// `name` is the route's label in metrics and logs (the pattern itself, e.g. "/api/v1/missions/{id}").
class Router {
 public:
  void add(const std::string& method, const std::string& pattern, Handler handler);

  struct Match {
    const Handler* handler = nullptr;
    std::string route;  ///< the pattern matched (for metrics)
    std::map<std::string, std::string> params;
    std::vector<std::string> allowed;  ///< methods allowed on the path when none matched (405)
  };
  /// handler == nullptr and allowed empty: 404; handler == nullptr and allowed not empty: 405.
  [[nodiscard]] Match match(const std::string& method, const std::string& path) const;
  /// Every registered route as (method, pattern), in registration order (the OpenAPI document test).
  [[nodiscard]] std::vector<std::pair<std::string, std::string>> routes() const;

 private:
  struct Route {
    std::string method;
    std::string pattern;
    std::vector<std::string> segments;
    Handler handler;
  };
  std::vector<Route> routes_;
};

/// Splits a request target ("/path?a=1&b=%20") into the percent-decoded path and query parameters
/// ('+' is a space in the query; the last of a repeated key wins). The absolute form
/// ("http://host:port/path?q", RFC 9112 3.2.2) is accepted: its authority is skipped (see
/// target_authority). HttpError 400 ("path" or "query") on a target without a leading '/', a malformed
/// escape or a NUL byte.
void decode_target(std::string_view target, Request& req);

/// The authority ("host:port") of an absolute-form target ("http://host:port/path"), nullopt for the
/// origin form ("/path"). The scheme is http or https, case-insensitive.
std::optional<std::string> target_authority(std::string_view target);

/// Which Host header values (or absolute-form authorities) the server answers, against DNS rebinding:
/// the listen address, localhost, 127.0.0.1 and [::1] with no port or the server's port; any IP
/// literal when it listens on an unspecified address (0.0.0.0, ::); and each `allowed` name (a proxy's
/// public name) with any port. Names compare case-insensitively, a trailing dot ignored.
struct HostPolicy {
  std::string listen_host;  ///< without brackets
  std::uint16_t port = 0;   ///< the bound port
  std::vector<std::string> allowed;
};
/// "name", "name:port", "[v6]" or "[v6]:port" split (name lower-cased, without brackets and a
/// trailing dot); false when malformed (empty, bad port, characters a host name cannot hold).
bool split_host(std::string_view value, std::string& host, std::optional<std::uint16_t>& port);
bool host_allowed(std::string_view value, const HostPolicy& policy);

/// True when a request's Origin header may drive the server: the configured CORS origin, or the
/// server's own origin (http:// or https:// followed by the request's Host value). "null" never is.
bool origin_allowed(std::string_view origin, std::string_view host,
                    const std::optional<std::string>& cors_origin);

/// A media type without parameters, trimmed and lower-cased ("Application/JSON; charset=utf-8" ->
/// "application/json").
std::string media_type(std::string_view content_type);

/// True for 127.0.0.0/8, ::1 (and ::ffff:127.x.y.z) and "localhost".
bool is_loopback(const std::string& host);

/// The routes whose body is multipart/form-data, not JSON: the vector importer's upload (docs/import.md),
/// the photos' tags (docs/photos.md) and the elevation models (docs/api.md). The transport lets that media
/// type through for them alone (a foreign page is refused by the Origin check first); the API registers them.
inline constexpr std::string_view kImportRoute = "/api/v1/missions/import";
inline constexpr std::string_view kPhotoTagsRoute = "/api/v1/photos/tags";
inline constexpr std::string_view kDemsRoute = "/api/v1/dems";  ///< an elevation model (issue 31)
inline bool multipart_route(std::string_view method, std::string_view path) {
  return method == "POST" && (path == kImportRoute || path == kPhotoTagsRoute || path == kDemsRoute);
}

/// One part of a multipart/form-data body (RFC 7578).
struct FormPart {
  std::string name;                     ///< Content-Disposition: form-data; name="..."
  std::optional<std::string> filename;  ///< its filename="..." parameter, when given
  std::string content_type;             ///< the part's Content-Type (empty when absent)
  std::string body;
};

/// Limits of parse_multipart (a fuzzed body never makes it allocate more than the body's size per part).
struct MultipartLimits {
  std::size_t max_parts = 16;
  std::size_t max_header_bytes = 8192;  ///< one part's header block
  std::string repeatable;               ///< the one name that may be given more than once (a file list)
};

/// Parses a multipart/form-data body strictly: the boundary from `content_type` (1 to 70 characters,
/// quoted or not), CRLF framing, a closing delimiter, each part with a Content-Disposition form-data
/// header naming it (name, optional filename; quoted-string escapes), names unique (but limits.repeatable).
/// HttpError 415
/// ("content-type") when the type is not multipart/form-data or has no usable boundary, 400 ("body",
/// or the part's name) when the framing or a part's headers are wrong.
std::vector<FormPart> parse_multipart(std::string_view content_type, std::string_view body,
                                      const MultipartLimits& limits = {});

/// A positive decimal id from a path or query parameter, without a sign or leading zeros; HttpError 400
/// (field) otherwise.
std::int64_t parse_id(const std::string& text, const std::string& field = "id");

}  // namespace uavcover::server
