// The mission store: missions with revisions, the job queue (plans, studies, comparisons) with
// leases, job artifacts (content-addressed blobs) and the UAV and camera catalogs. One interface,
// two real backends: SQLite (embedded, the default) and PostgreSQL (several servers share one
// database and its job queue). Only src/io/ and src/store/ touch disks and databases.
//
// Every method is thread-safe (each backend keeps a pool of connections) and every write is one
// transaction: once a method returns, its write is durable (kill -9 loses nothing returned).
// Times are Unix milliseconds from the database's clock, so leases agree across servers.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "uavcover/artifact.hpp"

namespace uavcover::store {

using Id = std::int64_t;

/// The thing asked for does not exist (HTTP 404).
struct NotFound : std::runtime_error {
  using std::runtime_error::runtime_error;
};
/// The request conflicts with the current state (HTTP 409), e.g. deleting a mission with running jobs.
struct Conflict : std::runtime_error {
  using std::runtime_error::runtime_error;
};
/// The job queue holds `max_queued` jobs already (HTTP 503 with Retry-After).
struct QueueFull : std::runtime_error {
  using std::runtime_error::runtime_error;
};
/// The database failed (cannot open, disk full, connection lost): HTTP 503, exit code 1.
struct StoreError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Bbox {
  double min_lon = 0, min_lat = 0, max_lon = 0, max_lat = 0;
};

// ---- missions ----

/// What a mission revision is made of (the server parses and validates before storing).
struct NewRevision {
  std::string name;
  std::string document;  ///< the normalised mission, uavcover v1 JSON text (mission_to_json)
  std::string source;    ///< the document as submitted (JSON text), catalog references unresolved
  Bbox bbox;             ///< of the mission area, WGS84
};

struct MissionRevision {
  Id mission_id = 0;
  int revision = 0;         ///< this revision's number, 1..
  int latest_revision = 0;  ///< the mission's newest revision
  std::string name;
  std::string document;
  std::string source;
  Bbox bbox;
  std::int64_t created_ms = 0;  ///< the mission's creation
  std::int64_t revised_ms = 0;  ///< this revision's creation
};

struct MissionSummary {
  Id id = 0;
  std::string name;
  int revision = 0;  ///< latest
  Bbox bbox;
  std::int64_t created_ms = 0;
  std::int64_t updated_ms = 0;
};

struct MissionQuery {
  std::optional<std::string>
      name_contains;               ///< case-insensitive substring of the name (plain text, no wildcards)
  std::optional<Bbox> intersects;  ///< missions whose bbox intersects this one
  int limit = 50;                  ///< 1..1000
  Id after = 0;                    ///< keyset paging: ids greater than this, ascending
};

struct MissionPage {
  std::vector<MissionSummary> items;
  std::optional<Id> next_after;  ///< pass as `after` for the next page; empty on the last page
};

// ---- jobs ----

enum class JobKind { Plan, Study, Comparison };
enum class JobState { Queued, Running, Done, Failed, Cancelled };
std::string to_string(JobKind kind);
std::string to_string(JobState state);
JobKind job_kind_from_string(const std::string& s);    ///< throws std::invalid_argument
JobState job_state_from_string(const std::string& s);  ///< throws std::invalid_argument
inline bool terminal(JobState s) {
  return s == JobState::Done || s == JobState::Failed || s == JobState::Cancelled;
}

struct NewJob {
  JobKind kind = JobKind::Plan;
  Id mission_id = 0;
  int revision = 0;                                  ///< the revision planned (the latest when queued)
  nlohmann::json params = nlohmann::json::object();  ///< validated job parameters
};

struct ArtifactRef {
  std::string name;
  std::string media_type;
  std::string sha256;  ///< hex; the blob's key
  std::int64_t size = 0;
};

/// A stored elevation model (issue 31).
struct StoredDem {
  Id id = 0;
  std::string name;
  std::string sha256;  ///< hex, of its bytes
  std::int64_t size = 0;
  nlohmann::json info = nlohmann::json::object();  ///< io::DemInfo as JSON (size, extent, CRS)
  std::int64_t created_ms = 0;
};

struct Job {
  Id id = 0;
  JobKind kind = JobKind::Plan;
  Id mission_id = 0;
  int revision = 0;
  nlohmann::json params = nlohmann::json::object();
  JobState state = JobState::Queued;
  double progress = 0.0;  ///< 0..1
  std::string stage;      ///< the engine's stage name while running
  int attempts = 0;       ///< leases taken so far
  int completions = 0;    ///< successful finish_job() calls: 1 for every finished job, never more
  bool cancel_requested = false;
  std::string worker;  ///< the lease holder while running
  std::int64_t created_ms = 0, started_ms = 0, finished_ms = 0, updated_ms = 0;
  nlohmann::json result = nlohmann::json::object();  ///< metrics and warnings when done
  nlohmann::json error;                              ///< {"field","message"} when failed; null otherwise
  std::vector<ArtifactRef> artifacts;                ///< when done (get_job fills it; get_jobs does not)
};

/// What a worker learns from a heartbeat.
struct LeaseStatus {
  bool held = false;              ///< false: the lease expired and another worker may own the job
  bool cancel_requested = false;  ///< DELETE /plans/{id} arrived: stop and finish as cancelled
};

struct JobCounts {
  std::int64_t queued = 0, running = 0, done = 0, failed = 0, cancelled = 0;
  /// Adds `n` jobs in `state` to its counter.
  void add(JobState state, std::int64_t n);
};

// ---- catalogs ----

enum class CatalogKind { Uav, Camera };

struct CatalogEntry {
  Id id = 0;
  std::string name;
  nlohmann::json data = nlohmann::json::object();  ///< the entry's fields (validated by the server)
  std::int64_t updated_ms = 0;
};

// ---- flights (docs/flights.md) ----

/// A flight's state words: "created", "uploading", "ready", "flying", "paused", "done", "aborted".
/// Done and aborted are terminal: the flight is no longer followed.
inline bool flight_terminal(const std::string& state) { return state == "done" || state == "aborted"; }

struct NewFlight {
  Id plan_id = 0;  ///< a done plan job
  std::string state = "created";
  nlohmann::json config = nlohmann::json::object();    ///< flight::config_json()
  nlohmann::json snapshot = nlohmann::json::object();  ///< flight::Flight::snapshot()
  bool simulated = false;
};

struct StoredFlight {
  Id id = 0;
  Id plan_id = 0;
  Id mission_id = 0;  ///< the plan job's mission
  std::string state;
  nlohmann::json config = nlohmann::json::object();
  nlohmann::json snapshot = nlohmann::json::object();
  bool simulated = false;
  std::int64_t created_ms = 0, updated_ms = 0;
  std::int64_t log_records = 0;  ///< flight-log records appended so far (the last seq)
};

/// One flight-log record (flight::LogRecord with its sequence number).
struct FlightLogRecord {
  std::int64_t seq = 0;  ///< 1.. per flight, in append order (ignored by append_flight_log)
  std::int64_t t_ms = 0;
  std::string uav;
  std::string kind;
  nlohmann::json data = nlohmann::json::object();
};

struct FlightLogPage {
  std::vector<FlightLogRecord> items;
  std::optional<std::int64_t> next_after;  ///< pass as `after` for the next page; empty on the last page
};

class Store {
 public:
  virtual ~Store() = default;

