// serve(): the store, the seed missions of a new database, the API router, the job events, the
// planning workers and the HTTP server, wired together.
#include "server/app.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <thread>

#include "io/folder.hpp"
#include "io/mbtiles.hpp"
#include "io/plan_io.hpp"
#include "json/strict.hpp"
#include "server/api.hpp"
#include "server/events.hpp"
#include "server/exports.hpp"
#include "server/flights.hpp"
#include "server/metrics.hpp"
#include "server/worker.hpp"
#include "uavcover/error.hpp"

namespace uavcover::server {
namespace {

/// Job events straight from the database, so a client sees jobs other servers run; flights from the
/// FlightManager (live ones from memory, the others as stored).
class StoreEvents : public EventSource {
 public:
  StoreEvents(store::Store& store, FlightManager& flights) : store_(store), flights_(flights) {}
  std::vector<nlohmann::json> snapshot(const std::vector<std::int64_t>& job_ids) override {
    std::vector<nlohmann::json> out;
    try {
      for (const auto& job : store_.get_jobs(job_ids)) out.push_back(job_json(job, false));
    } catch (const std::exception& e) {
      spdlog::warn("job events: {}", e.what());
    }
    return out;
  }
  std::vector<nlohmann::json> flights(const std::vector<std::int64_t>& ids) override {
    try {
      return flights_.get_many(ids);
    } catch (const std::exception& e) {
      spdlog::warn("flight events: {}", e.what());
      return {};
    }
  }

 private:
  store::Store& store_;
  FlightManager& flights_;
};

/// Stores every mission file of the folder; files that cannot be read or are not valid missions are
/// skipped with a warning.
void seed_missions(store::Store& store, const std::filesystem::path& dir, const ParseOptions& parse) {
  int stored = 0;
  for (const auto& file : io::list_json_files(dir, "--seed-dir")) {
    try {
      const auto doc = strict::parse_json(io::read_text_file(file, "--seed-dir"), file.filename().string());
      store.create_mission(prepare_mission(doc, store, parse));
      ++stored;
    } catch (const InputError& e) {
      spdlog::warn("seed mission {} skipped: {}", file.string(), e.what());
    }
  }
  spdlog::info("seeded {} mission(s) from {}", stored, dir.string());
}

}  // namespace

void serve(const ServeOptions& options) {
  // the tiles first: a file that is not a raster MBTiles stops the start (InputError naming --tiles)
  std::shared_ptr<io::MbTiles> tiles;
  if (options.tiles) {
    tiles = io::MbTiles::open(*options.tiles, "--tiles",
                              static_cast<std::size_t>(std::max(1, options.http.handler_threads)));
    const auto& i = tiles->info();
    spdlog::info("map tiles: {} ({}, zoom {}..{})", options.tiles->string(), i.format, i.minzoom, i.maxzoom);
  }
  std::unique_ptr<store::Store> store;
  try {
    store = store::open_store(options.db_url);
  } catch (const store::StoreError& e) {
    throw OperationError(std::string("cannot open the database: ") + e.what());
  }
  spdlog::info("database: {} (schema version {})", store->backend(), store->schema_version());
  constexpr int kMaxAttempts = 3;
  try {
    if (store->backend() == "sqlite") {
      // this server owns the database alone: the jobs it ran when it stopped are queued again
      const int requeued = store->recover_running(kMaxAttempts);
      if (requeued > 0) spdlog::info("{} interrupted job(s) queued again", requeued);
    }
    if (store->claim_first_start() && options.seed_dir)
      seed_missions(*store, *options.seed_dir, ParseOptions{options.max_cells});
    // blobs nothing refers to (left by an older version's deletions) go
    if (const auto orphans = store->collect_orphan_blobs(); orphans > 0)
      spdlog::info("{} orphan blob(s) collected", orphans);
  } catch (const store::StoreError& e) {
    // the first writes: a database that opens but cannot be written fails here, not as "internal error"
    throw OperationError("cannot write the " + store->backend() + " database: " + e.what());
  }

  FlightLimits flight_limits;
  flight_limits.allow_remote = options.http.token.has_value();  // vehicles beyond loopback need the token
  flight_limits.dem_dir = options.dem_dir;
  FlightManager flights(*store, flight_limits);
  flights.start();  // the flights that were flying when the server stopped are followed again
  ExportConfig ec;
  ec.threads = options.export_threads;
  ec.cache_cap_bytes = options.export_cache_bytes;
  ec.dem_dir = options.dem_dir;
  ExportService exports(*store, ec);
  ApiContext ctx{*store, ApiConfig{}, &flights, &exports, tiles.get()};
  ctx.config.max_queued = options.max_queued;
  ctx.config.parse.max_cells = options.max_cells;
  ctx.config.dem_dir = options.dem_dir;
  ctx.config.max_body_bytes = options.http.max_body;
  ctx.config.planner_threads = options.workers > 0
                                   ? options.workers
                                   : static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
  Router router;
  add_api_routes(router, ctx);
  StoreEvents events(*store, flights);

  set_job_counts_provider([&store]() -> std::map<std::string, std::int64_t> {
    const store::JobCounts c = store->count_jobs();
    return {{"queued", c.queued},
            {"running", c.running},
            {"done", c.done},
            {"failed", c.failed},
            {"cancelled", c.cancelled}};
  });

  ServerConfig http = options.http;
  http.ready_check = [&store] { return store->writable(); };

  WorkerConfig wc;
  wc.threads = options.workers > 0 ? options.workers
                                   : static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
  wc.lease = std::chrono::milliseconds(std::max(options.lease_ms, 100));
  wc.max_attempts = kMaxAttempts;
  wc.keep_plans = options.keep_plans;
  wc.parse = ctx.config.parse;
  wc.dem_dir = options.dem_dir;
  wc.on_job_finished = [](const store::Job& job, store::JobState state, double seconds) {
    if (job.kind == store::JobKind::Plan && state == store::JobState::Done) observe_plan_duration(seconds);
  };

  HttpServer server(http, router, events);  // binds first: a busy port starts no worker
  WorkerPool workers(*store, wc);
  workers.start();
  // the URL on stdout, once the port is bound (scripts and tests read this line; port 0 picks one)
  const ListenAddress where = parse_listen(http.listen);
  const std::string host = where.host.find(':') != std::string::npos ? "[" + where.host + "]" : where.host;
  std::printf("uavcover: serving on http://%s:%u (database: %s)\n", host.c_str(),
              static_cast<unsigned>(server.port()), store->backend().c_str());
  std::fflush(stdout);
  server.run();
  spdlog::info("stopping: running jobs are left for the next lease");
  workers.stop();
  flights.stop();
  set_job_counts_provider(nullptr);
}

}  // namespace uavcover::server
