// `uavcover serve`: the HTTP API (docs/api.md). Options are checked here; server::serve() (the API
// side, src/server/app.cpp) opens the store, starts the workers and runs the HTTP server.
#include <spdlog/spdlog.h>

#include <filesystem>
#include <thread>

#include "cli/command.hpp"
#include "cli/interrupt.hpp"
#include "cli/validators.hpp"
#include "io/plan_io.hpp"
#include "io/static_dir.hpp"
#include "server/app.hpp"
#include "uavcover/error.hpp"

namespace uavcover::cli {
namespace {

constexpr std::size_t kMinTokenLength = 16;
constexpr std::size_t kMaxStaticBytes = std::size_t{256} << 20;

struct ServeArgs {
  std::string listen = "127.0.0.1:8080";
  std::string db = "sqlite:data/uavcover.db";
  int workers = static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
  std::optional<std::string> token_file;
  std::optional<std::string> static_dir;
  std::optional<std::string> seed_dir;
  std::optional<std::string> tiles;
  std::optional<std::string> cors_origin;
  std::vector<std::string> allowed_hosts;
  std::size_t max_body = std::size_t{10} << 20;
  int max_queued = 100;
  int lease_ms = 10000;
  int keep_plans = 0;
  int export_cache_mb = 128;
  int export_threads = 2;
  std::size_t max_cells = ParseOptions{}.max_cells;
  bool log_json = false;
  std::optional<std::string> dem_dir;
};

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return "";
  const auto last = s.find_last_not_of(" \t\r\n");
  return s.substr(first, last - first + 1);
}

std::string read_token(const std::string& file) {
  const std::string token = trim(io::read_text_file(file, "--token-file", 4096));
  if (token.empty()) throw InputError("--token-file", "'" + file + "' is empty");
  if (token.size() < kMinTokenLength)
    throw InputError("--token-file", "the token in '" + file + "' is shorter than " +
                                         std::to_string(kMinTokenLength) + " characters");
  for (const char c : token)
    if (static_cast<unsigned char>(c) <= 0x20 || c == 0x7f)
      throw InputError("--token-file", "the token in '" + file + "' holds spaces or control characters");
  return token;
}

/// --cors-origin: scheme://host[:port] as a browser sends it in Origin (no path, no trailing slash).
std::string check_origin(const std::string& origin) {
  const auto scheme = origin.find("://");
  const bool ok = scheme != std::string::npos &&
                  (origin.substr(0, scheme) == "http" || origin.substr(0, scheme) == "https") &&
                  origin.size() > scheme + 3 && origin.find('/', scheme + 3) == std::string::npos &&
                  origin.find_first_of(" \t\r\n") == std::string::npos;
  if (!ok)
    throw InputError("--cors-origin",
                     "expected an origin such as https://app.example or http://localhost:5173, got '" +
                         origin.substr(0, 100) + "'");
  return origin;
}

/// --allowed-host: a host name or address as it appears in the Host header, without a port.
std::string check_allowed_host(const std::string& name) {
  std::string host;
  std::optional<std::uint16_t> port;
  if (!server::split_host(name, host, port) || port)
    throw InputError("--allowed-host",
                     "expected a host name such as uav.example.org (no scheme, no port), got '" +
                         name.substr(0, 100) + "'");
  return host;
}

void run_serve(const ServeArgs& a) {
  server::ServeOptions opt;
  opt.http.listen = a.listen;
  if (a.token_file) opt.http.token = read_token(*a.token_file);
  server::check_listen_policy(opt.http);
  opt.http.max_body = a.max_body;
  if (a.cors_origin) opt.http.cors_origin = check_origin(*a.cors_origin);
  for (const auto& h : a.allowed_hosts) opt.http.allowed_hosts.push_back(check_allowed_host(h));
  opt.http.log_json = a.log_json;
  opt.http.io_threads = 2;
  opt.http.stop = interrupt_token();
  if (a.static_dir)
    for (auto& file : io::read_static_dir(*a.static_dir, kMaxStaticBytes))
      opt.http.static_files["/" + file.name] = server::StaticFile{file.media_type, std::move(file.bytes)};
  opt.db_url = a.db;
  opt.workers = a.workers;
  if (a.seed_dir) opt.seed_dir = std::filesystem::path(*a.seed_dir);
  if (a.tiles) opt.tiles = std::filesystem::path(*a.tiles);
  opt.max_queued = a.max_queued;
  opt.lease_ms = a.lease_ms;
  opt.keep_plans = a.keep_plans;
  opt.export_cache_bytes = std::int64_t{a.export_cache_mb} << 20;
  opt.export_threads = a.export_threads;
  opt.max_cells = a.max_cells;
  if (a.dem_dir) opt.dem_dir = std::filesystem::path(*a.dem_dir);
  if (a.log_json) spdlog::set_pattern("%v");  // the request lines are whole JSON objects
  server::serve(opt);
}

const bool registered = CommandRegistry::add(60, [](CLI::App& app) {
  auto args = std::make_shared<ServeArgs>();
  auto* cmd = app.add_subcommand("serve", "Serve the HTTP API (REST + live job events; docs/api.md)");
  cmd->add_option("--listen", args->listen,
                  "Address to listen on, HOST:PORT or [IPv6]:PORT; other than loopback needs --token-file")
      ->capture_default_str();
  cmd->add_option("--db", args->db, "Database: sqlite:PATH or postgresql://...")->capture_default_str();
  cmd->add_option("--workers", args->workers, "Planning threads (default: the number of cores)")
      ->check(integer_in(1, 256));
  cmd->add_option("--token-file", args->token_file,
                  "File holding the bearer token (at least 16 characters) every request must carry");
  cmd->add_option("--static", args->static_dir, "Serve the web app: the files in this folder, read at start");
  cmd->add_option("--seed-dir", args->seed_dir, "Mission files stored when the database is first created");
  cmd->add_option(
      "--tiles", args->tiles,
      "Serve the map's tiles from this raster MBTiles file (png, jpg, webp) at /tiles/{z}/{x}/{y}; "
      "the web app then needs no internet for its map (scripts/make-tiles; docs/offline-maps.md)");
  cmd->add_option("--dem-dir", args->dem_dir,
                  "A folder of GeoTIFF or SRTM .hgt elevation tiles: missions with \"terrain\": {\"source\": "
                  "\"server\"} take their ground heights from the tiles that cover them (docs/api.md)")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--cors-origin", args->cors_origin,
                  "Allow browser requests from this origin (CORS); other foreign origins get 403");
  cmd->add_option("--allowed-host", args->allowed_hosts,
                  "A Host name served besides the listen address and localhost (behind a proxy); repeatable. "
                  "Other Host headers get 421");
  cmd->add_option("--max-cells", args->max_cells,
                  "Refuse missions whose grid needs more cells than this (422 naming the field), as "
                  "`plan --max-cells` (docs/limits.md)")
      ->capture_default_str()
      ->check(integer_in<std::size_t>(1, kMaxCellsLimit));
  cmd->add_option("--max-body", args->max_body, "Largest request body in bytes")
      ->capture_default_str()
      ->check(integer_in<std::size_t>(1024, std::size_t{1} << 30));
  cmd->add_option("--max-queued", args->max_queued, "Queued jobs beyond which new ones get 503")
      ->capture_default_str()
      ->check(integer_in(1, 1000000));
  cmd->add_option("--lease-ms", args->lease_ms,
                  "How long a job stays leased to a worker without a heartbeat (a dead server's jobs are "
                  "taken up again after it)")
      ->capture_default_str()
      ->check(integer_in(1000, 600000));
  cmd->add_option("--keep-plans", args->keep_plans,
                  "Keep each mission's newest N done plans; older ones are deleted, oldest first, except "
                  "those a flight uses (0: keep all; docs/cache.md)")
      ->capture_default_str()
      ->check(integer_in(0, 1000000));
  cmd->add_option("--export-cache-mb", args->export_cache_mb,
                  "Size cap of the export cache in MiB: exports are made on first request and cached, the "
                  "least recently used go first (docs/cache.md)")
      ->capture_default_str()
      ->check(integer_in(1, 1048576));
  cmd->add_option("--export-threads", args->export_threads, "Threads that make exports on request")
      ->capture_default_str()
      ->check(integer_in(1, 64));
  cmd->add_flag("--log-json", args->log_json, "Log one JSON object per line");
  cmd->footer(
      "Every response carries X-Request-Id; GET /healthz, /readyz and /metrics are for operations.\n"
      "SIGINT / SIGTERM stop the server: open connections are closed; running jobs are taken up again\nafter "
      "their lease (by this server's next start or another server on the same database).");
  cmd->callback([args] { run_serve(*args); });
});

}  // namespace
}  // namespace uavcover::cli