  /// "sqlite" or "postgresql".
  [[nodiscard]] virtual std::string backend() const = 0;
  /// A round trip to the database. False instead of throwing.
  virtual bool ping() noexcept = 0;
  /// Whether a write would succeed now (readyz): the database takes a write lock within about a
  /// second, and (SQLite) its file is still the one opened. False instead of throwing.
  virtual bool writable() noexcept { return ping(); }
  /// The schema version after the migrations applied at open.
  [[nodiscard]] virtual int schema_version() = 0;

  // missions
  virtual Id create_mission(const NewRevision& rev) = 0;
  /// Adds revision latest+1 and returns its number. NotFound when the mission does not exist.
  virtual int add_revision(Id mission, const NewRevision& rev) = 0;
  /// The latest revision, or revision `revision`. Empty when the mission or revision does not exist.
  virtual std::optional<MissionRevision> get_mission(Id mission, std::optional<int> revision = {}) = 0;
  virtual MissionPage list_missions(const MissionQuery& query) = 0;
  /// Deletes the mission, its revisions, its finished jobs and their flights. Conflict while one of its
  /// jobs is queued or running, or one of its flights is not done or aborted; NotFound when it does not
  /// exist.
  virtual void delete_mission(Id mission) = 0;
  [[nodiscard]] virtual std::int64_t count_missions() = 0;

