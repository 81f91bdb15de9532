// Exports on demand (issue 27, docs/cache.md): a plan job stores its plan; every export format is made
// from the stored plan.json and paths.geojson when it is first asked for, on a bounded pool of its own
// (never on an I/O or handler thread's own account: the handler waits for the pool), once for any
// number of concurrent first requests, and kept in the store's content-addressed export cache under
// a size cap (least recently used entries go first).
#pragma once

#include <boost/asio/thread_pool.hpp>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "server/terrain_source.hpp"
#include "store/store.hpp"
#include "uavcover/artifact.hpp"
#include "usecases/plan_outputs.hpp"

namespace uavcover::server {

struct ExportConfig {
  int threads = 2;                                         ///< the pool's threads (--export-threads)
  std::int64_t cache_cap_bytes = std::int64_t{128} << 20;  ///< the cache's size cap (--export-cache-mb)
  /// Test hook: called on the pool before each build with the cache key (a test holds a build here).
  std::function<void(const std::string& key)> before_build;
  /// `serve --dem-dir` (issue 31): a terrain plan's ground comes from its stored DEM or these tiles.
  DemDir dem_dir = {};
};

/// One export format of one plan: the files' names, its warnings or its refusal.
struct ExportEntry {
  std::string key;                     ///< "<plan prefix>/<format>"
  std::vector<std::string> names;      ///< export/<id>.<ext>, trajectory/<id>.csv, ...
  std::vector<std::string> warnings;   ///< the exporter's
  std::string refused_field, refused;  ///< when the format refuses the plan
  /// The files, when just built (and possibly not cached: over the cap, or the store failed).
  std::shared_ptr<const Artifacts> files;
};

class ExportService {
 public:
  ExportService(store::Store& store, ExportConfig config);
  ~ExportService();  ///< waits for the builds under way
  ExportService(const ExportService&) = delete;
  ExportService& operator=(const ExportService&) = delete;

  /// Export format `format` (exporting::known_formats(): "kml" also holds the .kmz) of the done plan job
  /// `job`: from the cache, else built on the pool and cached. Concurrent callers for the same plan and
  /// format share one build. Null when the job has no stored plan.json and paths.geojson to make it from
  /// (a plan stored before exports were made on request). Throws StoreError. `variant`: the client's
  /// export options (autopilot, terrain frame, capacity split), each variant its own cache entry.
  std::shared_ptr<const ExportEntry> get(const store::Job& job, const std::string& format,
                                         const usecases::ExportVariant& variant = {});
  /// The file `name` of an entry get() gave (built again when the cache evicted it meanwhile), or empty
  /// when the entry has no such file (or the plan no longer has its stored files).
  std::optional<Artifact> read(const ExportEntry& entry, const store::Job& job, const std::string& format,
                               const std::string& name, const usecases::ExportVariant& variant = {});

  /// Builds done since start (tests: concurrent first requests build once).
  [[nodiscard]] std::int64_t builds() const;
  /// Callers waiting for the build of `key` right now (tests).
  [[nodiscard]] int waiting(const std::string& key) const;

 private:
  std::shared_ptr<const ExportEntry> build(const store::Job& job, const std::string& key,
                                           const std::string& format, const usecases::ExportVariant& variant);
  std::shared_ptr<const ExportEntry> from_cache(const std::string& key);

  store::Store& store_;
  ExportConfig config_;
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_future<std::shared_ptr<const ExportEntry>>> inflight_;
  std::map<std::string, int> waiting_;
  std::int64_t builds_ = 0;
  boost::asio::thread_pool pool_;
};

}  // namespace uavcover::server
