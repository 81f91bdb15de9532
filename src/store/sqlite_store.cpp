// The SQLite store: one writer connection behind a mutex (writes are serialised by SQLite anyway, and
// queueing them here avoids busy-waiting between our own threads) and a pool of reader connections
// (WAL lets them read while the writer writes). Every write is one BEGIN IMMEDIATE transaction with
// synchronous=FULL, so a returned write survives kill -9 and power loss. ":memory:" has one connection
// for everything (each connection to :memory: is a database of its own).
#include <spdlog/spdlog.h>
#include <sqlite3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <optional>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <string_view>
#include <unordered_map>

#include "store/backends.hpp"
#include "store/catalog_seed.hpp"
#include "store/sha256.hpp"
#include "store/sqlite_migrations.hpp"

namespace uavcover::store {
namespace {

constexpr int kBusyTimeoutMs = 5000;
constexpr int kProbeBusyTimeoutMs = 1000;  // writable(): how long the probe waits for the write lock
constexpr std::size_t kMaxReaders = 8;

std::int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// the column values of the enums are the API's words (store.cpp)
JobKind kind_of(const std::string& s) {
  try {
    return job_kind_from_string(s);
  } catch (const std::invalid_argument&) {
    throw StoreError("sqlite: unknown job kind in the database");
  }
}
JobState state_of(const std::string& s) {
  try {
    return job_state_from_string(s);
  } catch (const std::invalid_argument&) {
    throw StoreError("sqlite: unknown job state in the database");
  }
}
const char* catalog_text(CatalogKind k) { return k == CatalogKind::Uav ? "uav" : "camera"; }

nlohmann::json parse_column(const std::string& text) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception&) {
    throw StoreError("sqlite: malformed JSON in the database");
  }
}

// ---- connections and statements ----

class Connection {
 public:
  Connection(const std::string& path, bool memory) {
    const int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX;
    const int rc = sqlite3_open_v2(path.c_str(), &db_, flags, nullptr);
    if (rc != SQLITE_OK) {
      const std::string why = db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(rc);
      sqlite3_close_v2(db_);
      db_ = nullptr;
      throw StoreError("cannot open the SQLite database " + path + ": " + why);
    }
    sqlite3_extended_result_codes(db_, 1);
    sqlite3_busy_timeout(db_, kBusyTimeoutMs);
    try {
      exec("PRAGMA foreign_keys = ON");
      if (!memory) {
        exec("PRAGMA journal_mode = WAL");
        exec("PRAGMA synchronous = FULL");
        // a checkpointed WAL is cut back to this size, so one large write does not keep its size
        exec("PRAGMA journal_size_limit = 16777216");
      }
    } catch (const StoreError& e) {
      sqlite3_close_v2(db_);  // the destructor does not run for a throwing constructor
      throw StoreError("cannot open the SQLite database " + path + ": " + e.what());
    }
  }
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;
  ~Connection() {
    for (auto& [sql, stmt] : cache_) sqlite3_finalize(stmt);
    sqlite3_close_v2(db_);
  }

  sqlite3* db() const { return db_; }

  [[noreturn]] void fail(const char* what) const {
    throw StoreError(std::string("sqlite: ") + what + ": " + sqlite3_errmsg(db_));
  }

  void exec(const char* sql) {
    char* err = nullptr;
    if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
      const std::string why = err ? err : sqlite3_errmsg(db_);
      sqlite3_free(err);
      throw StoreError("sqlite: " + why);
    }
  }

  sqlite3_stmt* prepare(const char* sql) {
    auto it = cache_.find(sql);
    if (it != cache_.end()) return it->second;
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v3(db_, sql, -1, SQLITE_PREPARE_PERSISTENT, &stmt, nullptr) != SQLITE_OK)
      fail("prepare");
    cache_.emplace(sql, stmt);
    return stmt;
  }

 private:
  sqlite3* db_ = nullptr;
  std::unordered_map<std::string, sqlite3_stmt*> cache_;
};

/// A cached prepared statement in use: bind, step, read columns; reset when it goes out of scope.
class Query {
 public:
  Query(Connection& c, const char* sql) : c_(c), s_(c.prepare(sql)) {}
  Query(const Query&) = delete;
  Query& operator=(const Query&) = delete;
  ~Query() {
    sqlite3_reset(s_);
    sqlite3_clear_bindings(s_);
  }

  Query& bind(int i, std::int64_t v) { return check(sqlite3_bind_int64(s_, i, v)); }
  Query& bind(int i, int v) { return check(sqlite3_bind_int(s_, i, v)); }
  Query& bind(int i, double v) { return check(sqlite3_bind_double(s_, i, v)); }
  Query& bind(int i, std::string_view v) {
    return check(sqlite3_bind_text64(s_, i, v.data(), v.size(), SQLITE_STATIC, SQLITE_UTF8));
  }
  Query& bind(int i, const std::string& v) { return bind(i, std::string_view(v)); }
  Query& bind(int i, std::string&& v) = delete;  // bound without a copy: it must outlive the step
  Query& bind(int i, const char* v) { return bind(i, std::string_view(v)); }
  Query& bind_blob(int i, std::string_view v) {
    return check(sqlite3_bind_blob64(s_, i, v.empty() ? "" : v.data(), v.size(), SQLITE_STATIC));
  }
  Query& bind_null(int i) { return check(sqlite3_bind_null(s_, i)); }

  /// True when a row is there to read, false when done.
  bool step() {
    const int rc = sqlite3_step(s_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    c_.fail("step");
  }
  /// Runs a statement that returns no rows; the number of rows it changed.
  int run() {
    while (step()) {
    }
    return sqlite3_changes(c_.db());
  }

  std::int64_t i64(int col) const { return sqlite3_column_int64(s_, col); }
  int i32(int col) const { return sqlite3_column_int(s_, col); }
  double dbl(int col) const { return sqlite3_column_double(s_, col); }
  std::string text(int col) const {
    const auto* p = sqlite3_column_text(s_, col);
    const int n = sqlite3_column_bytes(s_, col);
    return p ? std::string(reinterpret_cast<const char*>(p), static_cast<std::size_t>(n)) : std::string();
  }
  std::string blob(int col) const {
    const void* p = sqlite3_column_blob(s_, col);
    const int n = sqlite3_column_bytes(s_, col);
    return p ? std::string(static_cast<const char*>(p), static_cast<std::size_t>(n)) : std::string();
  }

 private:
  Query& check(int rc) {
    if (rc != SQLITE_OK) c_.fail("bind");
    return *this;
  }
  Connection& c_;
  sqlite3_stmt* s_;
};

/// A transaction: rolled back unless committed.
class Transaction {
 public:
  Transaction(Connection& c, bool write) : c_(c) { c_.exec(write ? "BEGIN IMMEDIATE" : "BEGIN"); }
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  ~Transaction() {
    if (open_) sqlite3_exec(c_.db(), "ROLLBACK", nullptr, nullptr, nullptr);
  }
  void commit() {
    c_.exec("COMMIT");
    open_ = false;
  }