  // jobs
  /// Queues a job. QueueFull when `max_queued` jobs are queued already; NotFound for a missing mission
  /// or revision.
  virtual Id enqueue(const NewJob& job, int max_queued) = 0;
  /// The job with its artifact list, or empty.
  virtual std::optional<Job> get_job(Id job) = 0;
  /// Several jobs' states (without artifacts), for the event stream; missing ids are left out.
  virtual std::vector<Job> get_jobs(const std::vector<Id>& jobs) = 0;
  /// A mission's jobs of one kind (without artifacts), newest first (created, then id, descending),
  /// at most `limit` (clamped to 1..1000). Empty when the mission does not exist.
  virtual std::vector<Job> list_jobs(Id mission, JobKind kind, int limit) = 0;
  /// Takes the oldest job that is queued, or running with an expired lease (its worker died), and
  /// leases it to `worker` for `lease`: state running, attempts + 1. A job whose attempts reached
  /// `max_attempts` is marked failed ("the job was interrupted N times") instead and skipped.
  /// Atomic across servers (PostgreSQL: SELECT ... FOR UPDATE SKIP LOCKED).
  virtual std::optional<Job> claim_job(const std::string& worker, std::chrono::milliseconds lease,
                                       int max_attempts) = 0;
  /// Extends the lease and records progress. Not held -> the worker must drop the job silently.
  virtual LeaseStatus heartbeat(Id job, const std::string& worker, std::chrono::milliseconds lease,
                                double progress, const std::string& stage) = 0;
  /// Ends a job the worker holds: state done, failed or cancelled, with result, error and artifacts
  /// (blobs stored content-addressed, shared between jobs). Returns false and writes nothing when the
  /// lease is no longer held. At most one call per job ever succeeds.
  virtual bool finish_job(Id job, const std::string& worker, JobState state, const nlohmann::json& result,
                          const nlohmann::json& error, const Artifacts& artifacts) = 0;
  /// Cancels a queued job at once (returns Cancelled); flags a running one (returns Running, the
  /// worker stops at its next heartbeat); returns a terminal state unchanged. NotFound.
  virtual JobState request_cancel(Id job) = 0;
  /// At start of a server that owns its database alone (SQLite): running jobs are queued again, or
  /// failed when they used up `max_attempts`. Returns how many were requeued.
  virtual int recover_running(int max_attempts) = 0;
  [[nodiscard]] virtual JobCounts count_jobs() = 0;
  /// An artifact of a job: its bytes and media type. Empty when missing.
  virtual std::optional<Artifact> get_artifact(Id job, const std::string& name) = 0;

  // retention (docs/cache.md)
  /// Deletes a finished job (done, failed or cancelled) with its artifacts and, when no other job holds
  /// the same plan, the plan's export cache entries; blobs nothing refers to any more are collected.
  /// NotFound; Conflict while it is queued or running, or while a flight of it exists (its log and
  /// flown coverage refer to the plan: delete the flight first).
  virtual void delete_job(Id job) = 0;
  /// Retention: deletes the mission's done plan jobs beyond its newest `keep` (oldest first), never one
  /// a flight uses, as delete_job() does. Returns the ids deleted, oldest first.
  virtual std::vector<Id> prune_plans(Id mission, int keep) = 0;
  /// Deletes the blobs no job artifact and no cache entry refers to. Returns how many.
  virtual std::int64_t collect_orphan_blobs() = 0;
  /// The number of stored blobs and the sum of their sizes.
  [[nodiscard]] virtual std::pair<std::int64_t, std::int64_t> count_blobs() = 0;

