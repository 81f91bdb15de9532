// PostgreSQL-only store properties: several servers (Store instances) on one database share the job
// queue, leases expire and move, migrations race safely, and bad URIs fail cleanly. Each test works
// in a database of its own on the throwaway cluster (scripts/pg-test-cluster, the CTest fixture "pg").
#include <gtest/gtest.h>
#include <libpq-fe.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <map>
#include <mutex>
#include <thread>

#include "store/backends.hpp"
#include "store/store.hpp"

#ifndef UAVCOVER_TEST_PG_URL_FILE
#error "UAVCOVER_TEST_PG_URL_FILE must name the file scripts/pg-test-cluster writes its URI to"
#endif

namespace uavcover::store {
namespace {

using namespace std::chrono_literals;

// The cluster's URI (database uavcover_test); empty (and the test fails) when the cluster is not up.
std::string cluster_url() {
  std::ifstream in(UAVCOVER_TEST_PG_URL_FILE);
  std::string url;
  std::getline(in, url);
  return url;
}

/// Runs one statement as the cluster's superuser; returns the rows it gave (-1 on failure).
int admin(const std::string& url, const std::string& sql) {
  PGconn* c = PQconnectdb(url.c_str());
  if (PQstatus(c) != CONNECTION_OK) {
    ADD_FAILURE() << PQerrorMessage(c);
    PQfinish(c);
    return -1;
  }
  PQsetNoticeProcessor(
      c, [](void*, const char*) {}, nullptr);
  PGresult* r = PQexec(c, sql.c_str());
  const auto status = PQresultStatus(r);
  const int rows = status == PGRES_TUPLES_OK ? PQntuples(r) : status == PGRES_COMMAND_OK ? 0 : -1;
  EXPECT_GE(rows, 0) << sql << ": " << PQerrorMessage(c);
  PQclear(r);
  PQfinish(c);
  return rows;
}

/// A fresh, empty database on the test cluster, dropped at the end of the test.
class FreshDatabase {
 public:
  FreshDatabase() {
    base_ = cluster_url();
    if (base_.empty()) {
      ADD_FAILURE() << "no PostgreSQL test cluster: " << UAVCOVER_TEST_PG_URL_FILE
                    << " is missing (run via ctest, or scripts/pg-test-cluster start build/pg-test)";
      return;
    }
    static std::atomic<int> counter{0};
    name_ = "uavcover_pg_" + std::to_string(getpid()) + "_" + std::to_string(counter++);
    admin(base_, "DROP DATABASE IF EXISTS " + name_ + " WITH (FORCE)");
    admin(base_, "CREATE DATABASE " + name_);
    const auto pos = base_.find("/uavcover_test");
    if (pos == std::string::npos) {
      ADD_FAILURE() << "unexpected cluster URI " << base_;
      return;
    }
    url_ = base_;
    url_.replace(pos, std::string("/uavcover_test").size(), "/" + name_);
  }
  ~FreshDatabase() {
    if (!name_.empty()) admin(base_, "DROP DATABASE IF EXISTS " + name_ + " WITH (FORCE)");
  }
  [[nodiscard]] bool ok() const { return !url_.empty(); }
  [[nodiscard]] const std::string& url() const { return url_; }
  [[nodiscard]] const std::string& base() const { return base_; }
  [[nodiscard]] const std::string& name() const { return name_; }

 private:
  std::string base_, name_, url_;
};

NewRevision sample_revision(const std::string& name) {
  return NewRevision{name, R"({"name":")" + name + R"("})", R"({"name":")" + name + R"("})",
                     Bbox{10, 50, 11, 51}};
}

TEST(PostgresStore, TwoServersShareTheQueueAndFinishEveryJobExactlyOnce) {
  FreshDatabase db;
  ASSERT_TRUE(db.ok());
  auto a = open_postgres(db.url());
  auto b = open_postgres(db.url());
  EXPECT_EQ(a->backend(), "postgresql");
  const Id mission = a->create_mission(sample_revision("shared queue"));
  std::vector<Id> ids;
  for (int i = 0; i < 40; ++i)
    ids.push_back((i % 2 ? a : b)->enqueue(NewJob{JobKind::Plan, mission, 1, {{"seed", i}}}, 1000));
  EXPECT_EQ(a->count_jobs().queued, 40);

  std::mutex mutex;
  std::map<Id, std::vector<std::string>> claimed;  // job -> workers that claimed it
  std::atomic<int> finish_failures{0};
  const Artifact shared{"shared.bin", "application/octet-stream", std::string("\0\1\2shared\xff", 10)};
  auto work = [&](Store* store, const std::string& worker) {
    for (;;) {
      auto job = store->claim_job(worker, 60s, 3);
      if (!job) return;
      {
        std::lock_guard lock(mutex);
        claimed[job->id].push_back(worker);
      }
      const Artifact own{"plan.json", "application/json", R"({"job":)" + std::to_string(job->id) + "}"};
      if (!store->finish_job(job->id, worker, JobState::Done, {{"job", job->id}}, nullptr, {own, shared}))
        ++finish_failures;
    }
  };
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back(work, a.get(), "a" + std::to_string(t));
    threads.emplace_back(work, b.get(), "b" + std::to_string(t));
  }
  for (auto& t : threads) t.join();

