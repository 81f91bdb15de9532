// The PostgreSQL store: libpq, parameterised SQL only, a small connection pool. Several servers share
// one database: the job queue is claimed with SELECT ... FOR UPDATE SKIP LOCKED and leases whose times
// come from the database's clock; migrations run under a transaction-scoped advisory lock.
#include <algorithm>
#include <numeric>
#include <type_traits>

#include "store/backends.hpp"
#include "store/catalog_seed.hpp"
#include "store/pg_pool.hpp"

namespace uavcover::store {
namespace {

using pg::exec;
using pg::integer;
using pg::null;
using pg::Param;
using pg::real;
using pg::Result;
using pg::text;

// Unix milliseconds from the database's clock, so leases agree between servers.
#define NOW_MS "(extract(epoch from clock_timestamp()) * 1000)::bigint"
// updated_ms moves forward on every change, even within one millisecond (the event stream polls it)
#define BUMP_UPDATED "updated_ms = GREATEST(" NOW_MS ", updated_ms + 1)"

constexpr std::int64_t kMigrationLock = 0x7561766376657221;  // "uavcver!"
constexpr std::int64_t kCacheLock = 0x7561766361636821;      // "uavcach!": writers of the export cache
constexpr std::int64_t kEnqueueLock = 0x7561766371756575;    // "uavcqueu"
constexpr std::size_t kPoolSize = 8;

// ---- migrations ----

const char* const kSchemaV1 = R"sql(
CREATE TABLE missions (
  id BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
  name TEXT NOT NULL,
  latest_revision INTEGER NOT NULL,
  min_lon DOUBLE PRECISION NOT NULL,
  min_lat DOUBLE PRECISION NOT NULL,
  max_lon DOUBLE PRECISION NOT NULL,
  max_lat DOUBLE PRECISION NOT NULL,
  created_ms BIGINT NOT NULL,
  updated_ms BIGINT NOT NULL
);
CREATE TABLE mission_revisions (
  mission_id BIGINT NOT NULL REFERENCES missions(id) ON DELETE CASCADE,
  revision INTEGER NOT NULL,
  name TEXT NOT NULL,
  document TEXT NOT NULL,
  source TEXT NOT NULL,
  min_lon DOUBLE PRECISION NOT NULL,
  min_lat DOUBLE PRECISION NOT NULL,
  max_lon DOUBLE PRECISION NOT NULL,
  max_lat DOUBLE PRECISION NOT NULL,
  created_ms BIGINT NOT NULL,
  PRIMARY KEY (mission_id, revision)
);
CREATE TABLE jobs (
  id BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
  kind TEXT NOT NULL CHECK (kind IN ('plan', 'study', 'comparison')),
  mission_id BIGINT NOT NULL REFERENCES missions(id),
  revision INTEGER NOT NULL,
  params TEXT NOT NULL,
  state TEXT NOT NULL CHECK (state IN ('queued', 'running', 'done', 'failed', 'cancelled')),
  progress DOUBLE PRECISION NOT NULL DEFAULT 0,
  stage TEXT NOT NULL DEFAULT '',
  attempts INTEGER NOT NULL DEFAULT 0,
  completions INTEGER NOT NULL DEFAULT 0,
  cancel_requested BOOLEAN NOT NULL DEFAULT false,
  worker TEXT NOT NULL DEFAULT '',
  lease_expires_ms BIGINT,
  created_ms BIGINT NOT NULL,
  started_ms BIGINT NOT NULL DEFAULT 0,
  finished_ms BIGINT NOT NULL DEFAULT 0,
  updated_ms BIGINT NOT NULL,
  result TEXT NOT NULL DEFAULT '{}',
  error TEXT NOT NULL DEFAULT 'null'
);
CREATE INDEX jobs_open ON jobs (created_ms, id) WHERE state IN ('queued', 'running');
CREATE INDEX jobs_mission ON jobs (mission_id);
CREATE TABLE blobs (
  sha256 TEXT PRIMARY KEY,
  size BIGINT NOT NULL,
  data BYTEA NOT NULL
);
CREATE TABLE job_artifacts (
  job_id BIGINT NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
  name TEXT NOT NULL,
  media_type TEXT NOT NULL,
  sha256 TEXT NOT NULL REFERENCES blobs(sha256),
  size BIGINT NOT NULL,
  PRIMARY KEY (job_id, name)
);
CREATE INDEX job_artifacts_blob ON job_artifacts (sha256);
CREATE TABLE catalog (
  id BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
  kind TEXT NOT NULL CHECK (kind IN ('uav', 'camera')),
  name TEXT NOT NULL,
  data TEXT NOT NULL,
  updated_ms BIGINT NOT NULL
);
CREATE INDEX catalog_kind ON catalog (kind, id);
CREATE TABLE meta (
  key TEXT PRIMARY KEY,
  value TEXT NOT NULL
);
)sql";

// Migration 3: flights of done plans (docs/flights.md) and their logs; both go with their plan job.
const char* const kSchemaV3 = R"sql(
CREATE TABLE flights (
  id BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
  plan_id BIGINT NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
  mission_id BIGINT NOT NULL REFERENCES missions(id) ON DELETE CASCADE,
  state TEXT NOT NULL,
  config TEXT NOT NULL,
  snapshot TEXT NOT NULL,
  simulated BOOLEAN NOT NULL DEFAULT false,
  log_seq BIGINT NOT NULL DEFAULT 0,
  created_ms BIGINT NOT NULL,
  updated_ms BIGINT NOT NULL
);
CREATE INDEX flights_plan ON flights (plan_id, created_ms);
CREATE INDEX flights_mission ON flights (mission_id);
CREATE INDEX flights_active ON flights (id) WHERE state NOT IN ('done', 'aborted');
CREATE TABLE flight_log (
  flight_id BIGINT NOT NULL REFERENCES flights(id) ON DELETE CASCADE,
  seq BIGINT NOT NULL,
  t_ms BIGINT NOT NULL,
  uav TEXT NOT NULL,
  kind TEXT NOT NULL,
  data TEXT NOT NULL,
  PRIMARY KEY (flight_id, seq)
);
)sql";

// Migration 4: outputs on demand (issue 27, docs/cache.md), as the SQLite backend's: the export cache,
// and the exports older versions stored with each plan job go with the blobs nothing refers to.
const char* const kSchemaV4 = R"sql(
CREATE TABLE export_cache (
  key TEXT NOT NULL,
  name TEXT NOT NULL,
  media_type TEXT NOT NULL,
  sha256 TEXT NOT NULL REFERENCES blobs(sha256),
  size BIGINT NOT NULL,
  used BIGINT NOT NULL,  -- the order of use: the greatest was used last
  PRIMARY KEY (key, name)
);
CREATE INDEX export_cache_used ON export_cache (used, key);
CREATE INDEX export_cache_blob ON export_cache (sha256);
DELETE FROM job_artifacts WHERE job_id IN (SELECT id FROM jobs WHERE kind = 'plan')
  AND (left(name, 7) = 'export/' OR left(name, 11) = 'trajectory/');
