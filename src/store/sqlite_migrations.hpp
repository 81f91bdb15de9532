// The SQLite schema, as ordered migrations: migration i (1-based) takes the schema to version i. Each
// is applied once, in its own transaction, and recorded in schema_migrations. Never edit a released
// migration: add a new one.
#pragma once

#include <array>
#include <string_view>

namespace uavcover::store::sqlite_schema {

/// The migration that seeds the catalogs (from store/catalog_seed.hpp, in C++).
inline constexpr int kSeedMigration = 2;

inline constexpr std::array<std::string_view, 5> kMigrations{
    // 1: missions with revisions, the job queue, artifacts over content-addressed blobs, catalogs, meta
    R"sql(
CREATE TABLE missions (
  id INTEGER PRIMARY KEY,
  name TEXT NOT NULL,
  created_ms INTEGER NOT NULL,
  updated_ms INTEGER NOT NULL,
  latest_revision INTEGER NOT NULL,
  min_lon REAL NOT NULL, min_lat REAL NOT NULL, max_lon REAL NOT NULL, max_lat REAL NOT NULL
);
CREATE INDEX missions_name ON missions(name);

CREATE TABLE mission_revisions (
  mission_id INTEGER NOT NULL REFERENCES missions(id) ON DELETE CASCADE,
  revision INTEGER NOT NULL,
  name TEXT NOT NULL,
  document TEXT NOT NULL,
  source TEXT NOT NULL,
  min_lon REAL NOT NULL, min_lat REAL NOT NULL, max_lon REAL NOT NULL, max_lat REAL NOT NULL,
  created_ms INTEGER NOT NULL,
  PRIMARY KEY (mission_id, revision)
);

CREATE TABLE jobs (
  id INTEGER PRIMARY KEY,
  kind TEXT NOT NULL CHECK (kind IN ('plan', 'study', 'comparison')),
  mission_id INTEGER NOT NULL REFERENCES missions(id) ON DELETE CASCADE,
  revision INTEGER NOT NULL,
  params TEXT NOT NULL,
  state TEXT NOT NULL CHECK (state IN ('queued', 'running', 'done', 'failed', 'cancelled')),
  progress REAL NOT NULL DEFAULT 0,
  stage TEXT NOT NULL DEFAULT '',
  attempts INTEGER NOT NULL DEFAULT 0,
  completions INTEGER NOT NULL DEFAULT 0,
  cancel_requested INTEGER NOT NULL DEFAULT 0,
  worker TEXT NOT NULL DEFAULT '',
  lease_expires_ms INTEGER NOT NULL DEFAULT 0,
  created_ms INTEGER NOT NULL,
  started_ms INTEGER NOT NULL DEFAULT 0,
  finished_ms INTEGER NOT NULL DEFAULT 0,
  updated_ms INTEGER NOT NULL,
  result TEXT NOT NULL DEFAULT '{}',
  error TEXT NOT NULL DEFAULT 'null'
);
CREATE INDEX jobs_state_created ON jobs(state, created_ms);
CREATE INDEX jobs_mission ON jobs(mission_id);

CREATE TABLE blobs (
  sha256 TEXT PRIMARY KEY,
  bytes BLOB NOT NULL
);

CREATE TABLE job_artifacts (
  job_id INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
  name TEXT NOT NULL,
  media_type TEXT NOT NULL,
  sha256 TEXT NOT NULL REFERENCES blobs(sha256),
  size INTEGER NOT NULL,
  PRIMARY KEY (job_id, name)
);
CREATE INDEX job_artifacts_sha256 ON job_artifacts(sha256);

CREATE TABLE catalog (
  id INTEGER PRIMARY KEY,
  kind TEXT NOT NULL CHECK (kind IN ('uav', 'camera')),
  name TEXT NOT NULL,
  data TEXT NOT NULL,
  updated_ms INTEGER NOT NULL
);
CREATE INDEX catalog_kind ON catalog(kind, id);

CREATE TABLE meta (
  key TEXT PRIMARY KEY,
  value TEXT NOT NULL
);
)sql",
    // 2: the catalogs' first entries, real cameras and UAVs (store/catalog_seed.hpp, the one table both
    // backends seed from): inserted by SqliteStore::migrate() after this empty script (kSeedMigration)
    R"sql(
-- the catalogs' first entries: store/catalog_seed.hpp
)sql",
    // 3: flights of done plans (docs/flights.md) and their logs; both go with their plan job
    R"sql(
CREATE TABLE flights (
  id INTEGER PRIMARY KEY,
  plan_id INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
  mission_id INTEGER NOT NULL REFERENCES missions(id) ON DELETE CASCADE,
  state TEXT NOT NULL,
  config TEXT NOT NULL,
  snapshot TEXT NOT NULL,
  simulated INTEGER NOT NULL DEFAULT 0,
  log_seq INTEGER NOT NULL DEFAULT 0,
  created_ms INTEGER NOT NULL,
  updated_ms INTEGER NOT NULL
);
CREATE INDEX flights_plan ON flights(plan_id, created_ms);
CREATE INDEX flights_mission ON flights(mission_id);
CREATE INDEX flights_active ON flights(state) WHERE state NOT IN ('done', 'aborted');

CREATE TABLE flight_log (
  flight_id INTEGER NOT NULL REFERENCES flights(id) ON DELETE CASCADE,
  seq INTEGER NOT NULL,
  t_ms INTEGER NOT NULL,
  uav TEXT NOT NULL,
  kind TEXT NOT NULL,
  data TEXT NOT NULL,
  PRIMARY KEY (flight_id, seq)
) WITHOUT ROWID;
)sql",
    // 4: outputs on demand (issue 27, docs/cache.md): a plan job stores its plan, evaluation and
    // pictures; exports are made on first request into a content-addressed cache with a size cap. The
    // exports older versions stored with each plan job go (they are made again, byte for byte, on
    // request), and so do the blobs nothing refers to any more.
    R"sql(
CREATE TABLE export_cache (
  key TEXT NOT NULL,
  name TEXT NOT NULL,
  media_type TEXT NOT NULL,
  sha256 TEXT NOT NULL REFERENCES blobs(sha256),
  size INTEGER NOT NULL,
  used INTEGER NOT NULL,  -- the order of use: the greatest was used last
  PRIMARY KEY (key, name)
);
CREATE INDEX export_cache_used ON export_cache(used, key);
CREATE INDEX export_cache_sha256 ON export_cache(sha256);
DELETE FROM job_artifacts WHERE job_id IN (SELECT id FROM jobs WHERE kind = 'plan')
  AND (substr(name, 1, 7) = 'export/' OR substr(name, 1, 11) = 'trajectory/');
DELETE FROM blobs WHERE sha256 NOT IN (SELECT sha256 FROM job_artifacts);
)sql",
    // 5: elevation models uploaded to the server (issue 31), content-addressed by their SHA-256
    R"sql(
CREATE TABLE dems (
  id INTEGER PRIMARY KEY,
  name TEXT NOT NULL,
  sha256 TEXT NOT NULL UNIQUE,
  size INTEGER NOT NULL,
  info TEXT NOT NULL,
  bytes BLOB NOT NULL,
  created_ms INTEGER NOT NULL
);
)sql",
};

}  // namespace uavcover::store::sqlite_schema
