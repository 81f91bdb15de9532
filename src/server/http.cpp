#include "server/http.hpp"

#include <boost/asio/ip/address.hpp>
#include <cctype>
#include <charconv>
#include <string_view>

namespace uavcover::server {
namespace {

std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> out;
  std::size_t pos = 0;
  while (pos < path.size()) {
    if (path[pos] == '/') {
      ++pos;
      continue;
    }
    const std::size_t end = std::min(path.find('/', pos), path.size());
    out.push_back(path.substr(pos, end - pos));
    pos = end;
  }
  return out;
}

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

/// %XX decoding; false on a malformed escape or a NUL byte.
bool percent_decode(std::string_view in, bool plus_is_space, std::string& out) {
  out.clear();
  out.reserve(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    const char c = in[i];
    if (c == '%') {
      if (i + 2 >= in.size()) return false;
      const int hi = hex_value(in[i + 1]);
      const int lo = hex_value(in[i + 2]);
      if (hi < 0 || lo < 0) return false;
      const char d = static_cast<char>(hi * 16 + lo);
      if (d == '\0') return false;
      out += d;
      i += 2;
    } else if (c == '+' && plus_is_space) {
      out += ' ';
    } else if (c == '\0') {
      return false;
    } else {
      out += c;
    }
  }
  return true;
}

bool is_param(const std::string& segment) {
  return segment.size() > 2 && segment.front() == '{' && segment.back() == '}';
}

}  // namespace

Response Response::json(int status, const nlohmann::json& body) {
  Response r;
  r.status = status;
  r.body = body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return r;
}

Response Response::error(int status, const std::string& field, const std::string& message) {
  return json(status, {{"error", {{"field", field}, {"message", message}}}});
}

void Router::add(const std::string& method, const std::string& pattern, Handler handler) {
  routes_.push_back(Route{method, pattern, split_path(pattern), std::move(handler)});
}

Router::Match Router::match(const std::string& method, const std::string& path) const {
  Match m;
  const auto segments = split_path(path);
  for (const auto& route : routes_) {
    if (route.segments.size() != segments.size()) continue;
    std::map<std::string, std::string> params;
    bool ok = true;
    for (std::size_t i = 0; i < segments.size() && ok; ++i) {
      if (is_param(route.segments[i]))
        params[route.segments[i].substr(1, route.segments[i].size() - 2)] = segments[i];
      else
        ok = route.segments[i] == segments[i];
    }
    if (!ok) continue;
    if (route.method != method) {
      m.allowed.push_back(route.method);
      continue;
    }
    m.handler = &route.handler;
    m.route = route.pattern;
    m.params = std::move(params);
    m.allowed.clear();
    return m;
  }
  return m;
}

std::vector<std::pair<std::string, std::string>> Router::routes() const {
  std::vector<std::pair<std::string, std::string>> out;
  out.reserve(routes_.size());
  for (const auto& r : routes_) out.emplace_back(r.method, r.pattern);
  return out;
}