  // the export cache: files made on demand from a stored plan, content-addressed (docs/cache.md)
  /// The files cached under `key` (names, media types, SHA-256, sizes; in name order), and the entry is
  /// marked the most recently used; empty when nothing is cached under it.
  virtual std::optional<std::vector<ArtifactRef>> cache_entry(const std::string& key) = 0;
  /// One file of a cache entry, or empty.
  virtual std::optional<Artifact> cached_file(const std::string& key, const std::string& name) = 0;
  /// Stores `files` under `key` (replacing what it held) in one transaction, then evicts the least
  /// recently used other entries while the cache holds more than `cap_bytes` (the sum of its files'
  /// sizes), and collects their blobs. An entry larger than the cap on its own is not stored.
  /// Returns whether it was stored.
  virtual bool put_cache(const std::string& key, const Artifacts& files, std::int64_t cap_bytes) = 0;
  /// The sum of the sizes of the cached files, and the number of entries.
  [[nodiscard]] virtual std::pair<std::int64_t, std::int64_t> cache_size() = 0;

  // catalogs
  virtual Id create_entry(CatalogKind kind, const std::string& name, const nlohmann::json& data) = 0;
  virtual std::optional<CatalogEntry> get_entry(CatalogKind kind, Id id) = 0;
  virtual std::vector<CatalogEntry> list_entries(CatalogKind kind) = 0;
  virtual void update_entry(CatalogKind kind, Id id, const std::string& name, const nlohmann::json& data) = 0;
  virtual void delete_entry(CatalogKind kind, Id id) = 0;  ///< NotFound

  // flights
  /// Stores a new flight of a plan job. NotFound when the job does not exist; Conflict when it is not a
  /// done plan.
  virtual Id create_flight(const NewFlight& flight) = 0;
  virtual std::optional<StoredFlight> get_flight(Id flight) = 0;
  /// A plan's flights, newest first, at most `limit` (clamped to 1..1000).
  virtual std::vector<StoredFlight> list_flights(Id plan, int limit) = 0;
  /// Every flight that is not done or aborted, oldest first (a server re-attaches them at start).
  virtual std::vector<StoredFlight> list_active_flights() = 0;
  /// Records the flight's state and snapshot. NotFound.
  virtual void update_flight(Id flight, const std::string& state, const nlohmann::json& snapshot) = 0;
  /// Appends records in one transaction (all or none), numbered after the last; returns the last seq.
  /// NotFound when the flight does not exist (e.g. deleted meanwhile).
  virtual std::int64_t append_flight_log(Id flight, const std::vector<FlightLogRecord>& records) = 0;
  /// Records with seq > `after`, in order, at most `limit` (clamped to 1..10000).
  virtual FlightLogPage read_flight_log(Id flight, std::int64_t after, int limit) = 0;
  /// Deletes the flight and its log. NotFound. (delete_mission deletes its missions' flights with its
  /// jobs, and refuses with Conflict while one of them is not done or aborted.)
  virtual void delete_flight(Id flight) = 0;

  // elevation models (issue 31, docs/api.md "Elevation models"): GeoTIFFs uploaded with
  // POST /api/v1/dems, content-addressed by their SHA-256
  /// Stores `bytes` under their SHA-256: the same bytes again give the stored DEM's id (created false).
  virtual std::pair<Id, bool> put_dem(const std::string& name, std::string_view bytes,
                                      const nlohmann::json& info) = 0;
  /// A DEM's description (no bytes), or empty.
  virtual std::optional<StoredDem> get_dem(Id id) = 0;
  /// A DEM's bytes, or empty.
  virtual std::optional<std::string> dem_bytes(Id id) = 0;
  /// Every stored DEM, oldest first, at most `limit` (clamped to 1..1000).
  virtual std::vector<StoredDem> list_dems(int limit) = 0;

  /// True exactly once per database: the caller then seeds it (example missions). Atomic.
  virtual bool claim_first_start() = 0;
};

/// The export cache's key prefix of a plan job: the SHA-256 of its plan.json and paths.geojson blobs
/// (hex, 64 characters), so that two jobs with the same plan share their exports; empty when the job
/// has not both. Cache keys are "<prefix>/<format>".
std::string plan_cache_prefix(const std::vector<ArtifactRef>& artifacts);

/// Opens (and migrates) a store: "sqlite:PATH" (the folder is created), "sqlite::memory:" for tests,
/// or a libpq URI "postgresql://..." / "postgres://...". StoreError with the reason when it cannot.
std::unique_ptr<Store> open_store(const std::string& url);

}  // namespace uavcover::store