DELETE FROM blobs b WHERE NOT EXISTS (SELECT 1 FROM job_artifacts a WHERE a.sha256 = b.sha256);
)sql";

// Migration 5: elevation models uploaded to the server (issue 31), as the SQLite backend's.
const char* const kSchemaV5 = R"sql(
CREATE TABLE dems (
  id BIGSERIAL PRIMARY KEY,
  name TEXT NOT NULL,
  sha256 TEXT NOT NULL UNIQUE,
  size BIGINT NOT NULL,
  info TEXT NOT NULL,
  data BYTEA NOT NULL,
  created_ms BIGINT NOT NULL
);
)sql";

Id insert_entry(PGconn* c, const char* kind, const std::string& name, const nlohmann::json& data) {
  return exec(c,
              "INSERT INTO catalog (kind, name, data, updated_ms) VALUES ($1, $2, $3, " NOW_MS
              ") RETURNING id",
              {text(kind), text(name), text(data.dump())})
      .i64(0, 0);
}

// Migration 2: the UAV and camera catalogs the first start offers (store/catalog_seed.hpp, the same
// table as the SQLite backend's).
void seed_catalogs(PGconn* c) {
  catalog_seed::seed([c](const char* kind, std::string_view name, const nlohmann::json& data) {
    return insert_entry(c, kind, std::string(name), data);
  });
}

struct Migration {
  int version;
  void (*apply)(PGconn*);
};

const Migration kMigrations[] = {
    {1, [](PGconn* c) { pg::exec_script(c, kSchemaV1); }},
    {2, seed_catalogs},
    {3, [](PGconn* c) { pg::exec_script(c, kSchemaV3); }},
    {4, [](PGconn* c) { pg::exec_script(c, kSchemaV4); }},
    {5, [](PGconn* c) { pg::exec_script(c, kSchemaV5); }},
};
constexpr int kLatestVersion = 5;

// ---- rows ----

nlohmann::json parse_json(const std::string& s) {
  auto j = nlohmann::json::parse(s, nullptr, false);
  if (j.is_discarded()) throw StoreError("database: a stored JSON value is corrupt");
  return j;
}

const char* kind_name(CatalogKind kind) { return kind == CatalogKind::Uav ? "uav" : "camera"; }

#define JOB_COLUMNS                                                                         \
  "id, kind, mission_id, revision, params, state, progress, stage, attempts, completions, " \
  "cancel_requested, "                                                                      \
  "worker, created_ms, started_ms, finished_ms, updated_ms, result, error"

Job job_from(const Result& r, int row) {
  Job j;
  j.id = r.i64(row, 0);
  j.kind = job_kind_from_string(r.str(row, 1));
  j.mission_id = r.i64(row, 2);
  j.revision = r.i32(row, 3);
  j.params = parse_json(r.str(row, 4));
  j.state = job_state_from_string(r.str(row, 5));
  j.progress = r.f64(row, 6);
  j.stage = r.str(row, 7);
  j.attempts = r.i32(row, 8);
  j.completions = r.i32(row, 9);
  j.cancel_requested = r.boolean(row, 10);
  j.worker = r.str(row, 11);
  j.created_ms = r.i64(row, 12);
  j.started_ms = r.i64(row, 13);
  j.finished_ms = r.i64(row, 14);
  j.updated_ms = r.i64(row, 15);
  j.result = parse_json(r.str(row, 16));
  j.error = parse_json(r.str(row, 17));
  return j;
}

#define FLIGHT_COLUMNS \
  "id, plan_id, mission_id, state, config, snapshot, simulated, created_ms, updated_ms, log_seq"

StoredFlight flight_from(const Result& r, int row) {
  StoredFlight f;
  f.id = r.i64(row, 0);
  f.plan_id = r.i64(row, 1);
  f.mission_id = r.i64(row, 2);
  f.state = r.str(row, 3);
  f.config = parse_json(r.str(row, 4));
  f.snapshot = parse_json(r.str(row, 5));
  f.simulated = r.boolean(row, 6);
  f.created_ms = r.i64(row, 7);
  f.updated_ms = r.i64(row, 8);
  f.log_records = r.i64(row, 9);
  return f;
}