  EXPECT_EQ(finish_failures, 0);
  ASSERT_EQ(claimed.size(), 40u);
  for (const auto& [id, workers] : claimed) EXPECT_EQ(workers.size(), 1u) << "job " << id;
  for (const Id id : ids) {
    const auto job = b->get_job(id);
    ASSERT_TRUE(job);
    EXPECT_EQ(job->state, JobState::Done);
    EXPECT_EQ(job->completions, 1);
    EXPECT_EQ(job->attempts, 1);
    EXPECT_EQ(job->worker, "") << "a finished job has no lease holder";
    EXPECT_EQ(job->result["job"], id);
    ASSERT_EQ(job->artifacts.size(), 2u);
    const auto own = a->get_artifact(id, "plan.json");
    ASSERT_TRUE(own);
    EXPECT_EQ(own->bytes, R"({"job":)" + std::to_string(id) + "}");
    const auto bin = b->get_artifact(id, "shared.bin");
    ASSERT_TRUE(bin);
    EXPECT_EQ(bin->bytes, shared.bytes);
    EXPECT_EQ(bin->media_type, "application/octet-stream");
  }
  const auto counts = a->count_jobs();
  EXPECT_EQ(counts.done, 40);
  EXPECT_EQ(counts.queued + counts.running + counts.failed + counts.cancelled, 0);
}

TEST(PostgresStore, TheQueueLimitHoldsAcrossServers) {
  FreshDatabase db;
  ASSERT_TRUE(db.ok());
  auto a = open_postgres(db.url());
  auto b = open_postgres(db.url());
  const Id mission = a->create_mission(sample_revision("limit"));
  std::atomic<int> queued{0}, full{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t)
    threads.emplace_back([&, t] {
      Store* store = t % 2 ? a.get() : b.get();
      for (int i = 0; i < 10; ++i) {
        try {
          store->enqueue(NewJob{JobKind::Plan, mission, 1, {}}, 30);
          ++queued;
        } catch (const QueueFull&) {
          ++full;
        }
      }
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(queued, 30);
  EXPECT_EQ(full, 50);
  EXPECT_EQ(b->count_jobs().queued, 30);
}

TEST(PostgresStore, AnExpiredLeaseMovesToTheOtherServerAndTheJobFinishesOnce) {
  FreshDatabase db;
  ASSERT_TRUE(db.ok());
  auto a = open_postgres(db.url());
  auto b = open_postgres(db.url());
  const Id mission = a->create_mission(sample_revision("lease"));
  const Id id = a->enqueue(NewJob{JobKind::Plan, mission, 1, {}}, 10);

  const auto first = a->claim_job("server-a", 60s, 3);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->id, id);
  EXPECT_EQ(first->attempts, 1);
  EXPECT_FALSE(b->claim_job("server-b", 60s, 3)) << "a held lease must not be taken";
  EXPECT_TRUE(a->heartbeat(id, "server-a", 60s, 0.3, "division").held);
  EXPECT_DOUBLE_EQ(b->get_job(id)->progress, 0.3);

  // server a stops heartbeating: its last heartbeat leaves a lease that ends at once
  ASSERT_TRUE(a->heartbeat(id, "server-a", 0ms, 0.4, "division").held);
  std::optional<Job> second;
  for (int i = 0; i < 1000 && !second; ++i) {  // the lease ends within a millisecond of the database clock
    second = b->claim_job("server-b", 60s, 3);
    if (!second) std::this_thread::sleep_for(5ms);
  }
  ASSERT_TRUE(second);
  EXPECT_EQ(second->id, id);
  EXPECT_EQ(second->attempts, 2);
  EXPECT_EQ(second->worker, "server-b");

  // the first server wakes up: its lease is gone and its results are refused
  EXPECT_FALSE(a->heartbeat(id, "server-a", 60s, 0.9, "x").held);
  EXPECT_FALSE(a->finish_job(id, "server-a", JobState::Done, {{"by", "a"}}, nullptr,
                             {Artifact{"plan.json", "application/json", "{\"by\":\"a\"}"}}));
  EXPECT_TRUE(b->finish_job(id, "server-b", JobState::Done, {{"by", "b"}}, nullptr,
                            {Artifact{"plan.json", "application/json", "{\"by\":\"b\"}"},
                             Artifact{"abc.txt", "text/plain", "abc"}}));
  EXPECT_FALSE(b->finish_job(id, "server-b", JobState::Done, {{"by", "b"}}, nullptr, {}))
      << "at most one finish succeeds";
  const auto job = a->get_job(id);
  ASSERT_TRUE(job);
  EXPECT_EQ(job->state, JobState::Done);
  EXPECT_EQ(job->completions, 1);
  EXPECT_EQ(job->result["by"], "b");
  EXPECT_EQ(a->get_artifact(id, "plan.json")->bytes, "{\"by\":\"b\"}");
  ASSERT_EQ(job->artifacts.size(), 2u);  // by name
  EXPECT_EQ(job->artifacts[0].name, "abc.txt");
  EXPECT_EQ(job->artifacts[0].media_type, "text/plain");
  EXPECT_EQ(job->artifacts[0].size, 3);
  EXPECT_EQ(job->artifacts[0].sha256, "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(PostgresStore, AJobInterruptedMaxAttemptsTimesFails) {
  FreshDatabase db;
  ASSERT_TRUE(db.ok());
  auto a = open_postgres(db.url());
  auto b = open_postgres(db.url());
  const Id mission = a->create_mission(sample_revision("interrupted"));
  const Id id = a->enqueue(NewJob{JobKind::Study, mission, 1, {}}, 10);
  for (int attempt = 1; attempt <= 2; ++attempt) {
    Store* store = attempt % 2 ? a.get() : b.get();
    const std::string worker = "w" + std::to_string(attempt);
    std::optional<Job> job;
    for (int i = 0; i < 1000 && !job; ++i) {
      job = store->claim_job(worker, 60s, 2);
      if (!job) std::this_thread::sleep_for(5ms);
    }
    ASSERT_TRUE(job);
    EXPECT_EQ(job->attempts, attempt);
    ASSERT_TRUE(store->heartbeat(id, worker, 0ms, 0.1, "").held);  // then the worker dies
  }
  std::this_thread::sleep_for(5ms);
  std::optional<Job> third;
  for (int i = 0; i < 1000; ++i) {
    third = a->claim_job("w3", 60s, 2);
    if (a->get_job(id)->state == JobState::Failed) break;
    std::this_thread::sleep_for(5ms);
  }
  EXPECT_FALSE(third);
  const auto job = b->get_job(id);
  EXPECT_EQ(job->state, JobState::Failed);
  EXPECT_EQ(job->attempts, 2);
  EXPECT_EQ(job->completions, 0);
  EXPECT_EQ(job->error, (nlohmann::json{{"field", ""}, {"message", "the job was interrupted 2 times"}}));
}

TEST(PostgresStore, ConcurrentMigrationsOnAFreshDatabaseAllSucceedOnce) {
  FreshDatabase db;
  ASSERT_TRUE(db.ok());
  std::vector<std::unique_ptr<Store>> stores(4);
  std::vector<std::string> errors(4);
  std::vector<std::thread> threads;
  for (int i = 0; i < 4; ++i)
    threads.emplace_back([&, i] {
      try {
        stores[i] = open_postgres(db.url());
      } catch (const std::exception& e) {
        errors[i] = e.what();
      }
    });
  for (auto& t : threads) t.join();
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(stores[i]) << errors[i];
    EXPECT_EQ(stores[i]->schema_version(), stores[0]->schema_version());
  }
  EXPECT_GE(stores[0]->schema_version(), 2);
  // the catalogs were seeded exactly once
  EXPECT_EQ(stores[1]->list_entries(CatalogKind::Camera).size(), 5u);
  const auto uavs = stores[2]->list_entries(CatalogKind::Uav);
  ASSERT_EQ(uavs.size(), 4u);
  const auto phantom = stores[3]->get_entry(CatalogKind::Camera, uavs[0].data.at("camera_id").get<Id>());
  ASSERT_TRUE(phantom);
  EXPECT_EQ(phantom->name, "DJI Phantom 4 Pro camera");
  // and reopening migrates nothing
  EXPECT_EQ(open_postgres(db.url())->schema_version(), stores[0]->schema_version());
  EXPECT_EQ(stores[0]->list_entries(CatalogKind::Camera).size(), 5u);
  // exactly one server gets to seed the examples
  int first = 0;
  for (auto& s : stores) first += s->claim_first_start() ? 1 : 0;
  EXPECT_EQ(first, 1);
}

TEST(PostgresStore, ABrokenUriGivesAStoreErrorWithoutThePassword) {
  const std::string secret = "s3cretPassw0rd";
  const std::string url = cluster_url();
  std::vector<std::string> uris = {
      "postgresql://uavcover:" + secret + "@127.0.0.1:1/uavcover",             // nothing listens
      "postgresql://uavcover:" + secret + "%zz@127.0.0.1/uavcover",            // bad percent-encoding
      "postgresql:///uavcover?password=" + secret + "&host=/nonexistent-dir",  // no such socket
      "postgresql://u:" + secret + "@[::1/db",                                 // unbalanced bracket
      "postgresql://u@h/db?bogus_option=" + secret,                            // unknown option
  };
  if (!url.empty()) {  // the cluster with a database that does not exist
    const auto q = url.find('?');
    uris.push_back("postgresql://postgres:" + secret + "@/no_such_db" + url.substr(q));
  } else {
    ADD_FAILURE() << "no PostgreSQL test cluster";
  }
  for (const auto& uri : uris) {
    try {
      auto store = open_store(uri);
      ADD_FAILURE() << "opened " << uri;
    } catch (const StoreError& e) {
      const std::string what = e.what();
      EXPECT_FALSE(what.empty());
      EXPECT_EQ(what.find(secret), std::string::npos) << what;
    }
  }
}

TEST(PostgresStore, ALostConnectionIsReopened) {
  FreshDatabase db;
  ASSERT_TRUE(db.ok());
  auto store = open_postgres(db.url());
  const Id mission = store->create_mission(sample_revision("reconnect"));
  // the server ends every session on this database (as a restart or a failover would)
  admin(db.base(),
        "SELECT pg_terminate_backend(pid) FROM pg_stat_activity WHERE datname = '" + db.name() + "'");
  EXPECT_TRUE(store->ping());
  EXPECT_EQ(store->count_missions(), 1);
  EXPECT_TRUE(store->get_mission(mission));
  // and again before a write (a transaction)
  ASSERT_GE(admin(db.base(), "SELECT pg_terminate_backend(pid) FROM pg_stat_activity WHERE datname = '" +
                                 db.name() + "' AND pid <> pg_backend_pid()"),
            1);
  EXPECT_GT(store->create_mission(sample_revision("after reconnect")), mission);
  EXPECT_EQ(store->count_missions(), 2);
}

TEST(PostgresStore, MissionsPageAndFilterLikeTheContractSays) {
  FreshDatabase db;
  ASSERT_TRUE(db.ok());
  auto store = open_postgres(db.url());
  std::vector<Id> ids;
  for (int i = 0; i < 7; ++i) {
    NewRevision rev =
        sample_revision(i % 2 ? "Field_" + std::to_string(i) : "100% orchard " + std::to_string(i));
    rev.bbox = Bbox{10.0 + i, 50, 10.5 + i, 50.5};
    ids.push_back(store->create_mission(rev));
  }
  MissionQuery q;
  q.limit = 3;
  std::vector<Id> seen;
  for (;;) {
    const auto page = store->list_missions(q);
    for (const auto& m : page.items) seen.push_back(m.id);
    if (!page.next_after) break;
    q.after = *page.next_after;
  }
  EXPECT_EQ(seen, ids);
  MissionQuery percent;
  percent.name_contains = "0% ORCH";  // plain text: % is no wildcard, case does not matter
  EXPECT_EQ(store->list_missions(percent).items.size(), 4u);
  MissionQuery underscore;
  underscore.name_contains = "d_";
  EXPECT_EQ(store->list_missions(underscore).items.size(), 3u);
  MissionQuery box;
  box.intersects = Bbox{12.2, 50.2, 13.1, 51};  // touches missions 2 (12..12.5) and 3 (13..13.5)
  const auto hits = store->list_missions(box).items;
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_EQ(hits[0].id, ids[2]);
  EXPECT_EQ(hits[1].id, ids[3]);

  // revisions, and deletion refused while a job is queued
  EXPECT_EQ(store->add_revision(ids[0], sample_revision("renamed")), 2);
  EXPECT_EQ(store->get_mission(ids[0])->name, "renamed");
  EXPECT_EQ(store->get_mission(ids[0], 1)->revision, 1);
  EXPECT_THROW(store->add_revision(999999, sample_revision("x")), NotFound);
  const Id job = store->enqueue(NewJob{JobKind::Plan, ids[0], 2, {}}, 1);
  EXPECT_THROW(store->enqueue(NewJob{JobKind::Plan, ids[1], 1, {}}, 1), QueueFull);
  EXPECT_THROW(store->enqueue(NewJob{JobKind::Plan, ids[1], 5, {}}, 10), NotFound);
  EXPECT_THROW(store->delete_mission(ids[0]), Conflict);
  EXPECT_EQ(store->request_cancel(job), JobState::Cancelled);
  store->delete_mission(ids[0]);
  EXPECT_FALSE(store->get_mission(ids[0]));
  EXPECT_FALSE(store->get_job(job));
  EXPECT_THROW(store->delete_mission(ids[0]), NotFound);
  EXPECT_EQ(store->count_missions(), 6);
}

}  // namespace
}  // namespace uavcover::store