 private:
  Connection& c_;
  bool open_ = true;
};

// ---- SQL ----

#define UAVCOVER_JOB_COLUMNS                                                                \
  "id, kind, mission_id, revision, params, state, progress, stage, attempts, completions, " \
  "cancel_requested, worker, created_ms, started_ms, finished_ms, updated_ms, result, error FROM jobs "

Job read_job(const Query& q) {
  Job j;
  j.id = q.i64(0);
  j.kind = kind_of(q.text(1));
  j.mission_id = q.i64(2);
  j.revision = q.i32(3);
  j.params = parse_column(q.text(4));
  j.state = state_of(q.text(5));
  j.progress = q.dbl(6);
  j.stage = q.text(7);
  j.attempts = q.i32(8);
  j.completions = q.i32(9);
  j.cancel_requested = q.i32(10) != 0;
  j.worker = q.text(11);
  j.created_ms = q.i64(12);
  j.started_ms = q.i64(13);
  j.finished_ms = q.i64(14);
  j.updated_ms = q.i64(15);
  j.result = parse_column(q.text(16));
  j.error = parse_column(q.text(17));
  return j;
}

#define UAVCOVER_FLIGHT_COLUMNS                                                                        \
  "id, plan_id, mission_id, state, config, snapshot, simulated, created_ms, updated_ms, log_seq FROM " \
  "flights "

StoredFlight read_flight(const Query& q) {
  StoredFlight f;
  f.id = q.i64(0);
  f.plan_id = q.i64(1);
  f.mission_id = q.i64(2);
  f.state = q.text(3);
  f.config = parse_column(q.text(4));
  f.snapshot = parse_column(q.text(5));
  f.simulated = q.i32(6) != 0;
  f.created_ms = q.i64(7);
  f.updated_ms = q.i64(8);
  f.log_records = q.i64(9);
  return f;
}

/// JSON text for a column; text the vehicles sent (STATUSTEXT) may not be UTF-8: replaced, not thrown.
std::string dump(const nlohmann::json& j) {
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::optional<Job> load_job(Connection& c, Id id) {
  Query q(c, "SELECT " UAVCOVER_JOB_COLUMNS "WHERE id = ?1");
  q.bind(1, id);
  if (!q.step()) return std::nullopt;
  return read_job(q);
}

/// `%text%` for LIKE ... ESCAPE '\': the text's own %, _ and \ match literally.
std::string like_pattern(const std::string& text) {
  std::string p = "%";
  for (char ch : text) {
    if (ch == '%' || ch == '_' || ch == '\\') p += '\\';
    p += ch;
  }
  p += '%';
  return p;
}

double clamp_progress(double p) {
  if (!(p >= 0.0)) return 0.0;  // NaN too
  return std::min(p, 1.0);
}

class SqliteStore final : public Store {
 private:
  template <class Q>
  static void bind_bbox(Q& q, int first, const Bbox& b) {
    q.bind(first, b.min_lon).bind(first + 1, b.min_lat).bind(first + 2, b.max_lon).bind(first + 3, b.max_lat);
  }

  static void insert_revision(Connection& c, Id mission, int revision, const NewRevision& rev,
                              std::int64_t now) {
    Query q(c,
            "INSERT INTO mission_revisions (mission_id, revision, name, document, source, min_lon, min_lat, "
            "max_lon, max_lat, created_ms) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)");
    q.bind(1, mission).bind(2, revision).bind(3, rev.name).bind(4, rev.document).bind(5, rev.source);
    bind_bbox(q, 6, rev.bbox);
    q.bind(10, now).run();
  }

  /// Runs `fn` in one BEGIN IMMEDIATE transaction on the writer; commits when it returns.
  template <class Fn>
  auto write(Fn&& fn) {
    std::lock_guard lock(write_mutex_);
    check_file();
    Transaction tx(*writer_, true);
    if constexpr (std::is_void_v<decltype(fn(*writer_))>) {
      fn(*writer_);
      tx.commit();
    } else {
      auto out = fn(*writer_);
      tx.commit();
      return out;
    }
  }

  /// Runs `fn` in one read transaction on a pooled reader (the writer for :memory:).
  template <class Fn>
  auto read(Fn&& fn) {
    if (memory_) {
      std::lock_guard lock(write_mutex_);
      Transaction tx(*writer_, false);
      auto out = fn(*writer_);
      tx.commit();
      return out;
    }
    std::unique_ptr<Connection> c = take_reader();
    struct Return {
      SqliteStore& s;
      std::unique_ptr<Connection>& c;
      ~Return() { s.give_back(std::move(c)); }
    } returner{*this, c};
    Transaction tx(*c, false);
    auto out = fn(*c);
    tx.commit();
    return out;
  }

  std::unique_ptr<Connection> take_reader() {
    std::unique_lock lock(pool_mutex_);
    pool_cv_.wait(lock, [&] { return !idle_.empty() || opened_ < kMaxReaders; });
    if (!idle_.empty()) {
      auto c = std::move(idle_.back());
      idle_.pop_back();
      return c;
    }
    ++opened_;
    lock.unlock();
    try {
      return std::make_unique<Connection>(path_, false);
    } catch (...) {
      lock.lock();
      --opened_;
      pool_cv_.notify_one();
      throw;
    }
  }

  void give_back(std::unique_ptr<Connection> c) {
    if (!c) return;
    {
      std::lock_guard lock(pool_mutex_);
      idle_.push_back(std::move(c));
    }
    pool_cv_.notify_one();
  }

  void migrate() {
    Connection& c = *writer_;
    c.exec(
        "CREATE TABLE IF NOT EXISTS schema_migrations (version INTEGER PRIMARY KEY, applied_at INTEGER NOT "
        "NULL)");
    const int known = static_cast<int>(sqlite_schema::kMigrations.size());
    for (int version = 1; version <= known; ++version) {
      Transaction tx(c, true);  // another process may be migrating the same file: check inside
      int current = 0;
      {
        Query q(c, "SELECT COALESCE(MAX(version), 0) FROM schema_migrations");
        q.step();
        current = q.i32(0);
      }
      if (current > known)
        throw StoreError("the SQLite database " + path_ + " has schema version " + std::to_string(current) +
                         ", newer than this uavcover knows (" + std::to_string(known) + ")");
      if (current >= version) continue;
      const std::string sql(sqlite_schema::kMigrations[static_cast<std::size_t>(version - 1)]);
      try {
        c.exec(sql.c_str());
        if (version == sqlite_schema::kSeedMigration)
          catalog_seed::seed([&c](const char* kind, std::string_view name, const nlohmann::json& data) {
            const std::string text = data.dump();
            Query q(c, "INSERT INTO catalog (kind, name, data, updated_ms) VALUES (?1, ?2, ?3, ?4)");
            q.bind(1, kind).bind(2, name).bind(3, text).bind(4, now_ms()).run();
            return static_cast<Id>(sqlite3_last_insert_rowid(c.db()));
          });
      } catch (const StoreError& e) {
        throw StoreError("schema migration " + std::to_string(version) + " failed: " + e.what());
      }
      Query q(c, "INSERT INTO schema_migrations (version, applied_at) VALUES (?1, ?2)");
      q.bind(1, version).bind(2, now_ms()).run();
      tx.commit();
    }
  }

 public:
  explicit SqliteStore(const std::string& path) : path_(path), memory_(path == ":memory:") {
    if (!memory_) {
      const auto folder = std::filesystem::path(path).parent_path();
      std::error_code ec;
      if (!folder.empty()) std::filesystem::create_directories(folder, ec);
      if (ec)
        throw StoreError("cannot create the folder of the SQLite database " + path + ": " + ec.message());
    }
    if (!memory_) check_writable_file(path_);
    writer_ = std::make_unique<Connection>(path_, memory_);
    migrate();
    if (!memory_) file_id_ = file_identity(path_);
  }

  std::string backend() const override { return "sqlite"; }

  /// The file's device and inode: a database file deleted or replaced while the server runs would take
  /// writes that vanish (an unlinked inode), so they are refused instead.
  static std::optional<std::pair<std::uintmax_t, std::uintmax_t>> file_identity(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return std::nullopt;
    return std::pair<std::uintmax_t, std::uintmax_t>{st.st_dev, st.st_ino};
  }

  void check_file() const {
    if (memory_ || !file_id_) return;
    if (file_identity(path_) != file_id_)
      throw StoreError("the SQLite database file " + path_ +
                       " was deleted or replaced while the server runs; restart it");
  }

  /// A read-only file (or folder: WAL needs the -wal and -shm files beside it) fails at start, naming it.
  static void check_writable_file(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::exists(path, ec) && ::access(path.c_str(), W_OK) != 0)
      throw StoreError("the SQLite database file " + path + " is read-only (" + std::strerror(errno) +
                       "): the server needs to write it");
    auto folder = std::filesystem::path(path).parent_path();
    if (folder.empty()) folder = ".";
    if (::access(folder.c_str(), W_OK | X_OK) != 0)
      throw StoreError("the folder " + folder.string() + " of the SQLite database " + path +
                       " is not writable (" + std::strerror(errno) +
                       "): the server writes the database's -wal and -shm files there");
  }

  bool ping() noexcept override {
    try {
      return read([](Connection& c) {
        Query q(c, "SELECT 1");
        return q.step() && q.i32(0) == 1;
      });
    } catch (...) {
      return false;
    }
  }

  bool writable() noexcept override {
    try {
      check_file();
      if (memory_) return ping();
      // a write lock on a reader connection, given back at once: fails while another connection
      // (another process's BEGIN EXCLUSIVE, or a long write) holds it
      std::unique_ptr<Connection> c = take_reader();
      struct Return {
        SqliteStore& s;
        std::unique_ptr<Connection>& c;
        ~Return() {
          sqlite3_busy_timeout(c->db(), kBusyTimeoutMs);
          s.give_back(std::move(c));
        }
      } returner{*this, c};
      sqlite3_busy_timeout(c->db(), kProbeBusyTimeoutMs);
      c->exec("BEGIN IMMEDIATE");
      c->exec("ROLLBACK");
      return true;
    } catch (const std::exception& e) {
      spdlog::warn("sqlite: {} does not take writes: {}", path_, e.what());
      return false;
    } catch (...) {
      return false;
    }
  }

  int schema_version() override {
    return read([](Connection& c) {
      Query q(c, "SELECT COALESCE(MAX(version), 0) FROM schema_migrations");
      q.step();
      return q.i32(0);
    });
  }

  // ---- missions ----

  Id create_mission(const NewRevision& rev) override {
    return write([&](Connection& c) {
      const std::int64_t now = now_ms();
      Query m(
          c,
          "INSERT INTO missions (name, created_ms, updated_ms, latest_revision, min_lon, min_lat, max_lon, "
          "max_lat) VALUES (?1, ?2, ?2, 1, ?3, ?4, ?5, ?6)");
      m.bind(1, rev.name).bind(2, now);
      bind_bbox(m, 3, rev.bbox);
      m.run();
      const Id id = sqlite3_last_insert_rowid(c.db());
      insert_revision(c, id, 1, rev, now);
      return id;
    });
  }

  int add_revision(Id mission, const NewRevision& rev) override {
    return write([&](Connection& c) {
      const std::int64_t now = now_ms();
      Query m(
          c,
          "UPDATE missions SET latest_revision = latest_revision + 1, name = ?2, updated_ms = ?3, "
          "min_lon = ?4, min_lat = ?5, max_lon = ?6, max_lat = ?7 WHERE id = ?1 RETURNING latest_revision");
      m.bind(1, mission).bind(2, rev.name).bind(3, now);
      bind_bbox(m, 4, rev.bbox);
      if (!m.step()) throw NotFound("mission " + std::to_string(mission) + " does not exist");
      const int revision = m.i32(0);
      while (m.step()) {
      }
      insert_revision(c, mission, revision, rev, now);
      return revision;
    });
  }

  std::optional<MissionRevision> get_mission(Id mission, std::optional<int> revision) override {
    return read([&](Connection& c) -> std::optional<MissionRevision> {
      Query q(c,
              "SELECT m.latest_revision, m.created_ms, r.revision, r.name, r.document, r.source, r.min_lon, "
              "r.min_lat, r.max_lon, r.max_lat, r.created_ms FROM missions m JOIN mission_revisions r ON "
              "r.mission_id = m.id AND r.revision = COALESCE(?2, m.latest_revision) WHERE m.id = ?1");
      q.bind(1, mission);
      if (revision) q.bind(2, *revision);
      if (!q.step()) return std::nullopt;
      MissionRevision r;
      r.mission_id = mission;
      r.latest_revision = q.i32(0);
      r.created_ms = q.i64(1);
      r.revision = q.i32(2);
      r.name = q.text(3);
      r.document = q.text(4);
      r.source = q.text(5);
      r.bbox = {q.dbl(6), q.dbl(7), q.dbl(8), q.dbl(9)};
      r.revised_ms = q.i64(10);
      return r;
    });
  }

  MissionPage list_missions(const MissionQuery& query) override {
    const int limit = std::clamp(query.limit, 1, 1000);
    return read([&](Connection& c) {
      Query q(c,
              "SELECT id, name, latest_revision, min_lon, min_lat, max_lon, max_lat, created_ms, updated_ms "
              "FROM missions WHERE id > ?1 AND (?2 IS NULL OR name LIKE ?2 ESCAPE '\\') AND (?3 IS NULL OR "
              "(max_lon >= ?3 AND min_lon <= ?5 AND max_lat >= ?4 AND min_lat <= ?6)) ORDER BY id LIMIT ?7");
      q.bind(1, query.after);
      const std::string pattern = query.name_contains ? like_pattern(*query.name_contains) : std::string();
      if (query.name_contains) q.bind(2, pattern);
      if (query.intersects) bind_bbox(q, 3, *query.intersects);
      q.bind(7, limit + 1);
      MissionPage page;
      while (q.step()) {
        if (static_cast<int>(page.items.size()) == limit) {
          page.next_after = page.items.back().id;
          break;
        }
        MissionSummary s;
        s.id = q.i64(0);
        s.name = q.text(1);
        s.revision = q.i32(2);
        s.bbox = {q.dbl(3), q.dbl(4), q.dbl(5), q.dbl(6)};
        s.created_ms = q.i64(7);
        s.updated_ms = q.i64(8);
        page.items.push_back(std::move(s));
      }
      return page;
    });
  }

  void delete_mission(Id mission) override {
    write([&](Connection& c) {
      {
        Query q(c, "SELECT 1 FROM missions WHERE id = ?1");
        q.bind(1, mission);
        if (!q.step()) throw NotFound("mission " + std::to_string(mission) + " does not exist");
      }
      {
        Query q(c, "SELECT id FROM jobs WHERE mission_id = ?1 AND state IN ('queued', 'running') LIMIT 1");
        q.bind(1, mission);
        if (q.step())
          throw Conflict("mission " + std::to_string(mission) + " has a queued or running job (" +
                         std::to_string(q.i64(0)) + ")");
      }
      {
        Query q(c,
                "SELECT id FROM flights WHERE mission_id = ?1 AND state NOT IN ('done', 'aborted') LIMIT 1");
        q.bind(1, mission);
        if (q.step())
          throw Conflict("mission " + std::to_string(mission) +
                         " has a flight that is not done or aborted (" + std::to_string(q.i64(0)) + ")");
      }
      std::vector<std::string> blobs;
      {
        Query q(c,
                "SELECT DISTINCT a.sha256 FROM job_artifacts a JOIN jobs j ON j.id = a.job_id "
                "WHERE j.mission_id = ?1");
        q.bind(1, mission);
        while (q.step()) blobs.push_back(q.text(0));
      }
      Query d(c, "DELETE FROM missions WHERE id = ?1");
      d.bind(1, mission).run();
      // blobs no other job and no cache entry refers to any more
      collect(c, blobs);
      return 0;
    });
  }

  std::int64_t count_missions() override {
    return read([](Connection& c) {
      Query q(c, "SELECT COUNT(*) FROM missions");
      q.step();
      return q.i64(0);
    });
  }

  // ---- jobs ----

  Id enqueue(const NewJob& job, int max_queued) override {
    return write([&](Connection& c) {
      {
        Query q(c, "SELECT 1 FROM mission_revisions WHERE mission_id = ?1 AND revision = ?2");
        q.bind(1, job.mission_id).bind(2, job.revision);
        if (!q.step())
          throw NotFound("mission " + std::to_string(job.mission_id) + " revision " +
                         std::to_string(job.revision) + " does not exist");
      }
      {
        Query q(c, "SELECT COUNT(*) FROM jobs WHERE state = 'queued'");
        q.step();
        if (q.i64(0) >= max_queued)
          throw QueueFull("the job queue is full (" + std::to_string(max_queued) + " jobs queued)");
      }
      const std::int64_t now = now_ms();
      const std::string params = job.params.dump();
      const std::string kind = to_string(job.kind);
      Query q(c,
              "INSERT INTO jobs (kind, mission_id, revision, params, state, created_ms, updated_ms) "
              "VALUES (?1, ?2, ?3, ?4, 'queued', ?5, ?5)");
      q.bind(1, kind).bind(2, job.mission_id).bind(3, job.revision).bind(4, params).bind(5, now);
      q.run();
      return static_cast<Id>(sqlite3_last_insert_rowid(c.db()));
    });
  }

  std::optional<Job> get_job(Id job) override {
    return read([&](Connection& c) -> std::optional<Job> {
      auto j = load_job(c, job);
      if (!j) return std::nullopt;
      Query q(c, "SELECT name, media_type, sha256, size FROM job_artifacts WHERE job_id = ?1 ORDER BY name");
      q.bind(1, job);
      while (q.step()) j->artifacts.push_back({q.text(0), q.text(1), q.text(2), q.i64(3)});
      return j;
    });
  }

  std::vector<Job> get_jobs(const std::vector<Id>& jobs) override {
    return read([&](Connection& c) {
      std::vector<Job> out;
      out.reserve(jobs.size());
      for (Id id : jobs)
        if (auto j = load_job(c, id)) out.push_back(std::move(*j));
      return out;
    });
  }

  std::vector<Job> list_jobs(Id mission, JobKind kind, int limit) override {
    const std::string kind_text = to_string(kind);
    return read([&](Connection& c) {
      Query q(c, "SELECT " UAVCOVER_JOB_COLUMNS
                 "WHERE mission_id = ?1 AND kind = ?2 ORDER BY created_ms DESC, id DESC LIMIT ?3");
      q.bind(1, mission).bind(2, kind_text).bind(3, static_cast<std::int64_t>(std::clamp(limit, 1, 1000)));
      std::vector<Job> out;
      while (q.step()) out.push_back(read_job(q));
      return out;
    });
  }

  std::optional<Job> claim_job(const std::string& worker, std::chrono::milliseconds lease,
                               int max_attempts) override {
    return write([&](Connection& c) -> std::optional<Job> {
      const std::int64_t now = now_ms();
      for (;;) {
        // the oldest queued job, or running one whose lease expired
        std::optional<std::pair<Id, int>> pick;
        std::int64_t pick_created = 0;
        {
          Query q(c,
                  "SELECT id, attempts, created_ms FROM jobs WHERE state = 'queued' ORDER BY created_ms, id "
                  "LIMIT 1");
          if (q.step()) {
            pick = {q.i64(0), q.i32(1)};
            pick_created = q.i64(2);
          }
        }
        {
          Query q(
              c,
              "SELECT id, attempts, created_ms FROM jobs WHERE state = 'running' AND lease_expires_ms <= ?1 "
              "ORDER BY created_ms, id LIMIT 1");
          q.bind(1, now);
          if (q.step() &&
              (!pick || q.i64(2) < pick_created || (q.i64(2) == pick_created && q.i64(0) < pick->first)))
            pick = {q.i64(0), q.i32(1)};
        }
        if (!pick) return std::nullopt;
        const auto [id, attempts] = *pick;
        if (interrupted_too_often(attempts, max_attempts)) {
          const std::string text = interrupted_error(attempts).dump();
          Query q(c,
                  "UPDATE jobs SET state = 'failed', error = ?2, worker = '', lease_expires_ms = 0, "
                  "finished_ms = ?3, updated_ms = MAX(?3, updated_ms + 1) WHERE id = ?1");
          q.bind(1, id).bind(2, text).bind(3, now).run();
          continue;
        }
        Query q(
            c,
            "UPDATE jobs SET state = 'running', attempts = attempts + 1, worker = ?2, lease_expires_ms = ?3, "
            "started_ms = CASE WHEN started_ms = 0 THEN ?4 ELSE started_ms END, "
            "updated_ms = MAX(?4, updated_ms + 1) WHERE id = ?1");
        q.bind(1, id).bind(2, worker).bind(3, now + lease.count()).bind(4, now).run();
        return load_job(c, id);
      }
    });
  }

  LeaseStatus heartbeat(Id job, const std::string& worker, std::chrono::milliseconds lease, double progress,
                        const std::string& stage) override {
    return write([&](Connection& c) {
      const std::int64_t now = now_ms();
      LeaseStatus status;
      Query q(c,
              "UPDATE jobs SET lease_expires_ms = ?3, "
              "updated_ms = CASE WHEN progress IS NOT ?4 OR stage IS NOT ?5 THEN MAX(?6, updated_ms + 1) "
              "ELSE updated_ms END, progress = ?4, stage = ?5 "
              "WHERE id = ?1 AND worker = ?2 AND state = 'running' RETURNING cancel_requested");
      q.bind(1, job).bind(2, worker).bind(3, now + lease.count()).bind(4, clamp_progress(progress));
      q.bind(5, stage).bind(6, now);
      if (q.step()) {
        status.held = true;
        status.cancel_requested = q.i32(0) != 0;
        while (q.step()) {
        }
      }
      return status;
    });
  }

  bool finish_job(Id job, const std::string& worker, JobState state, const nlohmann::json& result,
                  const nlohmann::json& error, const Artifacts& artifacts) override {
    if (!terminal(state))
      throw std::invalid_argument("finish_job: the state must be done, failed or cancelled");
    // hash outside the write lock
    std::vector<std::string> hashes;
    hashes.reserve(artifacts.size());
    for (const auto& a : artifacts) hashes.push_back(sha256_hex(a.bytes));
    const std::string result_text = result.dump();
    const std::string error_text = error.dump();
    return write([&](Connection& c) -> bool {
      const std::int64_t now = now_ms();
      JobState recorded = state;
      {
        // done after a cancel request: cancelled, with no result (and no artifacts below)
        Query q(c,
                "UPDATE jobs SET "
                "state = CASE WHEN ?3 = 'done' AND cancel_requested != 0 THEN 'cancelled' ELSE ?3 END, "
                "result = CASE WHEN ?3 = 'done' AND cancel_requested != 0 THEN '{}' ELSE ?4 END, "
                "error = ?5, completions = completions + 1, "
                "worker = '', lease_expires_ms = 0, finished_ms = ?6, updated_ms = MAX(?6, updated_ms + 1), "
                "progress = CASE WHEN ?3 = 'done' AND cancel_requested = 0 THEN 1.0 ELSE progress END "
                "WHERE id = ?1 AND worker = ?2 AND state = 'running' RETURNING state");
        const std::string state_word = to_string(state);
        q.bind(1, job).bind(2, worker).bind(3, state_word).bind(4, result_text).bind(5, error_text);
        q.bind(6, now);
        if (!q.step()) return false;  // the transaction rolls back: nothing written
        recorded = state_of(q.text(0));
      }
      if (recorded != state) return true;  // done after a cancel: cancelled, no artifacts
      for (std::size_t i = 0; i < artifacts.size(); ++i) {
        const auto& a = artifacts[i];
        bool stored = false;
        {
          Query q(c, "SELECT 1 FROM blobs WHERE sha256 = ?1");
          q.bind(1, hashes[i]);
          stored = q.step();
        }
        if (!stored) {
          Query q(c, "INSERT INTO blobs (sha256, bytes) VALUES (?1, ?2)");
          q.bind(1, hashes[i]).bind_blob(2, a.bytes).run();
        }
        Query q(
            c,
            "INSERT INTO job_artifacts (job_id, name, media_type, sha256, size) VALUES (?1, ?2, ?3, ?4, ?5) "
            "ON CONFLICT (job_id, name) DO UPDATE SET media_type = excluded.media_type, "
            "sha256 = excluded.sha256, size = excluded.size");
        q.bind(1, job).bind(2, a.name).bind(3, a.media_type).bind(4, hashes[i]);
        q.bind(5, static_cast<std::int64_t>(a.bytes.size())).run();
      }
      return true;
    });
  }

  JobState request_cancel(Id job) override {
    return write([&](Connection& c) {
      JobState state;
      {
        Query q(c, "SELECT state FROM jobs WHERE id = ?1");
        q.bind(1, job);
        if (!q.step()) throw NotFound("job " + std::to_string(job) + " does not exist");
        state = state_of(q.text(0));
      }
      const std::int64_t now = now_ms();
      if (state == JobState::Queued) {
        Query q(c,
                "UPDATE jobs SET state = 'cancelled', cancel_requested = 1, finished_ms = ?2, "
                "updated_ms = MAX(?2, updated_ms + 1) WHERE id = ?1");
        q.bind(1, job).bind(2, now).run();
        return JobState::Cancelled;
      }
      if (state == JobState::Running) {
        Query q(c,
                "UPDATE jobs SET cancel_requested = 1, updated_ms = MAX(?2, updated_ms + 1) "
                "WHERE id = ?1 AND cancel_requested = 0");
        q.bind(1, job).bind(2, now).run();
      }
      return state;
    });
  }

  int recover_running(int max_attempts) override {
    return write([&](Connection& c) {
      const std::int64_t now = now_ms();
      std::vector<std::pair<Id, int>> running;
      {
        Query q(c, "SELECT id, attempts FROM jobs WHERE state = 'running' ORDER BY id");
        while (q.step()) running.emplace_back(q.i64(0), q.i32(1));
      }
      int requeued = 0;
      for (const auto& [id, attempts] : running) {
        if (interrupted_too_often(attempts, max_attempts)) {
          const std::string text = interrupted_error(attempts).dump();
          Query q(c,
                  "UPDATE jobs SET state = 'failed', error = ?2, worker = '', lease_expires_ms = 0, "
                  "finished_ms = ?3, updated_ms = MAX(?3, updated_ms + 1) WHERE id = ?1");
          q.bind(1, id).bind(2, text).bind(3, now).run();
        } else {
          Query q(c,
                  "UPDATE jobs SET state = 'queued', worker = '', lease_expires_ms = 0, "
                  "updated_ms = MAX(?2, updated_ms + 1) WHERE id = ?1");
          q.bind(1, id).bind(2, now).run();
          ++requeued;
        }
      }
      return requeued;
    });
  }

  JobCounts count_jobs() override {
    return read([](Connection& c) {
      JobCounts n;
      Query q(c, "SELECT state, COUNT(*) FROM jobs GROUP BY state");
      while (q.step()) {
        n.add(state_of(q.text(0)), q.i64(1));
      }
      return n;
    });
  }

  std::optional<Artifact> get_artifact(Id job, const std::string& name) override {
    return read([&](Connection& c) -> std::optional<Artifact> {
      Query q(c,
              "SELECT a.media_type, b.bytes FROM job_artifacts a JOIN blobs b ON b.sha256 = a.sha256 "
              "WHERE a.job_id = ?1 AND a.name = ?2");
      q.bind(1, job).bind(2, name);
      if (!q.step()) return std::nullopt;
      return Artifact{name, q.text(0), q.blob(1)};
    });
  }

  // ---- retention and the export cache ----

  /// The blobs among `shas` nothing refers to any more are deleted.
  static void collect(Connection& c, const std::vector<std::string>& shas) {
    for (const auto& sha : shas) {
      Query b(c,
              "DELETE FROM blobs WHERE sha256 = ?1 AND NOT EXISTS (SELECT 1 FROM job_artifacts WHERE "
              "sha256 = ?1) AND NOT EXISTS (SELECT 1 FROM export_cache WHERE sha256 = ?1)");
      b.bind(1, sha).run();
    }
  }

  /// Deletes a terminal job without flights (checked by the caller), its artifacts, its plan's cache
  /// entries when no other job holds that plan, and the blobs left without a reference.
  static void delete_job_rows(Connection& c, Id job) {
    std::vector<ArtifactRef> refs;
    {
      Query q(c, "SELECT name, media_type, sha256, size FROM job_artifacts WHERE job_id = ?1");
      q.bind(1, job);
      while (q.step()) refs.push_back({q.text(0), q.text(1), q.text(2), q.i64(3)});
    }
    std::vector<std::string> shas;
    for (const auto& r : refs) shas.push_back(r.sha256);
    {
      Query d(c, "DELETE FROM jobs WHERE id = ?1");
      d.bind(1, job).run();
    }
    const std::string prefix = plan_cache_prefix(refs);
    const std::string like = prefix + "/";
    if (!prefix.empty()) {
      std::string plan_sha, paths_sha;
      for (const auto& r : refs) {
        if (r.name == "plan.json") plan_sha = r.sha256;
        if (r.name == "paths.geojson") paths_sha = r.sha256;
      }
      Query other(
          c,
          "SELECT 1 FROM job_artifacts a JOIN job_artifacts b ON b.job_id = a.job_id "
          "WHERE a.name = 'plan.json' AND a.sha256 = ?1 AND b.name = 'paths.geojson' AND b.sha256 = ?2 "
          "LIMIT 1");
      other.bind(1, plan_sha).bind(2, paths_sha);
      if (!other.step()) {
        {
          Query q(c, "SELECT sha256 FROM export_cache WHERE substr(key, 1, 65) = ?1");
          q.bind(1, like);
          while (q.step()) shas.push_back(q.text(0));
        }
        Query d(c, "DELETE FROM export_cache WHERE substr(key, 1, 65) = ?1");
        d.bind(1, like).run();
      }
    }
    collect(c, shas);
  }

  /// Conflict unless the job is terminal and no flight of it exists; NotFound.
  static void check_deletable(Connection& c, Id job) {
    Query q(c, "SELECT state FROM jobs WHERE id = ?1");
    q.bind(1, job);
    if (!q.step()) throw NotFound("job " + std::to_string(job) + " does not exist");
    const JobState state = job_state_from_string(q.text(0));
    if (!terminal(state))
      throw Conflict("job " + std::to_string(job) + " is " + to_string(state) + "; cancel it first");
    Query f(c, "SELECT id FROM flights WHERE plan_id = ?1 ORDER BY id LIMIT 1");
    f.bind(1, job);
    if (f.step())
      throw Conflict("plan " + std::to_string(job) + " is used by flight " + std::to_string(f.i64(0)) +
                     "; delete its flights first");
  }

  void delete_job(Id job) override {
    write([&](Connection& c) {
      check_deletable(c, job);
      delete_job_rows(c, job);
      return 0;
    });
  }

  std::vector<Id> prune_plans(Id mission, int keep) override {
    keep = std::max(keep, 0);
    return write([&](Connection& c) {
      std::vector<Id> victims;
      {
        // the done plans beyond the newest `keep`, oldest first, without flights
        Query q(
            c,
            "SELECT id FROM jobs j WHERE mission_id = ?1 AND kind = 'plan' AND state = 'done' "
            "AND NOT EXISTS (SELECT 1 FROM flights f WHERE f.plan_id = j.id) "
            "AND id NOT IN (SELECT id FROM jobs WHERE mission_id = ?1 AND kind = 'plan' AND state = 'done' "
            "ORDER BY created_ms DESC, id DESC LIMIT ?2) ORDER BY created_ms, id");
        q.bind(1, mission).bind(2, static_cast<std::int64_t>(keep));
        while (q.step()) victims.push_back(q.i64(0));
      }
      for (const Id id : victims) delete_job_rows(c, id);
      return victims;
    });
  }

  std::int64_t collect_orphan_blobs() override {
    return write([](Connection& c) {
      Query q(c,
              "DELETE FROM blobs WHERE sha256 NOT IN (SELECT sha256 FROM job_artifacts) AND sha256 NOT IN "
              "(SELECT sha256 FROM export_cache)");
      q.run();
      return static_cast<std::int64_t>(sqlite3_changes64(c.db()));
    });
  }

  std::optional<std::vector<ArtifactRef>> cache_entry(const std::string& key) override {
    return write([&](Connection& c) -> std::optional<std::vector<ArtifactRef>> {
      std::vector<ArtifactRef> refs;
      {
        Query q(c, "SELECT name, media_type, sha256, size FROM export_cache WHERE key = ?1 ORDER BY name");
        q.bind(1, key);
        while (q.step()) refs.push_back({q.text(0), q.text(1), q.text(2), q.i64(3)});
      }
      if (refs.empty()) return std::nullopt;
      Query u(c, "UPDATE export_cache SET used = (SELECT MAX(used) + 1 FROM export_cache) WHERE key = ?1");
      u.bind(1, key).run();
      return refs;
    });
  }

  std::optional<Artifact> cached_file(const std::string& key, const std::string& name) override {
    return read([&](Connection& c) -> std::optional<Artifact> {
      Query q(c,
              "SELECT e.media_type, b.bytes FROM export_cache e JOIN blobs b ON b.sha256 = e.sha256 "
              "WHERE e.key = ?1 AND e.name = ?2");
      q.bind(1, key).bind(2, name);
      if (!q.step()) return std::nullopt;
      return Artifact{name, q.text(0), q.blob(1)};
    });
  }

  bool put_cache(const std::string& key, const Artifacts& files, std::int64_t cap_bytes) override {
    std::int64_t total = 0;
    std::vector<std::string> hashes;
    for (const auto& f : files) {
      total += static_cast<std::int64_t>(f.bytes.size());
      hashes.push_back(sha256_hex(f.bytes));
    }
    if (files.empty() || total > cap_bytes) return false;
    return write([&](Connection& c) {
      std::vector<std::string> shas;
      {
        Query q(c, "SELECT sha256 FROM export_cache WHERE key = ?1");
        q.bind(1, key);
        while (q.step()) shas.push_back(q.text(0));
        Query d(c, "DELETE FROM export_cache WHERE key = ?1");
        d.bind(1, key).run();
      }
      std::int64_t use = 0;
      {
        Query q(c, "SELECT COALESCE(MAX(used), 0) + 1 FROM export_cache");
        q.step();
        use = q.i64(0);
      }
      for (std::size_t i = 0; i < files.size(); ++i) {
        {
          Query q(c, "INSERT INTO blobs (sha256, bytes) VALUES (?1, ?2) ON CONFLICT (sha256) DO NOTHING");
          q.bind(1, hashes[i]).bind_blob(2, files[i].bytes).run();
        }
        Query q(c,
                "INSERT INTO export_cache (key, name, media_type, sha256, size, used) VALUES "
                "(?1, ?2, ?3, ?4, ?5, ?6)");
        q.bind(1, key).bind(2, files[i].name).bind(3, files[i].media_type).bind(4, hashes[i]);
        q.bind(5, static_cast<std::int64_t>(files[i].bytes.size())).bind(6, use).run();
      }
      // least recently used entries go while the cache is over its cap
      std::int64_t held = 0;
      {
        Query q(c, "SELECT COALESCE(SUM(size), 0) FROM export_cache");
        q.step();
        held = q.i64(0);
      }
      while (held > cap_bytes) {
        std::string victim;
        {
          Query q(
              c, "SELECT key FROM export_cache WHERE key <> ?1 GROUP BY key ORDER BY MAX(used), key LIMIT 1");
          q.bind(1, key);
          if (!q.step()) break;
          victim = q.text(0);
        }
        {
          Query q(c, "SELECT sha256, size FROM export_cache WHERE key = ?1");
          q.bind(1, victim);
          while (q.step()) {
            shas.push_back(q.text(0));
            held -= q.i64(1);
          }
        }
        Query d(c, "DELETE FROM export_cache WHERE key = ?1");
        d.bind(1, victim).run();
      }
      collect(c, shas);
      return true;
    });
  }

  std::pair<std::int64_t, std::int64_t> count_blobs() override {
    return read([](Connection& c) {
      Query q(c, "SELECT COUNT(*), COALESCE(SUM(length(bytes)), 0) FROM blobs");
      q.step();
      return std::pair<std::int64_t, std::int64_t>{q.i64(0), q.i64(1)};
    });
  }

  std::pair<std::int64_t, std::int64_t> cache_size() override {
    return read([](Connection& c) {
      Query q(c, "SELECT COALESCE(SUM(size), 0), COUNT(DISTINCT key) FROM export_cache");
      q.step();
      return std::pair<std::int64_t, std::int64_t>{q.i64(0), q.i64(1)};
    });
  }

  // ---- catalogs ----

  /// A UAV's camera_id names a camera that exists, in the transaction that writes the UAV (a camera
  /// deleted meanwhile is seen: writes are serialised).
  static void check_camera_ref(Connection& c, CatalogKind kind, const nlohmann::json& data) {
    const Id camera = camera_ref(kind, data);
    if (camera == 0) return;
    Query q(c, "SELECT 1 FROM catalog WHERE kind = 'camera' AND id = ?1");
    q.bind(1, camera);
    if (!q.step()) throw Conflict(camera_missing_text(camera));
  }

  // ---- elevation models ----

  std::pair<Id, bool> put_dem(const std::string& name, std::string_view bytes,
                              const nlohmann::json& info) override {
    const std::string sha = sha256_hex(bytes);
    const std::string text = info.dump();
    return write([&](Connection& c) -> std::pair<Id, bool> {
      {
        Query q(c, "SELECT id FROM dems WHERE sha256 = ?1");
        q.bind(1, sha);
        if (q.step()) return {q.i64(0), false};
      }
      Query q(
          c,
          "INSERT INTO dems (name, sha256, size, info, bytes, created_ms) VALUES (?1, ?2, ?3, ?4, ?5, ?6)");
      q.bind(1, name).bind(2, sha).bind(3, static_cast<std::int64_t>(bytes.size())).bind(4, text);
      q.bind_blob(5, bytes).bind(6, now_ms()).run();
      return {static_cast<Id>(sqlite3_last_insert_rowid(c.db())), true};
    });
  }

  std::optional<StoredDem> get_dem(Id id) override {
    return read([&](Connection& c) -> std::optional<StoredDem> {
      Query q(c, "SELECT id, name, sha256, size, info, created_ms FROM dems WHERE id = ?1");
      q.bind(1, id);
      if (!q.step()) return std::nullopt;
      return StoredDem{q.i64(0), q.text(1), q.text(2), q.i64(3), parse_column(q.text(4)), q.i64(5)};
    });
  }

  std::optional<std::string> dem_bytes(Id id) override {
    return read([&](Connection& c) -> std::optional<std::string> {
      Query q(c, "SELECT bytes FROM dems WHERE id = ?1");
      q.bind(1, id);
      if (!q.step()) return std::nullopt;
      return q.blob(0);
    });
  }

  std::vector<StoredDem> list_dems(int limit) override {
    return read([&](Connection& c) {
      std::vector<StoredDem> out;
      Query q(c, "SELECT id, name, sha256, size, info, created_ms FROM dems ORDER BY id LIMIT ?1");
      q.bind(1, std::clamp(limit, 1, 1000));
      while (q.step())
        out.push_back({q.i64(0), q.text(1), q.text(2), q.i64(3), parse_column(q.text(4)), q.i64(5)});
      return out;
    });
  }

  Id create_entry(CatalogKind kind, const std::string& name, const nlohmann::json& data) override {
    const std::string text = data.dump();
    return write([&](Connection& c) {
      check_camera_ref(c, kind, data);
      Query q(c, "INSERT INTO catalog (kind, name, data, updated_ms) VALUES (?1, ?2, ?3, ?4)");
      q.bind(1, catalog_text(kind)).bind(2, name).bind(3, text).bind(4, now_ms()).run();
      return static_cast<Id>(sqlite3_last_insert_rowid(c.db()));
    });
  }

  std::optional<CatalogEntry> get_entry(CatalogKind kind, Id id) override {
    return read([&](Connection& c) -> std::optional<CatalogEntry> {
      Query q(c, "SELECT id, name, data, updated_ms FROM catalog WHERE kind = ?1 AND id = ?2");
      q.bind(1, catalog_text(kind)).bind(2, id);
      if (!q.step()) return std::nullopt;
      return CatalogEntry{q.i64(0), q.text(1), parse_column(q.text(2)), q.i64(3)};
    });
  }

  std::vector<CatalogEntry> list_entries(CatalogKind kind) override {
    return read([&](Connection& c) {
      std::vector<CatalogEntry> out;
      Query q(c, "SELECT id, name, data, updated_ms FROM catalog WHERE kind = ?1 ORDER BY id");
      q.bind(1, catalog_text(kind));
      while (q.step()) out.push_back({q.i64(0), q.text(1), parse_column(q.text(2)), q.i64(3)});
      return out;
    });
  }

  void update_entry(CatalogKind kind, Id id, const std::string& name, const nlohmann::json& data) override {
    const std::string text = data.dump();
    write([&](Connection& c) {
      check_camera_ref(c, kind, data);
      Query q(c,
              "UPDATE catalog SET name = ?3, data = ?4, updated_ms = MAX(?5, updated_ms + 1) "
              "WHERE kind = ?1 AND id = ?2");
      q.bind(1, catalog_text(kind)).bind(2, id).bind(3, name).bind(4, text).bind(5, now_ms());
      if (q.run() == 0)
        throw NotFound(std::string(catalog_text(kind)) + " " + std::to_string(id) + " does not exist");
      return 0;
    });
  }

  void delete_entry(CatalogKind kind, Id id) override {
    write([&](Connection& c) {
      Query q(c, "DELETE FROM catalog WHERE kind = ?1 AND id = ?2");
      q.bind(1, catalog_text(kind)).bind(2, id);
      if (q.run() == 0)
        throw NotFound(std::string(catalog_text(kind)) + " " + std::to_string(id) + " does not exist");
      if (kind == CatalogKind::Camera) {
        // in the same transaction: the delete rolls back when a UAV carries the camera
        Query users(c,
                    "SELECT id, name FROM catalog WHERE kind = 'uav' AND "
                    "json_extract(data, '$.camera_id') = ?1 ORDER BY id LIMIT 1");
        users.bind(1, id);
        if (users.step()) throw Conflict(camera_in_use_text(id, users.i64(0), users.text(1)));
      }
      return 0;
    });
  }

  // ---- flights ----

  Id create_flight(const NewFlight& flight) override {
    const std::string config = dump(flight.config);
    const std::string snapshot = dump(flight.snapshot);
    return write([&](Connection& c) {
      Id mission = 0;
      {
        Query q(c, "SELECT mission_id, kind, state FROM jobs WHERE id = ?1");
        q.bind(1, flight.plan_id);
        if (!q.step()) throw NotFound("plan " + std::to_string(flight.plan_id) + " does not exist");
        if (q.text(1) != "plan" || q.text(2) != "done")
          throw Conflict("job " + std::to_string(flight.plan_id) + " is not a done plan");
        mission = q.i64(0);
      }
      Query q(c,
              "INSERT INTO flights (plan_id, mission_id, state, config, snapshot, simulated, created_ms, "
              "updated_ms) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?7)");
      q.bind(1, flight.plan_id).bind(2, mission).bind(3, flight.state).bind(4, config).bind(5, snapshot);
      q.bind(6, flight.simulated ? 1 : 0).bind(7, now_ms()).run();
      return static_cast<Id>(sqlite3_last_insert_rowid(c.db()));
    });
  }

  std::optional<StoredFlight> get_flight(Id flight) override {
    return read([&](Connection& c) -> std::optional<StoredFlight> {
      Query q(c, "SELECT " UAVCOVER_FLIGHT_COLUMNS "WHERE id = ?1");
      q.bind(1, flight);
      if (!q.step()) return std::nullopt;
      return read_flight(q);
    });
  }

  std::vector<StoredFlight> list_flights(Id plan, int limit) override {
    return read([&](Connection& c) {
      Query q(c, "SELECT " UAVCOVER_FLIGHT_COLUMNS
                 "WHERE plan_id = ?1 ORDER BY created_ms DESC, id DESC LIMIT ?2");
      q.bind(1, plan).bind(2, static_cast<std::int64_t>(std::clamp(limit, 1, 1000)));
      std::vector<StoredFlight> out;
      while (q.step()) out.push_back(read_flight(q));
      return out;
    });
  }

  std::vector<StoredFlight> list_active_flights() override {
    return read([&](Connection& c) {
      Query q(c, "SELECT " UAVCOVER_FLIGHT_COLUMNS "WHERE state NOT IN ('done', 'aborted') ORDER BY id");
      std::vector<StoredFlight> out;
      while (q.step()) out.push_back(read_flight(q));
      return out;
    });
  }

  void update_flight(Id flight, const std::string& state, const nlohmann::json& snapshot) override {
    const std::string text = dump(snapshot);
    write([&](Connection& c) {
      Query q(
          c,
          "UPDATE flights SET state = ?2, snapshot = ?3, updated_ms = MAX(?4, updated_ms + 1) WHERE id = ?1");
      q.bind(1, flight).bind(2, state).bind(3, text).bind(4, now_ms());
      if (q.run() == 0) throw NotFound("flight " + std::to_string(flight) + " does not exist");
      return 0;
    });
  }

  std::int64_t append_flight_log(Id flight, const std::vector<FlightLogRecord>& records) override {
    std::vector<std::string> data;
    data.reserve(records.size());
    for (const auto& r : records) data.push_back(dump(r.data));
    return write([&](Connection& c) {
      std::int64_t last = 0;
      {
        // reserves the sequence numbers (and checks the flight is there)
        Query q(c, "UPDATE flights SET log_seq = log_seq + ?2 WHERE id = ?1 RETURNING log_seq");
        q.bind(1, flight).bind(2, static_cast<std::int64_t>(records.size()));
        if (!q.step()) throw NotFound("flight " + std::to_string(flight) + " does not exist");
        last = q.i64(0);
        while (q.step()) {
        }
      }
      std::int64_t seq = last - static_cast<std::int64_t>(records.size());
      for (std::size_t i = 0; i < records.size(); ++i) {
        Query q(
            c,
            "INSERT INTO flight_log (flight_id, seq, t_ms, uav, kind, data) VALUES (?1, ?2, ?3, ?4, ?5, ?6)");
        q.bind(1, flight).bind(2, ++seq).bind(3, records[i].t_ms).bind(4, records[i].uav);
        q.bind(5, records[i].kind).bind(6, data[i]).run();
      }
      return last;
    });
  }

  FlightLogPage read_flight_log(Id flight, std::int64_t after, int limit) override {
    limit = std::clamp(limit, 1, 10000);
    return read([&](Connection& c) {
      Query q(c,
              "SELECT seq, t_ms, uav, kind, data FROM flight_log WHERE flight_id = ?1 AND seq > ?2 "
              "ORDER BY seq LIMIT ?3");
      q.bind(1, flight).bind(2, after).bind(3, static_cast<std::int64_t>(limit) + 1);
      FlightLogPage page;
      while (q.step()) {
        if (static_cast<int>(page.items.size()) == limit) {
          page.next_after = page.items.back().seq;
          break;
        }
        page.items.push_back({q.i64(0), q.i64(1), q.text(2), q.text(3), parse_column(q.text(4))});
      }
      return page;
    });
  }

  void delete_flight(Id flight) override {
    write([&](Connection& c) {
      Query q(c, "DELETE FROM flights WHERE id = ?1");
      q.bind(1, flight);
      if (q.run() == 0) throw NotFound("flight " + std::to_string(flight) + " does not exist");
      return 0;
    });
  }

  bool claim_first_start() override {
    return write([](Connection& c) {
      Query q(c, "INSERT OR IGNORE INTO meta (key, value) VALUES ('first_start', ?1)");
      const std::string now = std::to_string(now_ms());
      q.bind(1, now);
      return q.run() == 1;
    });
  }

 private:
  std::string path_;
  bool memory_;
  std::optional<std::pair<std::uintmax_t, std::uintmax_t>> file_id_;  ///< see check_file()
  std::mutex write_mutex_;
  std::unique_ptr<Connection> writer_;
  std::mutex pool_mutex_;
  std::condition_variable pool_cv_;
  std::vector<std::unique_ptr<Connection>> idle_;
  std::size_t opened_ = 0;
};

}  // namespace

std::unique_ptr<Store> open_sqlite(const std::string& path) { return std::make_unique<SqliteStore>(path); }

}  // namespace uavcover::store
