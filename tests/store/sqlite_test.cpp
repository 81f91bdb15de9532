// What only the SQLite backend promises: the file and its folder are created, WAL mode, ":memory:",
// migrations recorded once, blobs shared and collected, and kill -9 during a burst of writes loses
// nothing that was acknowledged.
#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <set>
#include <thread>

#include "store/backends.hpp"
#include "store/sqlite_migrations.hpp"
#include "test_backends.hpp"

using namespace uavcover;
using namespace uavcover::store;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

// every migration of src/store/sqlite_migrations.hpp runs on a fresh database
constexpr int kMigrationCount = static_cast<int>(store::sqlite_schema::kMigrations.size());

NewRevision revision(const std::string& name) {
  NewRevision r;
  r.name = name;
  r.document = "{}";
  r.source = "{}";
  r.bbox = {1, 2, 3, 4};
  return r;
}

/// A fresh SQLite path, its folder removed afterwards.
class TempDb {
 public:
  TempDb() : path_(uavcover::testing::fresh_sqlite_path()) {}
  ~TempDb() { uavcover::testing::remove_test_store("sqlite:" + path_); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// One integer from the database file, read beside the store with the plain C API.
std::int64_t scalar(const std::string& path, const char* sql) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* stmt = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(db, sql, -1, &stmt, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
  std::int64_t v = -1;
  if (sqlite3_step(stmt) == SQLITE_ROW) v = sqlite3_column_int64(stmt, 0);
  sqlite3_finalize(stmt);
  sqlite3_close(db);
  return v;
}

void exec(const std::string& path, const char* sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, sql, nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
  sqlite3_close(db);
}

TEST(SqliteStore, CreatesItsFolderAndUsesWal) {
  TempDb tmp;
  const std::string nested = (fs::path(tmp.path()).parent_path() / "a" / "b" / "store.db").string();
  auto s = open_sqlite(nested);
  EXPECT_TRUE(fs::exists(nested));
  EXPECT_EQ(s->backend(), "sqlite");
  EXPECT_TRUE(s->ping());
  EXPECT_EQ(s->schema_version(), kMigrationCount);
  s->create_mission(revision("wal"));
  EXPECT_EQ(scalar(nested, "SELECT journal_mode = 'wal' FROM pragma_journal_mode"), 1);
  EXPECT_EQ(scalar(nested, "SELECT COUNT(*) FROM schema_migrations"), kMigrationCount);
  EXPECT_EQ(scalar(nested, "SELECT COUNT(*) FROM catalog WHERE kind = 'uav'"), 4);
  EXPECT_EQ(scalar(nested, "SELECT COUNT(*) FROM catalog WHERE kind = 'camera'"), 5);
}

TEST(SqliteStore, MemoryDatabaseWorksFromSeveralThreads) {
  auto s = open_sqlite(":memory:");
  EXPECT_EQ(s->schema_version(), kMigrationCount);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&] {
      for (int i = 0; i < 20; ++i) {
        const Id id = s->create_mission(revision("mem"));
        ASSERT_TRUE(s->get_mission(id));
      }
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(s->count_missions(), 80);
  EXPECT_FALSE(s->list_entries(CatalogKind::Camera).empty());
  EXPECT_TRUE(s->claim_first_start());
  EXPECT_FALSE(s->claim_first_start());
}

TEST(SqliteStore, RefusesWhatItCannotOpen) {
  TempDb tmp;
  const fs::path dir = fs::path(tmp.path()).parent_path() / "a-folder";
  fs::create_directories(dir);
  EXPECT_THROW(open_sqlite(dir.string()), StoreError) << "a folder is not a database";
  const fs::path junk = fs::path(tmp.path()).parent_path() / "junk.db";
  {
    std::FILE* f = std::fopen(junk.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    std::fputs("this is not an SQLite database, just text long enough to be a header......", f);
    std::fclose(f);
  }
  EXPECT_THROW(open_sqlite(junk.string()), StoreError);
}

TEST(SqliteStore, RefusesASchemaNewerThanItKnows) {
  TempDb tmp;
  open_sqlite(tmp.path()).reset();
  exec(tmp.path(), "INSERT INTO schema_migrations (version, applied_at) VALUES (99, 0)");
  try {
    open_sqlite(tmp.path());
    FAIL() << "opened a newer schema";
  } catch (const StoreError& e) {
    EXPECT_NE(std::string(e.what()).find("schema version 99"), std::string::npos) << e.what();
  }
}

TEST(SqliteStore, SharedBlobsAreStoredOnceAndCollectedWithTheirLastJob) {
  TempDb tmp;
  auto s = open_sqlite(tmp.path());
  const std::string bytes("shared\0bytes", 12);
  std::vector<Id> missions;
  for (int i = 0; i < 2; ++i) {
    const Id m = s->create_mission(revision("blob"));
    missions.push_back(m);
    NewJob j;
    j.mission_id = m;
    j.revision = 1;
    const Id id = s->enqueue(j, 10);
    ASSERT_EQ(s->claim_job("w", 60s, 3)->id, id);
    ASSERT_TRUE(s->finish_job(id, "w", JobState::Done, {}, nullptr,
                              {{"a.bin", "application/octet-stream", bytes},
                               {"b.bin", "application/octet-stream", bytes},
                               {"own.txt", "text/plain", "mission " + std::to_string(i)}}));
  }
  EXPECT_EQ(scalar(tmp.path(), "SELECT COUNT(*) FROM blobs"), 3) << "one shared blob and two own ones";
  EXPECT_EQ(scalar(tmp.path(), "SELECT COUNT(*) FROM job_artifacts"), 6);
  s->delete_mission(missions[0]);
  EXPECT_EQ(scalar(tmp.path(), "SELECT COUNT(*) FROM blobs"), 2) << "the shared blob stays";
  s->delete_mission(missions[1]);
  EXPECT_EQ(scalar(tmp.path(), "SELECT COUNT(*) FROM blobs"), 0);
  EXPECT_EQ(scalar(tmp.path(), "SELECT COUNT(*) FROM job_artifacts"), 0);
}

TEST(SqliteStore, ForeignKeysHoldOnEveryConnection) {
  TempDb tmp;
  auto s = open_sqlite(tmp.path());
  // readers run alongside; a job for a deleted mission must never remain
  const Id m = s->create_mission(revision("fk"));
  NewJob j;
  j.mission_id = m;
  j.revision = 1;
  const Id id = s->enqueue(j, 10);
  s->request_cancel(id);
  s->delete_mission(m);
  EXPECT_EQ(scalar(tmp.path(), "SELECT COUNT(*) FROM jobs"), 0);
  EXPECT_EQ(scalar(tmp.path(), "SELECT COUNT(*) FROM mission_revisions"), 0);
}

// A child process writes missions as fast as it can and reports every acknowledged id through a pipe;
// the parent kills it with SIGKILL mid-burst, reopens the file and finds every reported mission.
TEST(SqliteStore, KillNineDuringWritesLosesNothingAcknowledged) {
  TempDb tmp;
  open_sqlite(tmp.path()).reset();  // created and migrated before the burst
  std::vector<Id> acknowledged;
  const auto create_missions = [&](const std::function<void(std::int64_t)>& ack) {
    auto s = open_sqlite(tmp.path());
    for (int i = 0;; ++i) ack(s->create_mission(revision("burst " + std::to_string(i))));
  };
  ASSERT_TRUE(uavcover::testing::kill_nine_during(create_missions, [&](std::int64_t id) {
    acknowledged.push_back(id);
    return acknowledged.size() >= 200;
  })) << "the child stopped early";
  ASSERT_GE(acknowledged.size(), 200u);

  auto s = open_sqlite(tmp.path());
  EXPECT_GE(s->count_missions(), static_cast<std::int64_t>(acknowledged.size()));
  std::set<Id> distinct(acknowledged.begin(), acknowledged.end());
  EXPECT_EQ(distinct.size(), acknowledged.size());
  for (std::size_t i = 0; i < acknowledged.size(); ++i) {
    const auto m = s->get_mission(acknowledged[i]);
    ASSERT_TRUE(m) << "acknowledged mission " << acknowledged[i] << " lost";
    EXPECT_EQ(m->name, "burst " + std::to_string(i));
  }
  EXPECT_EQ(s->schema_version(), kMigrationCount);
  EXPECT_EQ(scalar(tmp.path(), "SELECT COUNT(*) FROM pragma_integrity_check WHERE integrity_check <> 'ok'"),
            0);
}

}  // namespace

namespace {

TEST(SqliteStore, NotWritableWhileAnotherConnectionHoldsAnExclusiveLock) {
  TempDb tmp;
  auto s = open_sqlite(tmp.path());
  EXPECT_TRUE(s->writable());
  // a second, real connection (as another process's sqlite3 shell would) takes the write lock
  sqlite3* other = nullptr;
  ASSERT_EQ(sqlite3_open(tmp.path().c_str(), &other), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(other, "BEGIN EXCLUSIVE", nullptr, nullptr, nullptr), SQLITE_OK)
      << sqlite3_errmsg(other);
  EXPECT_TRUE(s->ping()) << "reads still work (WAL)";
  EXPECT_FALSE(s->writable()) << "readyz must say 503 while writes would fail";
  ASSERT_EQ(sqlite3_exec(other, "ROLLBACK", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(other);
  EXPECT_TRUE(s->writable());
  s->create_mission(revision("after the lock"));
}

TEST(SqliteStore, RefusesWritesOnceItsFileIsDeletedOrReplaced) {
  TempDb tmp;
  auto s = open_sqlite(tmp.path());
  s->create_mission(revision("before"));
  EXPECT_TRUE(s->writable());
  fs::remove(tmp.path());
  EXPECT_FALSE(s->writable());
  try {
    s->create_mission(revision("lost"));
    FAIL() << "a write to a deleted database file was acknowledged";
  } catch (const StoreError& e) {
    EXPECT_NE(std::string(e.what()).find("deleted or replaced"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(tmp.path()), std::string::npos) << e.what();
  }
  // a new file at the same path is another database: still refused
  fs::remove(tmp.path() + "-wal");
  fs::remove(tmp.path() + "-shm");
  open_sqlite(tmp.path()).reset();
  EXPECT_FALSE(s->writable());
  EXPECT_THROW(s->create_mission(revision("elsewhere")), StoreError);
}

TEST(SqliteStore, AReadOnlyFileFailsAtOpenNamingIt) {
  if (::geteuid() == 0) GTEST_SKIP() << "root writes read-only files (hostile.test.mjs checks as nobody)";
  TempDb tmp;
  open_sqlite(tmp.path()).reset();
  fs::permissions(tmp.path(), fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  try {
    open_sqlite(tmp.path());
    FAIL() << "opened a read-only file";
  } catch (const StoreError& e) {
    EXPECT_NE(std::string(e.what()).find("read-only"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(tmp.path()), std::string::npos) << e.what();
  }
}

}  // namespace