namespace {

std::string ascii_lower(std::string_view in) {
  std::string out(in);
  for (auto& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

/// The length of an absolute-form target's "scheme://" prefix, 0 when there is none.
std::size_t scheme_length(std::string_view target) {
  const std::string head = ascii_lower(target.substr(0, 8));
  if (head.rfind("http://", 0) == 0) return 7;
  if (head.rfind("https://", 0) == 0) return 8;
  return 0;
}

}  // namespace

std::optional<std::string> target_authority(std::string_view target) {
  const std::size_t scheme = scheme_length(target);
  if (scheme == 0) return std::nullopt;
  const std::string_view rest = target.substr(scheme);
  return std::string(rest.substr(0, rest.find_first_of("/?")));
}

void decode_target(std::string_view target, Request& req) {
  std::string with_root;  // "http://host?q" becomes "/?q"
  if (const std::size_t scheme = scheme_length(target); scheme > 0) {
    const std::size_t path = target.find_first_of("/?", scheme);
    if (path == std::string_view::npos) {
      target = "/";
    } else if (target[path] == '?') {
      // "http://host?q": the path is "/" (RFC 9112 3.2.2); keep the query
      with_root = "/" + std::string(target.substr(path));
      target = with_root;
    } else {
      target = target.substr(path);
    }
  }
  if (target.empty() || target.front() != '/')
    throw HttpError(400, "path", "the request target must be a path starting with '/'");
  const auto q = target.find('?');
  if (!percent_decode(target.substr(0, q), false, req.path))
    throw HttpError(400, "path", "invalid percent-encoding (or a NUL byte) in the path");
  if (q == std::string_view::npos) return;
  std::string_view query = target.substr(q + 1);
  while (!query.empty()) {
    const auto amp = query.find('&');
    const std::string_view part = query.substr(0, amp);
    query = amp == std::string_view::npos ? std::string_view() : query.substr(amp + 1);
    if (part.empty()) continue;
    const auto eq = part.find('=');
    std::string key;
    std::string value;
    if (!percent_decode(part.substr(0, eq), true, key) ||
        (eq != std::string_view::npos && !percent_decode(part.substr(eq + 1), true, value)))
      throw HttpError(400, "query", "invalid percent-encoding (or a NUL byte) in the query");
    req.query[key] = value;
  }
}

bool is_loopback(const std::string& host) {
  if (host == "localhost") return true;
  boost::system::error_code ec;
  const auto addr = boost::asio::ip::make_address(host, ec);
  if (ec) return false;
  if (addr.is_v4()) return addr.to_v4().is_loopback();
  const auto v6 = addr.to_v6();
  if (v6.is_loopback()) return true;
  if (v6.is_v4_mapped())
    return boost::asio::ip::make_address_v4(boost::asio::ip::v4_mapped, v6).is_loopback();
  return false;
}

bool split_host(std::string_view value, std::string& host, std::optional<std::uint16_t>& port) {
  host.clear();
  port.reset();
  std::string_view name;
  std::string_view port_text;
  if (!value.empty() && value.front() == '[') {
    const auto close = value.find(']');
    if (close == std::string_view::npos) return false;
    name = value.substr(1, close - 1);
    const std::string_view rest = value.substr(close + 1);
    if (!rest.empty()) {
      if (rest.front() != ':') return false;
      port_text = rest.substr(1);
      if (port_text.empty()) return false;
    }
    boost::system::error_code ec;
    boost::asio::ip::make_address_v6(std::string(name), ec);
    if (ec) return false;
  } else {
    const auto colon = value.rfind(':');
    name = value.substr(0, colon);
    if (colon != std::string_view::npos) {
      port_text = value.substr(colon + 1);
      if (port_text.empty()) return false;
    }
    for (const char c : name)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '.' && c != '_') return false;
  }
  if (name.empty()) return false;
  if (!port_text.empty()) {
    unsigned v = 0;
    const auto [p, ec] = std::from_chars(port_text.data(), port_text.data() + port_text.size(), v);
    if (ec != std::errc() || p != port_text.data() + port_text.size() || v > 65535 || port_text.size() > 5)
      return false;
    port = static_cast<std::uint16_t>(v);
  }
  host = ascii_lower(name);
  if (host.size() > 1 && host.back() == '.') host.pop_back();
  return true;
}

bool host_allowed(std::string_view value, const HostPolicy& policy) {
  std::string host;
  std::optional<std::uint16_t> port;
  if (!split_host(value, host, port)) return false;
  for (const auto& name : policy.allowed) {
    std::string allowed = ascii_lower(name);
    if (allowed.size() > 1 && allowed.back() == '.') allowed.pop_back();
    if (host == allowed) return true;
  }
  if (port && *port != policy.port) return false;
  const std::string listen = ascii_lower(policy.listen_host);
  if (host == listen || host == "localhost" || host == "127.0.0.1" || host == "::1") return true;
  boost::system::error_code ec;
  const auto listen_addr = boost::asio::ip::make_address(listen, ec);
  if (!ec && listen_addr.is_unspecified()) {
    // listening on every address: an IP literal cannot be a rebound DNS name
    boost::asio::ip::make_address(host, ec);
    return !ec;
  }
  return false;
}

bool origin_allowed(std::string_view origin, std::string_view host,
                    const std::optional<std::string>& cors_origin) {
  const std::string o = ascii_lower(origin);
  if (o.empty() || o == "null") return false;
  if (cors_origin && o == ascii_lower(*cors_origin)) return true;
  if (host.empty()) return false;
  const std::string h = ascii_lower(host);
  return o == "http://" + h || o == "https://" + h;
}

std::string media_type(std::string_view content_type) {
  std::string media(content_type.substr(0, content_type.find(';')));
  media.erase(0, media.find_first_not_of(" \t"));
  media.erase(media.find_last_not_of(" \t") + 1);
  return ascii_lower(media);
}

namespace {

[[noreturn]] void bad_form(const std::string& field, const std::string& message) {
  throw HttpError(400, field, message);
}

// A parameter value at `pos` of a header (after "name="): a token or a quoted-string. Advances pos.
std::optional<std::string> param_value(std::string_view h, std::size_t& pos) {
  std::string v;
  if (pos < h.size() && h[pos] == '"') {
    for (++pos; pos < h.size(); ++pos) {
      if (h[pos] == '\\' && pos + 1 < h.size()) {
        v.push_back(h[++pos]);
      } else if (h[pos] == '"') {
        ++pos;
        return v;
      } else {
        v.push_back(h[pos]);
      }
    }
    return std::nullopt;  // unterminated
  }
  while (pos < h.size() && h[pos] != ';' && h[pos] != ' ' && h[pos] != '\t') v.push_back(h[pos++]);
  return v;
}

// "type; a=1; b=\"x\"" -> {a: 1, b: x} (lower-case names); nullopt when malformed.
std::optional<std::map<std::string, std::string>> header_params(std::string_view h) {
  std::map<std::string, std::string> out;
  std::size_t pos = h.find(';');
  while (pos != std::string_view::npos && pos < h.size()) {
    ++pos;  // past ';'
    while (pos < h.size() && (h[pos] == ' ' || h[pos] == '\t')) ++pos;
    if (pos == h.size()) break;
    const std::size_t eq = h.find('=', pos);
    if (eq == std::string_view::npos) return std::nullopt;
    std::string key = ascii_lower(std::string(h.substr(pos, eq - pos)));
    key.erase(key.find_last_not_of(" \t") + 1);
    pos = eq + 1;
    while (pos < h.size() && (h[pos] == ' ' || h[pos] == '\t')) ++pos;
    auto value = param_value(h, pos);
    if (!value || key.empty() || out.count(key) != 0) return std::nullopt;
    out[key] = *value;
    while (pos < h.size() && (h[pos] == ' ' || h[pos] == '\t')) ++pos;
    if (pos < h.size() && h[pos] != ';') return std::nullopt;
  }
  return out;
}

}  // namespace

std::vector<FormPart> parse_multipart(std::string_view content_type, std::string_view body,
                                      const MultipartLimits& limits) {
  if (media_type(content_type) != "multipart/form-data")
    throw HttpError(415, "content-type",
                    "expected Content-Type multipart/form-data, got \"" +
                        std::string(content_type.substr(0, 100)) + "\"");
  const auto params = header_params(content_type);
  const auto b = params ? params->find("boundary") : std::map<std::string, std::string>::const_iterator{};
  if (!params || b == params->end() || b->second.empty() || b->second.size() > 70 ||
      b->second.find_first_of("\r\n") != std::string::npos)
    throw HttpError(415, "content-type", "multipart/form-data needs a boundary of 1 to 70 characters");
  const std::string dash = "--" + b->second;
  const std::string delimiter = "\r\n" + dash;
  // the first delimiter: at the very start or after a preamble ending in CRLF
  std::size_t pos = 0;
  if (body.substr(0, dash.size()) == dash) {
    pos = dash.size();
  } else {
    const std::size_t d = body.find(delimiter);
    if (d == std::string_view::npos) bad_form("body", "no multipart boundary in the body");
    pos = d + delimiter.size();
  }
  std::vector<FormPart> parts;
  for (;;) {
    if (body.substr(pos, 2) == "--") return parts;  // the closing delimiter (an epilogue may follow)
    while (pos < body.size() && (body[pos] == ' ' || body[pos] == '\t')) ++pos;  // transport padding
    if (body.substr(pos, 2) != "\r\n") bad_form("body", "a multipart boundary must end its line with CRLF");
    pos += 2;
    if (parts.size() == limits.max_parts)
      bad_form("body", "more than " + std::to_string(limits.max_parts) + " parts");
    const std::size_t head_end = body.find("\r\n\r\n", pos);
    const bool no_headers = body.substr(pos, 2) == "\r\n";
    if (no_headers || head_end == std::string_view::npos || head_end - pos > limits.max_header_bytes)
      bad_form("body", no_headers ? "a part without a Content-Disposition header"
                                  : "a part's headers are unterminated or longer than " +
                                        std::to_string(limits.max_header_bytes) + " bytes");
    FormPart part;
    bool disposition = false;
    std::string_view head = body.substr(pos, head_end - pos);
    while (!head.empty()) {
      const std::size_t eol = std::min(head.find("\r\n"), head.size());
      const std::string_view line = head.substr(0, eol);
      head.remove_prefix(std::min(eol + 2, head.size()));
      const std::size_t colon = line.find(':');
      if (colon == std::string_view::npos || colon == 0) bad_form("body", "a malformed part header line");
      const std::string key = ascii_lower(std::string(line.substr(0, colon)));
      std::string_view value = line.substr(colon + 1);
      while (!value.empty() && (value.front() == ' ' || value.front() == '\t')) value.remove_prefix(1);
      if (key == "content-disposition") {
        if (disposition) bad_form("body", "a part with two Content-Disposition headers");
        disposition = true;
        if (media_type(value) != "form-data")
          bad_form("body", "a part's Content-Disposition must be form-data");
        const auto p = header_params(value);
        if (!p || p->count("name") == 0 || p->at("name").empty())
          bad_form("body", "a part's Content-Disposition needs a name");
        part.name = p->at("name");
        if (const auto f = p->find("filename"); f != p->end()) part.filename = f->second;
      } else if (key == "content-type") {
        part.content_type = std::string(value);
      }
    }
    if (!disposition) bad_form("body", "a part without a Content-Disposition header");
    pos = head_end + 4;
    const std::size_t end = body.find(delimiter, pos);
    if (end == std::string_view::npos) bad_form(part.name, "the part is not closed by the boundary");
    for (const auto& other : parts)
      if (other.name == part.name && part.name != limits.repeatable)
        bad_form(part.name, "the part is given twice");
    part.body = std::string(body.substr(pos, end - pos));
    parts.push_back(std::move(part));
    pos = end + delimiter.size();
  }
}

std::int64_t parse_id(const std::string& text, const std::string& field) {
  std::int64_t v = 0;
  const auto* end = text.data() + text.size();
  const auto [p, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || text.size() > 18 || text.front() < '1' || text.front() > '9' || ec != std::errc() ||
      p != end || v <= 0)
    throw HttpError(400, field, "expected a positive integer id, got \"" + text.substr(0, 40) + "\"");
  return v;
}

}  // namespace uavcover::server