/// JSON text for a column; text the vehicles sent (STATUSTEXT) may not be UTF-8: replaced, not thrown.
std::string dump(const nlohmann::json& j) {
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

CatalogEntry entry_from(const Result& r, int row) {
  return CatalogEntry{r.i64(row, 0), r.str(row, 1), parse_json(r.str(row, 2)), r.i64(row, 3)};
}

class PostgresStore final : public Store {
 public:
  explicit PostgresStore(const std::string& uri) : pool_(uri, kPoolSize) { migrate(); }

  [[nodiscard]] std::string backend() const override { return "postgresql"; }

  bool ping() noexcept override {
    try {
      return read([](PGconn* c) { return exec(c, "SELECT 1").rows() == 1; });
    } catch (...) {
      return false;
    }
  }

  [[nodiscard]] int schema_version() override {
    return read([](PGconn* c) {
      return exec(c, "SELECT coalesce(max(version), 0) FROM schema_migrations").i32(0, 0);
    });
  }

  // ---- missions ----

  Id create_mission(const NewRevision& rev) override {
    return transaction([&](PGconn* c) {
      const auto m = exec(c,
                          "INSERT INTO missions (name, latest_revision, min_lon, min_lat, max_lon, max_lat, "
                          "created_ms, updated_ms) VALUES ($1, 1, $2, $3, $4, $5, " NOW_MS ", " NOW_MS
                          ") RETURNING id, created_ms",
                          {text(rev.name), real(rev.bbox.min_lon), real(rev.bbox.min_lat),
                           real(rev.bbox.max_lon), real(rev.bbox.max_lat)});
      insert_revision(c, m.i64(0, 0), 1, rev, m.i64(0, 1));
      return m.i64(0, 0);
    });
  }

  int add_revision(Id mission, const NewRevision& rev) override {
    return transaction([&](PGconn* c) {
      const auto m =
          exec(c,
               "UPDATE missions SET latest_revision = latest_revision + 1, name = $2, min_lon = $3, "
               "min_lat = $4, max_lon = $5, max_lat = $6, " BUMP_UPDATED
               " WHERE id = $1 RETURNING latest_revision, updated_ms",
               {integer(mission), text(rev.name), real(rev.bbox.min_lon), real(rev.bbox.min_lat),
                real(rev.bbox.max_lon), real(rev.bbox.max_lat)});
      if (m.rows() == 0) throw NotFound("mission " + std::to_string(mission) + " does not exist");
      const int revision = m.i32(0, 0);
      insert_revision(c, mission, revision, rev, m.i64(0, 1));
      return revision;
    });
  }

  std::optional<MissionRevision> get_mission(Id mission, std::optional<int> revision) override {
    return read([&](PGconn* c) -> std::optional<MissionRevision> {
      const auto r =
          exec(c,
               "SELECT m.id, r.revision, m.latest_revision, r.name, r.document, r.source, r.min_lon, "
               "r.min_lat, r.max_lon, r.max_lat, m.created_ms, r.created_ms FROM missions m "
               "JOIN mission_revisions r ON r.mission_id = m.id "
               "AND r.revision = coalesce($2::integer, m.latest_revision) WHERE m.id = $1",
               {integer(mission), revision ? integer(*revision) : null()});
      if (r.rows() == 0) return std::nullopt;
      MissionRevision out;
      out.mission_id = r.i64(0, 0);
      out.revision = r.i32(0, 1);
      out.latest_revision = r.i32(0, 2);
      out.name = r.str(0, 3);
      out.document = r.str(0, 4);
      out.source = r.str(0, 5);
      out.bbox = {r.f64(0, 6), r.f64(0, 7), r.f64(0, 8), r.f64(0, 9)};
      out.created_ms = r.i64(0, 10);
      out.revised_ms = r.i64(0, 11);
      return out;
    });
  }

  MissionPage list_missions(const MissionQuery& query) override {
    const int limit = std::clamp(query.limit, 1, 1000);
    const auto& box = query.intersects;
    return read([&](PGconn* c) {
      const auto r =
          exec(c,
               "SELECT id, name, latest_revision, min_lon, min_lat, max_lon, max_lat, created_ms, updated_ms "
               "FROM missions WHERE id > $1 "
               "AND ($2::text IS NULL OR position(lower($2::text) IN lower(name)) > 0) "
               "AND ($3::float8 IS NULL OR (min_lon <= $5::float8 AND max_lon >= $3::float8 "
               "AND min_lat <= $6::float8 AND max_lat >= $4::float8)) "
               "ORDER BY id LIMIT $7",
               {integer(query.after), query.name_contains ? text(*query.name_contains) : null(),
                box ? real(box->min_lon) : null(), box ? real(box->min_lat) : null(),
                box ? real(box->max_lon) : null(), box ? real(box->max_lat) : null(), integer(limit + 1)});
      MissionPage page;
      const int n = std::min(r.rows(), limit);
      for (int i = 0; i < n; ++i)
        page.items.push_back(MissionSummary{r.i64(i, 0), r.str(i, 1), r.i32(i, 2),
                                            Bbox{r.f64(i, 3), r.f64(i, 4), r.f64(i, 5), r.f64(i, 6)},
                                            r.i64(i, 7), r.i64(i, 8)});
      if (r.rows() > limit) page.next_after = page.items.back().id;
      return page;
    });
  }

  void delete_mission(Id mission) override {
    transaction([&](PGconn* c) {
      // the row lock waits for enqueues that reference the mission (they hold FOR KEY SHARE)
      if (exec(c, "SELECT 1 FROM missions WHERE id = $1 FOR UPDATE", {integer(mission)}).rows() == 0)
        throw NotFound("mission " + std::to_string(mission) + " does not exist");
      if (exec(c, "SELECT 1 FROM jobs WHERE mission_id = $1 AND state IN ('queued', 'running') LIMIT 1",
               {integer(mission)})
              .rows() > 0)
        throw Conflict("mission " + std::to_string(mission) + " has queued or running jobs");
      if (const auto f =
              exec(c,
                   "SELECT id FROM flights WHERE mission_id = $1 AND state NOT IN ('done', 'aborted') "
                   "LIMIT 1",
                   {integer(mission)});
          f.rows() > 0)
        throw Conflict("mission " + std::to_string(mission) + " has a flight that is not done or aborted (" +
                       std::to_string(f.i64(0, 0)) + ")");
      std::vector<std::string> shas;
      const auto b = exec(c,
                          "SELECT DISTINCT a.sha256 FROM job_artifacts a JOIN jobs j ON j.id = a.job_id "
                          "WHERE j.mission_id = $1",
                          {integer(mission)});
      for (int i = 0; i < b.rows(); ++i) shas.push_back(b.str(i, 0));
      exec(c, "DELETE FROM jobs WHERE mission_id = $1", {integer(mission)});
      exec(c, "DELETE FROM missions WHERE id = $1", {integer(mission)});
      collect(c, shas);  // blobs no other job and no cache entry refers to any more
      return true;
    });
  }

  [[nodiscard]] std::int64_t count_missions() override {
    return read([](PGconn* c) { return exec(c, "SELECT count(*) FROM missions").i64(0, 0); });
  }

  // ---- jobs ----

  Id enqueue(const NewJob& job, int max_queued) override {
    return transaction([&](PGconn* c) {
      if (exec(c, "SELECT 1 FROM missions WHERE id = $1 FOR KEY SHARE", {integer(job.mission_id)}).rows() ==
          0)
        throw NotFound("mission " + std::to_string(job.mission_id) + " does not exist");
      if (exec(c, "SELECT 1 FROM mission_revisions WHERE mission_id = $1 AND revision = $2",
               {integer(job.mission_id), integer(job.revision)})
              .rows() == 0)
        throw NotFound("mission " + std::to_string(job.mission_id) + " has no revision " +
                       std::to_string(job.revision));
      // one enqueue at a time across servers, so the queue never grows past max_queued
      exec(c, "SELECT pg_advisory_xact_lock($1)", {integer(kEnqueueLock)});
      if (exec(c, "SELECT count(*) FROM jobs WHERE state = 'queued'").i64(0, 0) >= max_queued)
        throw QueueFull("the job queue is full (" + std::to_string(max_queued) + " jobs queued)");
      return exec(c,
                  "INSERT INTO jobs (kind, mission_id, revision, params, state, created_ms, updated_ms) "
                  "VALUES ($1, $2, $3, $4, 'queued', " NOW_MS ", " NOW_MS ") RETURNING id",
                  {text(to_string(job.kind)), integer(job.mission_id), integer(job.revision),
                   text(job.params.dump())})
          .i64(0, 0);
    });
  }

  std::optional<Job> get_job(Id id) override {
    return transaction([&](PGconn* c) -> std::optional<Job> {
      const auto r = exec(c, "SELECT " JOB_COLUMNS " FROM jobs WHERE id = $1", {integer(id)});
      if (r.rows() == 0) return std::nullopt;
      Job job = job_from(r, 0);
      const auto a =
          exec(c, "SELECT name, media_type, sha256, size FROM job_artifacts WHERE job_id = $1 ORDER BY name",
               {integer(id)});
      for (int i = 0; i < a.rows(); ++i)
        job.artifacts.push_back(ArtifactRef{a.str(i, 0), a.str(i, 1), a.str(i, 2), a.i64(i, 3)});
      return job;
    });
  }

  std::vector<Job> get_jobs(const std::vector<Id>& ids) override {
    if (ids.empty()) return {};
    std::string array = "{";
    for (std::size_t i = 0; i < ids.size(); ++i) array += (i ? "," : "") + std::to_string(ids[i]);
    array += "}";
    return read([&](PGconn* c) {
      const auto r =
          exec(c, "SELECT " JOB_COLUMNS " FROM jobs WHERE id = ANY($1::bigint[]) ORDER BY id", {text(array)});
      std::vector<Job> out;
      for (int i = 0; i < r.rows(); ++i) out.push_back(job_from(r, i));
      return out;
    });
  }

  std::vector<Job> list_jobs(Id mission, JobKind kind, int limit) override {
    return read([&](PGconn* c) {
      const auto r = exec(c,
                          "SELECT " JOB_COLUMNS
                          " FROM jobs WHERE mission_id = $1 AND kind = $2 "
                          "ORDER BY created_ms DESC, id DESC LIMIT $3",
                          {integer(mission), text(to_string(kind)), integer(std::clamp(limit, 1, 1000))});
      std::vector<Job> out;
      for (int i = 0; i < r.rows(); ++i) out.push_back(job_from(r, i));
      return out;
    });
  }

  std::optional<Job> claim_job(const std::string& worker, std::chrono::milliseconds lease,
                               int max_attempts) override {
    max_attempts = std::max(max_attempts, 1);
    return transaction([&](PGconn* c) -> std::optional<Job> {
      for (;;) {
        const auto r = exec(c,
                            "SELECT id, attempts, cancel_requested FROM jobs WHERE state = 'queued' "
                            "OR (state = 'running' AND lease_expires_ms < " NOW_MS
                            ") ORDER BY created_ms, id LIMIT 1 FOR UPDATE SKIP LOCKED");
        if (r.rows() == 0) return std::nullopt;
        const Id id = r.i64(0, 0);
        const int attempts = r.i32(0, 1);
        if (r.boolean(0, 2)) {  // cancelled while its worker was gone
          exec(c,
               "UPDATE jobs SET state = 'cancelled', worker = '', lease_expires_ms = NULL, finished_ms "
               "= " NOW_MS ", " BUMP_UPDATED " WHERE id = $1",
               {integer(id)});
          continue;
        }
        if (interrupted_too_often(attempts, max_attempts)) {
          exec(c,
               "UPDATE jobs SET state = 'failed', error = $2, worker = '', lease_expires_ms = NULL, "
               "finished_ms = " NOW_MS ", " BUMP_UPDATED " WHERE id = $1",
               {integer(id), text(interrupted_error(attempts).dump())});
          continue;
        }
        const auto j =
            exec(c,
                 "UPDATE jobs SET state = 'running', worker = $2, attempts = attempts + 1, "
                 "lease_expires_ms = " NOW_MS " + $3, started_ms = CASE WHEN started_ms = 0 THEN " NOW_MS
                 " ELSE started_ms END, " BUMP_UPDATED
                 ", progress = 0, stage = '' WHERE id = $1 RETURNING " JOB_COLUMNS,
                 {integer(id), text(worker), integer(lease.count())});
        return job_from(j, 0);
      }
    });
  }

  LeaseStatus heartbeat(Id job, const std::string& worker, std::chrono::milliseconds lease, double progress,
                        const std::string& stage) override {
    if (!(progress >= 0.0)) progress = 0.0;  // NaN too
    progress = std::min(progress, 1.0);
    return transaction([&](PGconn* c) {
      const auto r = exec(c,
                          "UPDATE jobs SET lease_expires_ms = " NOW_MS
                          " + $3, progress = $4, stage = $5, "
                          "" BUMP_UPDATED
                          " WHERE id = $1 AND state = 'running' AND worker = $2 RETURNING cancel_requested",
                          {integer(job), text(worker), integer(lease.count()), real(progress), text(stage)});
      if (r.rows() == 0) return LeaseStatus{false, false};
      return LeaseStatus{true, r.boolean(0, 0)};
    });
  }

  bool finish_job(Id job, const std::string& worker, JobState state, const nlohmann::json& result,
                  const nlohmann::json& error, const Artifacts& artifacts) override {
    if (!terminal(state))
      throw std::invalid_argument("finish_job: the state must be done, failed or cancelled");
    // blobs in one order (by content) so two finishing jobs sharing blobs cannot deadlock
    std::vector<std::size_t> order(artifacts.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return artifacts[a].bytes < artifacts[b].bytes; });
    return transaction([&](PGconn* c) {
      // done after a cancel request (a DELETE while the worker was storing): recorded cancelled, with no
      // result and no artifacts
      const auto r =
          exec(c,
               "UPDATE jobs SET "
               "state = CASE WHEN $3::text = 'done' AND cancel_requested THEN 'cancelled' ELSE $3::text END, "
               "result = CASE WHEN $3::text = 'done' AND cancel_requested THEN '{}' ELSE $4 END, error = $5, "
               "progress = CASE WHEN $3::text = 'done' AND NOT cancel_requested THEN 1 ELSE progress END, "
               "completions = completions + 1, worker = '', lease_expires_ms = NULL, finished_ms = " NOW_MS
               ", " BUMP_UPDATED " WHERE id = $1 AND state = 'running' AND worker = $2 RETURNING state",
               {integer(job), text(worker), text(to_string(state)), text(result.dump()), text(error.dump())});
      if (r.rows() == 0) return false;
      if (job_state_from_string(r.str(0, 0)) != state) return true;  // cancelled: no artifacts
      for (const std::size_t i : order) {
        const Artifact& a = artifacts[i];
        // the key is the SHA-256 of the bytes, computed by the database (pgcrypto-free sha256(), PG 11+)
        exec(c,
             "WITH b AS (SELECT encode(sha256($4::bytea), 'hex') AS h, $4::bytea AS d), "
             "ins AS (INSERT INTO blobs (sha256, size, data) SELECT h, length(d), d FROM b "
             "ON CONFLICT (sha256) DO NOTHING) "
             "INSERT INTO job_artifacts (job_id, name, media_type, sha256, size) "
             "SELECT $1, $2, $3, h, length(d) FROM b",
             {integer(job), text(a.name), text(a.media_type), pg::bytes(a.bytes)});
      }
      return true;
    });
  }

  JobState request_cancel(Id job) override {
    return transaction([&](PGconn* c) {
      const auto r = exec(c, "SELECT state FROM jobs WHERE id = $1 FOR UPDATE", {integer(job)});
      if (r.rows() == 0) throw NotFound("job " + std::to_string(job) + " does not exist");
      const JobState state = job_state_from_string(r.str(0, 0));
      if (state == JobState::Queued) {
        exec(c,
             "UPDATE jobs SET state = 'cancelled', cancel_requested = true, finished_ms = " NOW_MS
             ", " BUMP_UPDATED " WHERE id = $1",
             {integer(job)});
        return JobState::Cancelled;
      }
      if (state == JobState::Running)
        exec(c, "UPDATE jobs SET cancel_requested = true, " BUMP_UPDATED " WHERE id = $1", {integer(job)});
      return state;
    });
  }

  int recover_running(int max_attempts) override {
    max_attempts = std::max(max_attempts, 1);
    return transaction([&](PGconn* c) {
      exec(c,
           "UPDATE jobs SET state = 'cancelled', worker = '', lease_expires_ms = NULL, finished_ms = " NOW_MS
           ", " BUMP_UPDATED " WHERE state = 'running' AND cancel_requested");
      // interrupted_too_often() (backends.hpp), in SQL
      const auto failed =
          exec(c, "SELECT id, attempts FROM jobs WHERE state = 'running' AND attempts >= $1 FOR UPDATE",
               {integer(max_attempts)});
      for (int i = 0; i < failed.rows(); ++i)
        exec(c,
             "UPDATE jobs SET state = 'failed', error = $2, worker = '', lease_expires_ms = NULL, "
             "finished_ms = " NOW_MS ", " BUMP_UPDATED " WHERE id = $1",
             {integer(failed.i64(i, 0)), text(interrupted_error(failed.i32(i, 1)).dump())});
      return exec(c,
                  "UPDATE jobs SET state = 'queued', worker = '', lease_expires_ms = NULL, progress = 0, "
                  "stage = '', " BUMP_UPDATED " WHERE state = 'running' RETURNING id")
          .rows();
    });
  }

  [[nodiscard]] JobCounts count_jobs() override {
    return read([](PGconn* c) {
      const auto r = exec(c, "SELECT state, count(*) FROM jobs GROUP BY state");
      JobCounts n;
      for (int i = 0; i < r.rows(); ++i) {
        n.add(job_state_from_string(r.str(i, 0)), r.i64(i, 1));
      }
      return n;
    });
  }

  std::optional<Artifact> get_artifact(Id job, const std::string& name) override {
    return read([&](PGconn* c) -> std::optional<Artifact> {
      // binary results: the media type's text and the blob's raw bytes
      const auto r =
          exec(c,
               "SELECT a.media_type, b.data FROM job_artifacts a JOIN blobs b ON b.sha256 = a.sha256 "
               "WHERE a.job_id = $1 AND a.name = $2",
               {integer(job), text(name)}, true);
      if (r.rows() == 0) return std::nullopt;
      return Artifact{name, r.str(0, 0), r.str(0, 1)};
    });
  }

  // ---- retention and the export cache ----

  /// The blobs among `shas` nothing refers to any more are deleted.
  static void collect(PGconn* c, const std::vector<std::string>& shas) {
    if (shas.empty()) return;
    std::string list = "{";
    for (const auto& s : shas) list += (list.size() > 1 ? "," : "") + s;  // hex digits only
    list += "}";
    exec(c,
         "DELETE FROM blobs b WHERE b.sha256 = ANY($1::text[]) "
         "AND NOT EXISTS (SELECT 1 FROM job_artifacts a WHERE a.sha256 = b.sha256) "
         "AND NOT EXISTS (SELECT 1 FROM export_cache e WHERE e.sha256 = b.sha256)",
         {text(list)});
  }

  static void delete_job_rows(PGconn* c, Id job) {
    const auto r =
        exec(c, "SELECT name, media_type, sha256, size FROM job_artifacts WHERE job_id = $1", {integer(job)});
    std::vector<ArtifactRef> refs;
    std::vector<std::string> shas;
    std::string plan_sha, paths_sha;
    for (int i = 0; i < r.rows(); ++i) {
      refs.push_back({r.str(i, 0), r.str(i, 1), r.str(i, 2), r.i64(i, 3)});
      shas.push_back(refs.back().sha256);
      if (refs.back().name == "plan.json") plan_sha = refs.back().sha256;
      if (refs.back().name == "paths.geojson") paths_sha = refs.back().sha256;
    }
    exec(c, "DELETE FROM jobs WHERE id = $1", {integer(job)});
    const std::string prefix = plan_cache_prefix(refs);
    if (!prefix.empty() &&
        exec(c,
             "SELECT 1 FROM job_artifacts a JOIN job_artifacts b ON b.job_id = a.job_id WHERE a.name = "
             "'plan.json' AND a.sha256 = $1 AND b.name = 'paths.geojson' AND b.sha256 = $2 LIMIT 1",
             {text(plan_sha), text(paths_sha)})
                .rows() == 0) {
      const auto e =
          exec(c, "DELETE FROM export_cache WHERE left(key, 65) = $1 RETURNING sha256", {text(prefix + "/")});
      for (int i = 0; i < e.rows(); ++i) shas.push_back(e.str(i, 0));
    }
    collect(c, shas);
  }

  static void check_deletable(PGconn* c, Id job) {
    const auto r = exec(c, "SELECT state FROM jobs WHERE id = $1 FOR UPDATE", {integer(job)});
    if (r.rows() == 0) throw NotFound("job " + std::to_string(job) + " does not exist");
    const JobState state = job_state_from_string(r.str(0, 0));
    if (!terminal(state))
      throw Conflict("job " + std::to_string(job) + " is " + to_string(state) + "; cancel it first");
    const auto f = exec(c, "SELECT id FROM flights WHERE plan_id = $1 ORDER BY id LIMIT 1", {integer(job)});
    if (f.rows() > 0)
      throw Conflict("plan " + std::to_string(job) + " is used by flight " + std::to_string(f.i64(0, 0)) +
                     "; delete its flights first");
  }

  void delete_job(Id job) override {
    transaction([&](PGconn* c) {
      check_deletable(c, job);
      delete_job_rows(c, job);
      return true;
    });
  }

  std::vector<Id> prune_plans(Id mission, int keep) override {
    keep = std::max(keep, 0);
    return transaction([&](PGconn* c) {
      const auto r = exec(c,
                          "SELECT id FROM jobs j WHERE mission_id = $1 AND kind = 'plan' AND state = 'done' "
                          "AND NOT EXISTS (SELECT 1 FROM flights f WHERE f.plan_id = j.id) "
                          "AND id NOT IN (SELECT id FROM jobs WHERE mission_id = $1 AND kind = 'plan' AND "
                          "state = 'done' ORDER BY created_ms DESC, id DESC LIMIT $2) "
                          "ORDER BY created_ms, id FOR UPDATE",
                          {integer(mission), integer(keep)});
      std::vector<Id> victims;
      for (int i = 0; i < r.rows(); ++i) victims.push_back(r.i64(i, 0));
      for (const Id id : victims) delete_job_rows(c, id);
      return victims;
    });
  }

  std::int64_t collect_orphan_blobs() override {
    return transaction([](PGconn* c) {
      return static_cast<std::int64_t>(
          exec(c,
               "DELETE FROM blobs b WHERE NOT EXISTS (SELECT 1 FROM job_artifacts a WHERE a.sha256 = "
               "b.sha256) "
               "AND NOT EXISTS (SELECT 1 FROM export_cache e WHERE e.sha256 = b.sha256) RETURNING 1")
              .rows());
    });
  }

  std::optional<std::vector<ArtifactRef>> cache_entry(const std::string& key) override {
    return transaction([&](PGconn* c) -> std::optional<std::vector<ArtifactRef>> {
      const auto r = exec(c,
                          "UPDATE export_cache SET used = (SELECT max(used) + 1 FROM export_cache) "
                          "WHERE key = $1 RETURNING name, media_type, sha256, size",
                          {text(key)});
      if (r.rows() == 0) return std::nullopt;
      std::vector<ArtifactRef> refs;
      for (int i = 0; i < r.rows(); ++i) refs.push_back({r.str(i, 0), r.str(i, 1), r.str(i, 2), r.i64(i, 3)});
      std::sort(refs.begin(), refs.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
      return refs;
    });
  }

  std::optional<Artifact> cached_file(const std::string& key, const std::string& name) override {
    return read([&](PGconn* c) -> std::optional<Artifact> {
      const auto r =
          exec(c,
               "SELECT e.media_type, b.data FROM export_cache e JOIN blobs b ON b.sha256 = e.sha256 "
               "WHERE e.key = $1 AND e.name = $2",
               {text(key), text(name)}, true);
      if (r.rows() == 0) return std::nullopt;
      return Artifact{name, r.str(0, 0), r.str(0, 1)};
    });
  }

  bool put_cache(const std::string& key, const Artifacts& files, std::int64_t cap_bytes) override {
    std::int64_t total = 0;
    for (const auto& f : files) total += static_cast<std::int64_t>(f.bytes.size());
    if (files.empty() || total > cap_bytes) return false;
    std::vector<std::size_t> order(files.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return files[a].bytes < files[b].bytes; });
    return transaction([&](PGconn* c) {
      // one writer of the cache at a time across servers (the eviction reads the whole cache's size)
      exec(c, "SELECT pg_advisory_xact_lock($1)", {integer(kCacheLock)});
      std::vector<std::string> shas;
      const auto old = exec(c, "DELETE FROM export_cache WHERE key = $1 RETURNING sha256", {text(key)});
      for (int i = 0; i < old.rows(); ++i) shas.push_back(old.str(i, 0));
      const std::int64_t use = exec(c, "SELECT coalesce(max(used), 0) + 1 FROM export_cache").i64(0, 0);
      for (const std::size_t i : order) {
        const Artifact& a = files[i];
        exec(c,
             "WITH b AS (SELECT encode(sha256($4::bytea), 'hex') AS h, $4::bytea AS d), "
             "ins AS (INSERT INTO blobs (sha256, size, data) SELECT h, length(d), d FROM b "
             "ON CONFLICT (sha256) DO NOTHING) "
             "INSERT INTO export_cache (key, name, media_type, sha256, size, used) "
             "SELECT $1, $2, $3, h, length(d), $5::bigint FROM b",
             {text(key), text(a.name), text(a.media_type), pg::bytes(a.bytes), integer(use)});
      }
      std::int64_t held = exec(c, "SELECT coalesce(sum(size), 0)::bigint FROM export_cache").i64(0, 0);
      while (held > cap_bytes) {
        const auto v = exec(c,
                            "SELECT key FROM export_cache WHERE key <> $1 GROUP BY key ORDER BY max(used), "
                            "key LIMIT 1",
                            {text(key)});
        if (v.rows() == 0) break;
        const auto gone =
            exec(c, "DELETE FROM export_cache WHERE key = $1 RETURNING sha256, size", {text(v.str(0, 0))});
        for (int i = 0; i < gone.rows(); ++i) {
          shas.push_back(gone.str(i, 0));
          held -= gone.i64(i, 1);
        }
      }
      collect(c, shas);
      return true;
    });
  }

  std::pair<std::int64_t, std::int64_t> count_blobs() override {
    return read([](PGconn* c) {
      const auto r = exec(c, "SELECT count(*), coalesce(sum(size), 0)::bigint FROM blobs");
      return std::pair<std::int64_t, std::int64_t>{r.i64(0, 0), r.i64(0, 1)};
    });
  }

  std::pair<std::int64_t, std::int64_t> cache_size() override {
    return read([](PGconn* c) {
      const auto r = exec(c, "SELECT coalesce(sum(size), 0)::bigint, count(DISTINCT key) FROM export_cache");
      return std::pair<std::int64_t, std::int64_t>{r.i64(0, 0), r.i64(0, 1)};
    });
  }

  // ---- catalogs ----

  /// A UAV's camera_id names a camera that exists; FOR SHARE holds it until this transaction ends, so a
  /// camera's delete (which takes the row's lock) waits for the UAV and then sees it.
  static void check_camera_ref(PGconn* c, CatalogKind kind, const nlohmann::json& data) {
    const Id camera = camera_ref(kind, data);
    if (camera == 0) return;
    if (exec(c, "SELECT id FROM catalog WHERE kind = 'camera' AND id = $1 FOR SHARE", {integer(camera)})
            .rows() == 0)
      throw Conflict(camera_missing_text(camera));
  }

  // ---- elevation models ----

  std::pair<Id, bool> put_dem(const std::string& name, std::string_view bytes,
                              const nlohmann::json& info) override {
    return transaction([&](PGconn* c) -> std::pair<Id, bool> {
      // the key is the SHA-256 of the bytes, computed by the database as for the blobs
      const auto r =
          exec(c,
               "WITH b AS (SELECT encode(sha256($2::bytea), 'hex') AS h), "
               "ins AS (INSERT INTO dems (name, sha256, size, info, data, created_ms) "
               "SELECT $1, h, length($2::bytea), $3, $2::bytea, " NOW_MS
               " FROM b "
               "ON CONFLICT (sha256) DO NOTHING RETURNING id) "
               "SELECT id, true FROM ins UNION ALL "
               "SELECT d.id, false FROM dems d, b WHERE d.sha256 = b.h AND NOT EXISTS (SELECT 1 FROM ins)",
               {text(name), pg::bytes(bytes), text(info.dump())});
      if (r.rows() > 0) return {r.i64(0, 0), r.boolean(0, 1)};
      // another transaction stored the same bytes meanwhile: the insert waited for it and did nothing,
      // and this statement's snapshot predates it; a new statement (READ COMMITTED) sees its row
      const auto again =
          exec(c, "SELECT id FROM dems WHERE sha256 = encode(sha256($1::bytea), 'hex')", {pg::bytes(bytes)});
      if (again.rows() == 0) throw StoreError("database: the DEM was neither stored nor found");
      return {again.i64(0, 0), false};
    });
  }

  std::optional<StoredDem> get_dem(Id id) override {
    return read([&](PGconn* c) -> std::optional<StoredDem> {
      const auto r =
          exec(c, "SELECT id, name, sha256, size, info, created_ms FROM dems WHERE id = $1", {integer(id)});
      if (r.rows() == 0) return std::nullopt;
      return StoredDem{r.i64(0, 0), r.str(0, 1), r.str(0, 2), r.i64(0, 3), parse_json(r.str(0, 4)),
                       r.i64(0, 5)};
    });
  }

  std::optional<std::string> dem_bytes(Id id) override {
    return read([&](PGconn* c) -> std::optional<std::string> {
      const auto r = exec(c, "SELECT data FROM dems WHERE id = $1", {integer(id)}, true);
      if (r.rows() == 0) return std::nullopt;
      return r.str(0, 0);
    });
  }

  std::vector<StoredDem> list_dems(int limit) override {
    return read([&](PGconn* c) {
      const auto r = exec(c, "SELECT id, name, sha256, size, info, created_ms FROM dems ORDER BY id LIMIT $1",
                          {integer(std::clamp(limit, 1, 1000))});
      std::vector<StoredDem> out;
      for (int i = 0; i < r.rows(); ++i)
        out.push_back(
            {r.i64(i, 0), r.str(i, 1), r.str(i, 2), r.i64(i, 3), parse_json(r.str(i, 4)), r.i64(i, 5)});
      return out;
    });
  }

  Id create_entry(CatalogKind kind, const std::string& name, const nlohmann::json& data) override {
    return transaction([&](PGconn* c) {
      check_camera_ref(c, kind, data);
      return insert_entry(c, kind_name(kind), name, data);
    });
  }

  std::optional<CatalogEntry> get_entry(CatalogKind kind, Id id) override {
    return read([&](PGconn* c) -> std::optional<CatalogEntry> {
      const auto r = exec(c, "SELECT id, name, data, updated_ms FROM catalog WHERE kind = $1 AND id = $2",
                          {text(kind_name(kind)), integer(id)});
      if (r.rows() == 0) return std::nullopt;
      return entry_from(r, 0);
    });
  }

  std::vector<CatalogEntry> list_entries(CatalogKind kind) override {
    return read([&](PGconn* c) {
      const auto r = exec(c, "SELECT id, name, data, updated_ms FROM catalog WHERE kind = $1 ORDER BY id",
                          {text(kind_name(kind))});
      std::vector<CatalogEntry> out;
      for (int i = 0; i < r.rows(); ++i) out.push_back(entry_from(r, i));
      return out;
    });
  }

  void update_entry(CatalogKind kind, Id id, const std::string& name, const nlohmann::json& data) override {
    transaction([&](PGconn* c) {
      check_camera_ref(c, kind, data);
      if (exec(c,
               "UPDATE catalog SET name = $3, data = $4, " BUMP_UPDATED
               " WHERE kind = $1 AND id = $2 RETURNING id",
               {text(kind_name(kind)), integer(id), text(name), text(data.dump())})
              .rows() == 0)
        throw NotFound(std::string(kind_name(kind)) + " " + std::to_string(id) + " does not exist");
      return true;
    });
  }

  void delete_entry(CatalogKind kind, Id id) override {
    transaction([&](PGconn* c) {
      if (exec(c, "DELETE FROM catalog WHERE kind = $1 AND id = $2 RETURNING id",
               {text(kind_name(kind)), integer(id)})
              .rows() == 0)
        throw NotFound(std::string(kind_name(kind)) + " " + std::to_string(id) + " does not exist");
      if (kind == CatalogKind::Camera) {
        // after the delete took the row's lock (a UAV naming it committed first, or waits and then
        // finds it gone): this statement's snapshot sees every UAV that names it; one rolls it back
        const auto users = exec(c,
                                "SELECT id, name FROM catalog WHERE kind = 'uav' AND "
                                "(data::jsonb -> 'camera_id') = to_jsonb($1::bigint) ORDER BY id LIMIT 1",
                                {integer(id)});
        if (users.rows() > 0) throw Conflict(camera_in_use_text(id, users.i64(0, 0), users.str(0, 1)));
      }
      return true;
    });
  }

  // ---- flights ----

  Id create_flight(const NewFlight& flight) override {
    return transaction([&](PGconn* c) {
      // FOR KEY SHARE: the job cannot be deleted (delete_mission) before the flight is in
      const auto j = exec(c, "SELECT mission_id, kind, state FROM jobs WHERE id = $1 FOR KEY SHARE",
                          {integer(flight.plan_id)});
      if (j.rows() == 0) throw NotFound("plan " + std::to_string(flight.plan_id) + " does not exist");
      if (j.str(0, 1) != "plan" || j.str(0, 2) != "done")
        throw Conflict("job " + std::to_string(flight.plan_id) + " is not a done plan");
      return exec(c,
                  "INSERT INTO flights (plan_id, mission_id, state, config, snapshot, simulated, created_ms, "
                  "updated_ms) VALUES ($1, $2, $3, $4, $5, $6, " NOW_MS ", " NOW_MS ") RETURNING id",
                  {integer(flight.plan_id), integer(j.i64(0, 0)), text(flight.state),
                   text(dump(flight.config)), text(dump(flight.snapshot)), pg::boolean(flight.simulated)})
          .i64(0, 0);
    });
  }

  std::optional<StoredFlight> get_flight(Id flight) override {
    return read([&](PGconn* c) -> std::optional<StoredFlight> {
      const auto r = exec(c, "SELECT " FLIGHT_COLUMNS " FROM flights WHERE id = $1", {integer(flight)});
      if (r.rows() == 0) return std::nullopt;
      return flight_from(r, 0);
    });
  }

  std::vector<StoredFlight> list_flights(Id plan, int limit) override {
    return read([&](PGconn* c) {
      const auto r = exec(c,
                          "SELECT " FLIGHT_COLUMNS
                          " FROM flights WHERE plan_id = $1 ORDER BY created_ms DESC, id DESC LIMIT $2",
                          {integer(plan), integer(std::clamp(limit, 1, 1000))});
      std::vector<StoredFlight> out;
      for (int i = 0; i < r.rows(); ++i) out.push_back(flight_from(r, i));
      return out;
    });
  }

  std::vector<StoredFlight> list_active_flights() override {
    return read([&](PGconn* c) {
      const auto r = exec(
          c, "SELECT " FLIGHT_COLUMNS " FROM flights WHERE state NOT IN ('done', 'aborted') ORDER BY id");
      std::vector<StoredFlight> out;
      for (int i = 0; i < r.rows(); ++i) out.push_back(flight_from(r, i));
      return out;
    });
  }

  void update_flight(Id flight, const std::string& state, const nlohmann::json& snapshot) override {
    transaction([&](PGconn* c) {
      if (exec(c, "UPDATE flights SET state = $2, snapshot = $3, " BUMP_UPDATED " WHERE id = $1 RETURNING id",
               {integer(flight), text(state), text(dump(snapshot))})
              .rows() == 0)
        throw NotFound("flight " + std::to_string(flight) + " does not exist");
      return true;
    });
  }

  std::int64_t append_flight_log(Id flight, const std::vector<FlightLogRecord>& records) override {
    // one round trip for the batch: the records as one JSON array parameter
    nlohmann::json batch = nlohmann::json::array();
    for (const auto& r : records)
      batch.push_back({{"t", r.t_ms}, {"u", r.uav}, {"k", r.kind}, {"d", r.data}});
    const std::string batch_text = dump(batch);
    return transaction([&](PGconn* c) {
      // the row lock orders concurrent appends to one flight; the range of seqs is reserved here
      const auto r = exec(c, "UPDATE flights SET log_seq = log_seq + $2 WHERE id = $1 RETURNING log_seq",
                          {integer(flight), integer(static_cast<std::int64_t>(records.size()))});
      if (r.rows() == 0) throw NotFound("flight " + std::to_string(flight) + " does not exist");
      const std::int64_t last = r.i64(0, 0);
      if (!records.empty())
        exec(c,
             "INSERT INTO flight_log (flight_id, seq, t_ms, uav, kind, data) "
             "SELECT $1, $2 + x.n, (x.e->>'t')::bigint, x.e->>'u', x.e->>'k', (x.e->'d')::text "
             "FROM json_array_elements($3::json) WITH ORDINALITY AS x(e, n)",
             {integer(flight), integer(last - static_cast<std::int64_t>(records.size())), text(batch_text)});
      return last;
    });
  }

  FlightLogPage read_flight_log(Id flight, std::int64_t after, int limit) override {
    limit = std::clamp(limit, 1, 10000);
    return read([&](PGconn* c) {
      const auto r =
          exec(c,
               "SELECT seq, t_ms, uav, kind, data FROM flight_log WHERE flight_id = $1 AND seq > $2 "
               "ORDER BY seq LIMIT $3",
               {integer(flight), integer(after), integer(limit + 1)});
      FlightLogPage page;
      const int n = std::min(r.rows(), limit);
      for (int i = 0; i < n; ++i)
        page.items.push_back({r.i64(i, 0), r.i64(i, 1), r.str(i, 2), r.str(i, 3), parse_json(r.str(i, 4))});
      if (r.rows() > limit) page.next_after = page.items.back().seq;
      return page;
    });
  }

  void delete_flight(Id flight) override {
    transaction([&](PGconn* c) {
      if (exec(c, "DELETE FROM flights WHERE id = $1 RETURNING id", {integer(flight)}).rows() == 0)
        throw NotFound("flight " + std::to_string(flight) + " does not exist");
      return true;
    });
  }

  bool claim_first_start() override {
    return transaction([](PGconn* c) {
      return exec(c, "INSERT INTO meta (key, value) VALUES ('first_start_ms', (" NOW_MS
                     ")::text) ON CONFLICT (key) DO NOTHING RETURNING key")
                 .rows() == 1;
    });
  }

 private:
  static void insert_revision(PGconn* c, Id mission, int revision, const NewRevision& rev,
                              std::int64_t created_ms) {
    exec(c,
         "INSERT INTO mission_revisions (mission_id, revision, name, document, source, min_lon, min_lat, "
         "max_lon, max_lat, created_ms) VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10)",
         {integer(mission), integer(revision), text(rev.name), text(rev.document), text(rev.source),
          real(rev.bbox.min_lon), real(rev.bbox.min_lat), real(rev.bbox.max_lon), real(rev.bbox.max_lat),
          integer(created_ms)});
  }

  // BEGIN on a pooled connection; a connection that broke while idle (server restart) is reset and
  // BEGIN tried once more: nothing was sent yet, so that retry is safe.
  void begin(PGconn* c) {
    try {
      exec(c, "BEGIN");
    } catch (const StoreError&) {
      if (PQstatus(c) == CONNECTION_OK || !pool_.reset(c)) throw;
      exec(c, "BEGIN");
    }
  }

  // One read-only statement (autocommit: one round trip). A connection that broke while idle is reset
  // and the statement sent once more, which is safe for a read.
  template <class F>
  std::invoke_result_t<F&, PGconn*> read(F&& fn) {
    auto conn = pool_.acquire();
    PGconn* c = conn.get();
    try {
      return fn(c);
    } catch (const pg::PgError&) {
      throw;
    } catch (const StoreError&) {
      if (PQstatus(c) == CONNECTION_OK || !pool_.reset(c)) throw;
      return fn(c);
    }
  }

  // One transaction on one pooled connection; deadlocks and serialization failures are retried.
  template <class F>
  std::invoke_result_t<F&, PGconn*> transaction(F&& fn) {
    for (int attempt = 0;; ++attempt) {
      auto conn = pool_.acquire();
      PGconn* c = conn.get();
      begin(c);
      try {
        auto out = fn(c);
        exec(c, "COMMIT");
        return out;
      } catch (const pg::PgError& e) {
        if ((e.sqlstate == "40001" || e.sqlstate == "40P01") && attempt < 3)
          continue;  // rolled back on release
        throw;
      }
    }
  }

  void migrate() {
    transaction([](PGconn* c) {
      // several servers may start at once on a fresh database: one migrates, the others wait here
      exec(c, "SELECT pg_advisory_xact_lock($1)", {integer(kMigrationLock)});
      exec(c,
           "CREATE TABLE IF NOT EXISTS schema_migrations (version INTEGER PRIMARY KEY, applied_ms BIGINT NOT "
           "NULL)");
      const int current = exec(c, "SELECT coalesce(max(version), 0) FROM schema_migrations").i32(0, 0);
      if (current > kLatestVersion)
        throw StoreError("the database schema (version " + std::to_string(current) +
                         ") is newer than this uavcover understands (" + std::to_string(kLatestVersion) +
                         ")");
      for (const Migration& m : kMigrations) {
        if (m.version <= current) continue;
        m.apply(c);
        exec(c, "INSERT INTO schema_migrations (version, applied_ms) VALUES ($1, " NOW_MS ")",
             {integer(m.version)});
      }
      return true;
    });
  }

  pg::Pool pool_;
};

}  // namespace

std::unique_ptr<Store> open_postgres(const std::string& uri) {
  // refuse what libpq cannot parse without echoing it (it may hold a password)
  char* err = nullptr;
  PQconninfoOption* options = PQconninfoParse(uri.c_str(), &err);
  if (options == nullptr) {
    std::string why = err != nullptr ? pg::redact(err, uri) : "out of memory";
    PQfreemem(err);
    while (!why.empty() && why.back() == '\n') why.pop_back();
    throw StoreError("--db: not a valid PostgreSQL URI: " + why);
  }
  PQconninfoFree(options);
  return std::make_unique<PostgresStore>(uri);
}

}  // namespace uavcover::store
