// The store conformance suite: the same tests for every backend of store_test_urls() (SQLite always,
// PostgreSQL when one is configured, see test_backends.hpp). Real databases, no mocks; every test on a
// fresh database, yet written not to assume empty tables (unique names, counts before and after).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <thread>

#include "store/backends.hpp"
#include "store/sha256.hpp"
#include "test_backends.hpp"

using namespace uavcover;
using namespace uavcover::store;
using namespace std::chrono_literals;
using uavcover::testing::unique_name;

namespace {

NewRevision revision(const std::string& name, Bbox bbox = {22.0, 40.0, 22.1, 40.1}) {
  NewRevision r;
  r.name = name;
  r.document = R"({"version":1,"name":")" + name + R"("})";
  r.source = R"({"name":")" + name + R"(","source":true})";
  r.bbox = bbox;
  return r;
}

class StoreConformance : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    url_ = uavcover::testing::fresh_store_url(GetParam());
    store_ = uavcover::testing::open_test_store(url_);
    drain();
  }
  void TearDown() override {
    if (store_) drain();
    store_.reset();
    uavcover::testing::remove_test_store(url_);
  }

  /// Ends every claimable job (queued, or running with an expired lease) left by earlier tests.
  void drain() {
    while (auto j = store_->claim_job("test-drain", 60s, 1 << 20))
      store_->finish_job(j->id, "test-drain", JobState::Cancelled, {}, nullptr, {});
  }

  Id mission(const std::string& prefix = "m") {
    return store_->create_mission(revision(unique_name(prefix)));
  }

  Id job(Id mission_id, int rev = 1, nlohmann::json params = nlohmann::json::object()) {
    NewJob j;
    j.mission_id = mission_id;
    j.revision = rev;
    j.params = std::move(params);
    return store_->enqueue(j, 1000000);
  }

  std::vector<Id> ids(const MissionQuery& q) {
    std::vector<Id> out;
    for (const auto& s : store_->list_missions(q).items) out.push_back(s.id);
    return out;
  }

  std::string url_;
  std::unique_ptr<Store> store_;
};

// ---- missions ----

TEST_P(StoreConformance, MissionRevisionsStayReadable) {
  EXPECT_TRUE(store_->ping());
  EXPECT_TRUE(store_->writable());  // readyz on an idle database
  const std::int64_t before = store_->count_missions();
  const std::string name = unique_name("Ελλάδα mission");
  const Id id = store_->create_mission(revision(name, {1, 2, 3, 4}));
  EXPECT_GT(id, 0);
  EXPECT_EQ(store_->count_missions(), before + 1);

  auto m = store_->get_mission(id);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->mission_id, id);
  EXPECT_EQ(m->revision, 1);
  EXPECT_EQ(m->latest_revision, 1);
  EXPECT_EQ(m->name, name);
  EXPECT_EQ(m->document, revision(name).document);
  EXPECT_EQ(m->source, revision(name).source);
  EXPECT_EQ(m->bbox.min_lon, 1);
  EXPECT_EQ(m->bbox.max_lat, 4);
  EXPECT_GT(m->created_ms, 0);
  EXPECT_GE(m->revised_ms, m->created_ms);

  const std::string renamed = name + " v2";
  EXPECT_EQ(store_->add_revision(id, revision(renamed, {5, 6, 7, 8})), 2);
  EXPECT_EQ(store_->add_revision(id, revision(renamed + "3")), 3);
  m = store_->get_mission(id, 2);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->revision, 2);
  EXPECT_EQ(m->latest_revision, 3);
  EXPECT_EQ(m->name, renamed);
  EXPECT_EQ(m->bbox.min_lon, 5);
  const auto first = store_->get_mission(id, 1);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->name, name) << "old revisions stay as they were";
  EXPECT_EQ(first->latest_revision, 3);
  EXPECT_EQ(first->created_ms, m->created_ms);
  EXPECT_EQ(store_->get_mission(id)->revision, 3);

  EXPECT_FALSE(store_->get_mission(id, 4));
  EXPECT_FALSE(store_->get_mission(id, 0));
  EXPECT_FALSE(store_->get_mission(id + 1000000));
  EXPECT_THROW(store_->add_revision(id + 1000000, revision("x")), NotFound);
  EXPECT_EQ(store_->count_missions(), before + 1);

  // the summary follows the latest revision
  MissionQuery q;
  q.name_contains = renamed + "3";
  const auto page = store_->list_missions(q);
  ASSERT_EQ(page.items.size(), 1u);
  EXPECT_EQ(page.items[0].id, id);
  EXPECT_EQ(page.items[0].revision, 3);
  EXPECT_EQ(page.items[0].name, renamed + "3");
  EXPECT_GE(page.items[0].updated_ms, page.items[0].created_ms);
}

TEST_P(StoreConformance, MissionListPagesByIdAndFiltersByName) {
  const std::string tag = unique_name("Paging");
  std::vector<Id> made;
  for (int i = 0; i < 7; ++i)
    made.push_back(store_->create_mission(revision(tag + " #" + std::to_string(i))));
  store_->create_mission(revision(unique_name("other")));

  MissionQuery q;
  std::string lower = tag;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  q.name_contains = lower;  // case-insensitive
  q.limit = 3;
  std::vector<Id> seen;
  int pages = 0;
  for (;;) {
    const auto page = store_->list_missions(q);
    ++pages;
    for (const auto& s : page.items) seen.push_back(s.id);
    if (!page.next_after) break;
    EXPECT_EQ(page.items.size(), 3u);
    EXPECT_EQ(*page.next_after, page.items.back().id);
    q.after = *page.next_after;
    ASSERT_LT(pages, 10);
  }
  EXPECT_EQ(pages, 3);
  EXPECT_EQ(seen, made) << "every mission once, ids ascending";

  // a page that ends exactly at the last row has no next page
  q.after = 0;
  q.limit = 7;
  auto page = store_->list_missions(q);
  EXPECT_EQ(page.items.size(), 7u);
  EXPECT_FALSE(page.next_after);

  // the limit is clamped to 1..1000
  q.limit = 0;
  page = store_->list_missions(q);
  EXPECT_EQ(page.items.size(), 1u);
  EXPECT_TRUE(page.next_after);
  q.limit = 5000;
  EXPECT_EQ(store_->list_missions(q).items.size(), 7u);

  // without a filter, paging walks ids ascending
  MissionQuery all;
  all.after = made[2];
  all.limit = 2;
  EXPECT_EQ(ids(all), (std::vector<Id>{made[3], made[4]}));
}

TEST_P(StoreConformance, NameFilterIsPlainTextNotAPattern) {
  const std::string tag = unique_name("lit");
  const Id percent = store_->create_mission(revision(tag + " 50% off"));
  const Id fifty = store_->create_mission(revision(tag + " 50X off"));
  const Id underscore = store_->create_mission(revision(tag + " a_b"));
  const Id axb = store_->create_mission(revision(tag + " aXb"));
  const Id backslash = store_->create_mission(revision(tag + " c\\d"));
  const Id cd = store_->create_mission(revision(tag + " cd"));
  const Id quote = store_->create_mission(revision(tag + " it's \"quoted\""));

  MissionQuery q;
  q.name_contains = tag + " 50%";
  EXPECT_EQ(ids(q), std::vector<Id>{percent});
  q.name_contains = tag + " a_b";
  EXPECT_EQ(ids(q), std::vector<Id>{underscore});
  q.name_contains = tag + " c\\d";
  EXPECT_EQ(ids(q), std::vector<Id>{backslash});
  q.name_contains = tag + " it's \"";
  EXPECT_EQ(ids(q), std::vector<Id>{quote});
  q.name_contains = tag + " ";
  EXPECT_EQ(ids(q), (std::vector<Id>{percent, fifty, underscore, axb, backslash, cd, quote}));
  q.name_contains = unique_name("nothing has this name");
  EXPECT_TRUE(ids(q).empty());
  q.name_contains = "%";
  for (const auto& s : store_->list_missions(q).items)
    EXPECT_NE(s.name.find('%'), std::string::npos) << s.name;
}

TEST_P(StoreConformance, BboxFilterKeepsIntersectingMissions) {
  const std::string tag = unique_name("bbox");
  const Id a = store_->create_mission(revision(tag + " a", {10, 10, 11, 11}));
  const Id b = store_->create_mission(revision(tag + " b", {12, 10, 13, 11}));
  const Id c = store_->create_mission(revision(tag + " c", {-50, -40, 50, 40}));  // contains the others
  MissionQuery q;
  q.name_contains = tag;
  q.intersects = Bbox{10.5, 10.5, 11.5, 11.5};
  EXPECT_EQ(ids(q), (std::vector<Id>{a, c}));
  q.intersects = Bbox{11, 11, 12, 12};  // touching corners intersect
  EXPECT_EQ(ids(q), (std::vector<Id>{a, b, c}));
  q.intersects = Bbox{60, 60, 61, 61};
  EXPECT_TRUE(ids(q).empty());
  q.intersects = Bbox{12.2, 10.2, 12.3, 10.3};  // inside b
  EXPECT_EQ(ids(q), (std::vector<Id>{b, c}));
}

TEST_P(StoreConformance, DeleteMissionRefusesWhileJobsAreQueuedOrRunning) {
  const std::int64_t before = store_->count_missions();
  const Id m = mission();
  store_->add_revision(m, revision(unique_name("m2")));
  const Id j = job(m, 2);
  EXPECT_THROW(store_->delete_mission(m), Conflict);
  auto claimed = store_->claim_job("w1", 60s, 3);
  ASSERT_TRUE(claimed);
  ASSERT_EQ(claimed->id, j);
  EXPECT_THROW(store_->delete_mission(m), Conflict);
  ASSERT_TRUE(store_->finish_job(j, "w1", JobState::Done, {{"poc", 1.0}}, nullptr,
                                 {{"plan.json", "application/json", "{}"}}));
  EXPECT_TRUE(store_->get_mission(m)) << "nothing deleted by the refusals";

  store_->delete_mission(m);
  EXPECT_FALSE(store_->get_mission(m));
  EXPECT_FALSE(store_->get_mission(m, 1));
  EXPECT_FALSE(store_->get_job(j)) << "its finished jobs go with it";
  EXPECT_FALSE(store_->get_artifact(j, "plan.json"));
  EXPECT_EQ(store_->count_missions(), before);
  EXPECT_THROW(store_->delete_mission(m), NotFound);
  EXPECT_THROW(store_->delete_mission(987654321), NotFound);
}

// ---- jobs ----

TEST_P(StoreConformance, EnqueueNeedsTheMissionRevision) {
  const Id m = mission();
  NewJob j;
  j.mission_id = m + 1000000;
  j.revision = 1;
  EXPECT_THROW(store_->enqueue(j, 100), NotFound);
  j.mission_id = m;
  j.revision = 2;
  EXPECT_THROW(store_->enqueue(j, 100), NotFound);
  j.revision = 1;
  j.kind = JobKind::Study;
  j.params = {{"uavs", "1..5"}, {"seed", 7}};
  const Id id = store_->enqueue(j, 100);
  const auto got = store_->get_job(id);
  ASSERT_TRUE(got);
  EXPECT_EQ(got->kind, JobKind::Study);
  EXPECT_EQ(got->mission_id, m);
  EXPECT_EQ(got->revision, 1);
  EXPECT_EQ(got->params, j.params);
  EXPECT_EQ(got->state, JobState::Queued);
  EXPECT_EQ(got->attempts, 0);
  EXPECT_EQ(got->completions, 0);
  EXPECT_FALSE(got->cancel_requested);
  EXPECT_EQ(got->worker, "");
  EXPECT_GT(got->created_ms, 0);
  EXPECT_EQ(got->started_ms, 0);
  EXPECT_EQ(got->finished_ms, 0);
  EXPECT_TRUE(got->error.is_null());
  EXPECT_TRUE(got->artifacts.empty());
  EXPECT_FALSE(store_->get_job(id + 1000000));
}

TEST_P(StoreConformance, EnqueueRefusesWhenTheQueueIsFull) {
  const Id m = mission();
  const std::int64_t queued = store_->count_jobs().queued;
  NewJob j;
  j.mission_id = m;
  j.revision = 1;
  const int max = static_cast<int>(queued) + 2;
  store_->enqueue(j, max);
  store_->enqueue(j, max);
  EXPECT_THROW(store_->enqueue(j, max), QueueFull);
  EXPECT_EQ(store_->count_jobs().queued, queued + 2);
  EXPECT_THROW(store_->enqueue(j, 0), QueueFull);
}

TEST_P(StoreConformance, ClaimTakesTheOldestQueuedJob) {
  const Id m = mission();
  const Id a = job(m, 1, {{"planner", "darp"}, {"seed", 1}});
  const Id b = job(m);
  const Id c = job(m);
  const JobCounts before = store_->count_jobs();

  auto first = store_->claim_job("worker-1", 60s, 3);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->id, a);
  EXPECT_EQ(first->state, JobState::Running);
  EXPECT_EQ(first->attempts, 1);
  EXPECT_EQ(first->worker, "worker-1");
  EXPECT_GT(first->started_ms, 0);
  EXPECT_EQ(first->params, (nlohmann::json{{"planner", "darp"}, {"seed", 1}}));
  auto second = store_->claim_job("worker-2", 60s, 3);
  ASSERT_TRUE(second);
  EXPECT_EQ(second->id, b);
  auto third = store_->claim_job("worker-1", 60s, 3);
  ASSERT_TRUE(third);
  EXPECT_EQ(third->id, c);
  EXPECT_FALSE(store_->claim_job("worker-3", 60s, 3)) << "running jobs with live leases are not taken";

  const JobCounts after = store_->count_jobs();
  EXPECT_EQ(after.queued, before.queued - 3);
  EXPECT_EQ(after.running, before.running + 3);

  const auto jobs = store_->get_jobs({c, a, 987654321, b});
  ASSERT_EQ(jobs.size(), 3u);
  std::map<Id, std::string> workers;
  for (const auto& j : jobs) {
    EXPECT_EQ(j.state, JobState::Running);
    workers[j.id] = j.worker;
  }
  EXPECT_EQ(workers[a], "worker-1");
  EXPECT_EQ(workers[b], "worker-2");
  for (Id id : {a, c}) EXPECT_TRUE(store_->finish_job(id, "worker-1", JobState::Done, {}, nullptr, {}));
  EXPECT_TRUE(store_->finish_job(b, "worker-2", JobState::Failed, {},
                                 {{"field", "planner"}, {"message", "no such planner"}}, {}));
  const auto failed = store_->get_job(b);
  EXPECT_EQ(failed->state, JobState::Failed);
  EXPECT_EQ(failed->error, (nlohmann::json{{"field", "planner"}, {"message", "no such planner"}}));
}

TEST_P(StoreConformance, HeartbeatRecordsProgressWhileTheLeaseIsHeld) {
  const Id m = mission();
  const Id id = job(m);
  const auto claimed = store_->claim_job("w1", 60s, 3);
  ASSERT_TRUE(claimed);
  ASSERT_EQ(claimed->id, id);

  EXPECT_FALSE(store_->heartbeat(id, "w2", 60s, 0.9, "intruder").held);
  EXPECT_FALSE(store_->heartbeat(id + 1000000, "w1", 60s, 0.9, "nobody").held);
  auto status = store_->heartbeat(id, "w1", 60s, 0.5, "division");
  EXPECT_TRUE(status.held);
  EXPECT_FALSE(status.cancel_requested);
  auto j = store_->get_job(id);
  EXPECT_DOUBLE_EQ(j->progress, 0.5);
  EXPECT_EQ(j->stage, "division");
  EXPECT_GT(j->updated_ms, claimed->updated_ms) << "every change moves updated_ms (events poll it)";
  const std::int64_t updated = j->updated_ms;
  store_->heartbeat(id, "w1", 60s, 0.75, "paths");
  j = store_->get_job(id);
  EXPECT_DOUBLE_EQ(j->progress, 0.75);
  EXPECT_EQ(j->stage, "paths");
  EXPECT_GT(j->updated_ms, updated);

  EXPECT_EQ(store_->request_cancel(id), JobState::Running);
  j = store_->get_job(id);
  EXPECT_TRUE(j->cancel_requested);
  EXPECT_EQ(j->state, JobState::Running);
  status = store_->heartbeat(id, "w1", 60s, 0.8, "paths");
  EXPECT_TRUE(status.held);
  EXPECT_TRUE(status.cancel_requested);
  EXPECT_TRUE(store_->finish_job(id, "w1", JobState::Cancelled, {}, nullptr, {}));
  j = store_->get_job(id);
  EXPECT_EQ(j->state, JobState::Cancelled);
  EXPECT_GT(j->finished_ms, 0);
  EXPECT_EQ(j->worker, "");
  EXPECT_EQ(store_->request_cancel(id), JobState::Cancelled);
}

// A DELETE that lands while the worker stores its result: the job is never recorded done.
TEST_P(StoreConformance, ADoneAfterACancelRequestIsRecordedCancelledWithoutArtifacts) {
  const Id m = mission();
  const Id id = job(m);
  ASSERT_TRUE(store_->claim_job("w1", 60s, 3));
  EXPECT_EQ(store_->request_cancel(id), JobState::Running);
  const Artifacts outputs{{"plan.json", "application/json", "{\"late\": true}"}};
  ASSERT_TRUE(store_->finish_job(id, "w1", JobState::Done, {{"poc", 1.0}}, nullptr, outputs));
  const auto j = store_->get_job(id);
  EXPECT_EQ(j->state, JobState::Cancelled);
  EXPECT_TRUE(j->artifacts.empty());
  EXPECT_EQ(j->result, nlohmann::json::object());
  EXPECT_FALSE(store_->get_artifact(id, "plan.json"));
  EXPECT_EQ(j->completions, 1);
  // without a cancel request a done stays done
  const Id other = job(m);
  ASSERT_TRUE(store_->claim_job("w1", 60s, 3));
  ASSERT_TRUE(store_->finish_job(other, "w1", JobState::Done, {{"poc", 1.0}}, nullptr, outputs));
  EXPECT_EQ(store_->get_job(other)->state, JobState::Done);
  EXPECT_TRUE(store_->get_artifact(other, "plan.json"));
}

TEST_P(StoreConformance, CancelAQueuedJobAtOnce) {
  const Id m = mission();
  const Id id = job(m);
  EXPECT_EQ(store_->request_cancel(id), JobState::Cancelled);
  const auto j = store_->get_job(id);
  EXPECT_EQ(j->state, JobState::Cancelled);
  EXPECT_GT(j->finished_ms, 0);
  EXPECT_EQ(j->attempts, 0);
  EXPECT_FALSE(store_->claim_job("w1", 60s, 3)) << "a cancelled job is never claimed";
  EXPECT_EQ(store_->request_cancel(id), JobState::Cancelled);
  EXPECT_THROW(store_->request_cancel(id + 1000000), NotFound);
  store_->delete_mission(m);  // a cancelled job does not hold its mission
}

TEST_P(StoreConformance, ListJobsGivesOneMissionsJobsOfOneKindNewestFirst) {
  const Id m = mission();
  const Id other = mission();
  const Id p1 = job(m, 1, {{"planner", "darp"}});
  const Id p2 = job(m, 1, {{"planner", "boustrophedon"}});
  NewJob study;
  study.kind = JobKind::Study;
  study.mission_id = m;
  study.revision = 1;
  const Id s1 = store_->enqueue(study, 1000000);
  const Id p3 = job(m);
  job(other);
  // p1 done with metrics, p2 failed; p3 stays queued
  ASSERT_EQ(store_->claim_job("w", 60s, 3)->id, p1);
  const nlohmann::json result = {{"metrics", {{"poc", 0.97}}}, {"planner", "darp"}};
  ASSERT_TRUE(store_->finish_job(p1, "w", JobState::Done, result, nullptr,
                                 {{"plan.json", "application/json", "{}"}}));
  ASSERT_EQ(store_->claim_job("w", 60s, 3)->id, p2);
  ASSERT_TRUE(store_->finish_job(p2, "w", JobState::Failed, {}, {{"field", ""}, {"message", "no"}}, {}));

  auto ids_of = [](const std::vector<Job>& jobs) {
    std::vector<Id> out;
    for (const auto& j : jobs) out.push_back(j.id);
    return out;
  };
  const auto plans = store_->list_jobs(m, JobKind::Plan, 20);
  EXPECT_EQ(ids_of(plans), (std::vector<Id>{p3, p2, p1}));
  ASSERT_EQ(plans.size(), 3u);
  EXPECT_EQ(plans[0].state, JobState::Queued);
  EXPECT_EQ(plans[1].state, JobState::Failed);
  EXPECT_EQ(plans[1].params, (nlohmann::json{{"planner", "boustrophedon"}}));
  EXPECT_EQ(plans[2].state, JobState::Done);
  EXPECT_EQ(plans[2].result, result);
  EXPECT_EQ(plans[2].mission_id, m);
  EXPECT_GT(plans[2].finished_ms, 0);
  EXPECT_TRUE(plans[2].artifacts.empty()) << "listing leaves the artifacts out";
  EXPECT_EQ(ids_of(store_->list_jobs(m, JobKind::Plan, 2)), (std::vector<Id>{p3, p2}));
  EXPECT_EQ(ids_of(store_->list_jobs(m, JobKind::Plan, 0)), (std::vector<Id>{p3})) << "limit clamped to 1";
  EXPECT_EQ(ids_of(store_->list_jobs(m, JobKind::Study, 20)), (std::vector<Id>{s1}));
  EXPECT_TRUE(store_->list_jobs(m, JobKind::Comparison, 20).empty());
  EXPECT_EQ(store_->list_jobs(other, JobKind::Plan, 20).size(), 1u);
  EXPECT_TRUE(store_->list_jobs(987654321, JobKind::Plan, 20).empty());
}

TEST_P(StoreConformance, FinishSucceedsOnceOnly) {
  const Id m = mission();
  const Id id = job(m);
  ASSERT_EQ(store_->claim_job("w1", 60s, 3)->id, id);
  const nlohmann::json result = {{"metrics", {{"poc", 0.98}}}, {"warnings", nlohmann::json::array()}};
  EXPECT_TRUE(store_->finish_job(id, "w1", JobState::Done, result, nullptr,
                                 {{"plan.json", "application/json", R"({"uavs":[]})"}}));
  EXPECT_FALSE(store_->finish_job(id, "w1", JobState::Failed, {}, {{"field", ""}, {"message", "late"}}, {}));
  EXPECT_FALSE(store_->finish_job(id, "w2", JobState::Done, {{"other", true}}, nullptr,
                                  {{"plan.json", "application/json", "overwritten"}}));
  EXPECT_FALSE(store_->heartbeat(id, "w1", 60s, 0.1, "again").held);
  const auto j = store_->get_job(id);
  EXPECT_EQ(j->state, JobState::Done);
  EXPECT_EQ(j->completions, 1);
  EXPECT_EQ(j->result, result);
  EXPECT_TRUE(j->error.is_null());
  EXPECT_DOUBLE_EQ(j->progress, 1.0);
  EXPECT_EQ(j->worker, "");
  EXPECT_GE(j->finished_ms, j->started_ms);
  ASSERT_EQ(j->artifacts.size(), 1u);
  EXPECT_EQ(store_->get_artifact(id, "plan.json")->bytes, R"({"uavs":[]})");
  EXPECT_EQ(store_->request_cancel(id), JobState::Done);
  EXPECT_THROW(store_->finish_job(id, "w1", JobState::Running, {}, nullptr, {}), std::invalid_argument);
}

TEST_P(StoreConformance, AnExpiredLeaseIsTakenOverAndTheOldWorkerCannotFinish) {
  const Id m = mission();
  const Id id = job(m);
  const auto first = store_->claim_job("w1", 50ms, 3);
  ASSERT_TRUE(first);
  ASSERT_EQ(first->id, id);
  EXPECT_FALSE(store_->claim_job("w2", 60s, 3)) << "the lease still holds";
  std::this_thread::sleep_for(100ms);

  const auto second = store_->claim_job("w2", 60s, 3);
  ASSERT_TRUE(second);
  EXPECT_EQ(second->id, id);
  EXPECT_EQ(second->attempts, 2);
  EXPECT_EQ(second->worker, "w2");
  EXPECT_EQ(second->started_ms, first->started_ms) << "started once";

  EXPECT_FALSE(store_->heartbeat(id, "w1", 60s, 0.5, "stale").held);
  EXPECT_FALSE(store_->finish_job(id, "w1", JobState::Done, {{"by", "w1"}}, nullptr, {}));
  EXPECT_TRUE(store_->heartbeat(id, "w2", 60s, 0.5, "fresh").held);
  EXPECT_TRUE(store_->finish_job(id, "w2", JobState::Done, {{"by", "w2"}}, nullptr, {}));
  const auto j = store_->get_job(id);
  EXPECT_EQ(j->completions, 1);
  EXPECT_EQ(j->result, (nlohmann::json{{"by", "w2"}}));
}

TEST_P(StoreConformance, AJobInterruptedTooOftenFails) {
  const Id m = mission();
  const Id doomed = job(m);
  const Id next = job(m);
  ASSERT_EQ(store_->claim_job("w1", 1ms, 2)->id, doomed);
  std::this_thread::sleep_for(20ms);
  const auto again = store_->claim_job("w2", 1ms, 2);
  ASSERT_TRUE(again);
  ASSERT_EQ(again->id, doomed);
  EXPECT_EQ(again->attempts, 2);
  std::this_thread::sleep_for(20ms);

  const auto claimed = store_->claim_job("w3", 60s, 2);
  ASSERT_TRUE(claimed) << "the exhausted job is skipped and the next one taken";
  EXPECT_EQ(claimed->id, next);
  const auto j = store_->get_job(doomed);
  EXPECT_EQ(j->state, JobState::Failed);
  EXPECT_EQ(j->error, (nlohmann::json{{"field", ""}, {"message", "the job was interrupted 2 times"}}));
  EXPECT_GT(j->finished_ms, 0);
  EXPECT_EQ(j->completions, 0);
  EXPECT_FALSE(store_->finish_job(doomed, "w2", JobState::Done, {}, nullptr, {}));
  EXPECT_TRUE(store_->finish_job(next, "w3", JobState::Done, {}, nullptr, {}));
}

TEST_P(StoreConformance, RecoverRunningRequeuesOrFails) {
  const Id m = mission();
  const Id fresh = job(m);
  const Id tired = job(m);
  ASSERT_EQ(store_->claim_job("w1", 60s, 3)->id, fresh);
  ASSERT_EQ(store_->claim_job("w1", 1ms, 3)->id, tired);
  std::this_thread::sleep_for(20ms);
  ASSERT_EQ(store_->claim_job("w2", 60s, 3)->id, tired);  // attempts 2

  EXPECT_EQ(store_->recover_running(2), 1);
  auto f = store_->get_job(fresh);
  EXPECT_EQ(f->state, JobState::Queued);
  EXPECT_EQ(f->worker, "");
  EXPECT_EQ(f->attempts, 1);
  const auto t = store_->get_job(tired);
  EXPECT_EQ(t->state, JobState::Failed);
  EXPECT_EQ(t->error.at("message"), "the job was interrupted 2 times");
  EXPECT_FALSE(store_->finish_job(fresh, "w1", JobState::Done, {}, nullptr, {})) << "w1 lost it";

  const auto reclaimed = store_->claim_job("w3", 60s, 3);
  ASSERT_TRUE(reclaimed);
  EXPECT_EQ(reclaimed->id, fresh);
  EXPECT_EQ(reclaimed->attempts, 2);
  EXPECT_TRUE(store_->finish_job(fresh, "w3", JobState::Done, {}, nullptr, {}));
  EXPECT_EQ(store_->recover_running(2), 0);
}

// ---- artifacts ----

TEST_P(StoreConformance, ArtifactsAreContentAddressedAndByteExact) {
  std::string binary;
  for (int i = 0; i < 256; ++i) binary += static_cast<char>(i);
  binary += std::string(3, '\0');
  std::string large;
  unsigned x = 12345;
  for (int i = 0; i < 1 << 20; ++i) {
    x = x * 1103515245u + 12345u;
    large += static_cast<char>(x >> 24);
  }
  const Artifacts outputs{{"plan.png", "image/png", binary},
                          {"export/uav1.plan", "application/json", large},
                          {"empty.csv", "text/csv", ""}};
  const Id m = mission();
  const Id a = job(m);
  const Id b = job(m);
  ASSERT_EQ(store_->claim_job("w", 60s, 3)->id, a);
  ASSERT_TRUE(store_->finish_job(a, "w", JobState::Done, {}, nullptr, outputs));
  ASSERT_EQ(store_->claim_job("w", 60s, 3)->id, b);
  ASSERT_TRUE(store_->finish_job(b, "w", JobState::Done, {}, nullptr,
                                 {{"copy.png", "image/png", binary}, {"other.txt", "text/plain", "other"}}));

  const auto ja = store_->get_job(a);
  ASSERT_EQ(ja->artifacts.size(), 3u);
  std::map<std::string, ArtifactRef> refs;
  for (const auto& r : ja->artifacts) refs[r.name] = r;
  EXPECT_EQ(refs["plan.png"].sha256, sha256_hex(binary));
  EXPECT_EQ(refs["plan.png"].size, 259);
  EXPECT_EQ(refs["plan.png"].media_type, "image/png");
  EXPECT_EQ(refs["export/uav1.plan"].size, 1 << 20);
  EXPECT_EQ(refs["empty.csv"].size, 0);
  const auto jb = store_->get_job(b);
  ASSERT_EQ(jb->artifacts.size(), 2u);
  for (const auto& r : jb->artifacts)
    if (r.name == "copy.png") {
      EXPECT_EQ(r.sha256, refs["plan.png"].sha256) << "the same bytes, the same blob";
    }

  for (const auto& o : outputs) {
    const auto got = store_->get_artifact(a, o.name);
    ASSERT_TRUE(got) << o.name;
    EXPECT_EQ(got->name, o.name);
    EXPECT_EQ(got->media_type, o.media_type);
    EXPECT_TRUE(got->bytes == o.bytes) << o.name << ": bytes differ";
  }
  EXPECT_TRUE(store_->get_artifact(b, "copy.png")->bytes == binary);
  EXPECT_FALSE(store_->get_artifact(a, "copy.png"));
  EXPECT_FALSE(store_->get_artifact(a, "missing"));
  EXPECT_FALSE(store_->get_artifact(a + 1000000, "plan.png"));
  EXPECT_TRUE(store_->get_jobs({a}).at(0).artifacts.empty()) << "get_jobs leaves artifacts out";
}

// ---- catalogs ----

TEST_P(StoreConformance, CatalogsAreSeededWithRealUavsAndCameras) {
  const auto uavs = store_->list_entries(CatalogKind::Uav);
  const auto cameras = store_->list_entries(CatalogKind::Camera);
  auto find = [](const std::vector<CatalogEntry>& list, const std::string& part) -> const CatalogEntry* {
    for (const auto& e : list)
      if (e.name.find(part) != std::string::npos) return &e;
    return nullptr;
  };
  const auto* phantom = find(uavs, "DJI Phantom 4 Pro V2.0");
  ASSERT_NE(phantom, nullptr);
  EXPECT_EQ(phantom->data.at("speed_mps"), 10);
  EXPECT_EQ(phantom->data.at("max_accel_mps2"), 4);
  EXPECT_EQ(phantom->data.at("endurance_min"), 28);
  EXPECT_DOUBLE_EQ(phantom->data.at("cost_per_min_eur").get<double>(), 0.017228);
  ASSERT_TRUE(phantom->data.contains("camera_id"));
  const auto camera = store_->get_entry(CatalogKind::Camera, phantom->data.at("camera_id").get<Id>());
  ASSERT_TRUE(camera);
  EXPECT_NE(camera->name.find("Phantom 4 Pro"), std::string::npos) << camera->name;
  EXPECT_DOUBLE_EQ(camera->data.at("sensor_width_mm").get<double>(), 13.2);
  EXPECT_DOUBLE_EQ(camera->data.at("focal_length_mm").get<double>(), 8.8);
  EXPECT_EQ(camera->data.at("image_width_px"), 5472);
  EXPECT_DOUBLE_EQ(camera->data.at("hfov_deg").get<double>(), 73.7);
  for (const char* name : {"DJI Mavic 3 Enterprise", "DJI Matrice 300 RTK"})
    EXPECT_NE(find(uavs, name), nullptr);
  for (const char* name : {"Sony RX1R II", "MicaSense RedEdge-MX"}) EXPECT_NE(find(cameras, name), nullptr);
  for (const auto& u : uavs) {
    if (u.data.contains("name")) {
      EXPECT_EQ(u.data["name"], u.name);
    }
    if (u.data.contains("camera_id")) {
      EXPECT_TRUE(store_->get_entry(CatalogKind::Camera, u.data["camera_id"].get<Id>())) << u.name;
    }
  }
  EXPECT_FALSE(store_->get_entry(CatalogKind::Uav, camera->id)) << "kinds are apart";
}

TEST_P(StoreConformance, CatalogEntriesCanBeCreatedChangedAndDeleted) {
  const std::string name = unique_name("Survey wing");
  const nlohmann::json data = {{"name", name},
                               {"speed_mps", 18},
                               {"max_accel_mps2", 3},
                               {"endurance_min", 90},
                               {"cost_per_min_eur", 0.05}};
  const std::size_t before = store_->list_entries(CatalogKind::Uav).size();
  const Id id = store_->create_entry(CatalogKind::Uav, name, data);
  auto e = store_->get_entry(CatalogKind::Uav, id);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->id, id);
  EXPECT_EQ(e->name, name);
  EXPECT_EQ(e->data, data);
  EXPECT_GT(e->updated_ms, 0);
  EXPECT_EQ(store_->list_entries(CatalogKind::Uav).size(), before + 1);
  EXPECT_FALSE(store_->get_entry(CatalogKind::Camera, id));

  nlohmann::json changed = data;
  changed["speed_mps"] = 20;
  changed["name"] = name + " II";
  store_->update_entry(CatalogKind::Uav, id, name + " II", changed);
  const auto after = store_->get_entry(CatalogKind::Uav, id);
  EXPECT_EQ(after->name, name + " II");
  EXPECT_EQ(after->data, changed);
  EXPECT_GT(after->updated_ms, e->updated_ms);
  EXPECT_THROW(store_->update_entry(CatalogKind::Camera, id, "x", {}), NotFound);
  EXPECT_THROW(store_->update_entry(CatalogKind::Uav, id + 1000000, "x", {}), NotFound);

  EXPECT_THROW(store_->delete_entry(CatalogKind::Camera, id), NotFound);
  store_->delete_entry(CatalogKind::Uav, id);
  EXPECT_FALSE(store_->get_entry(CatalogKind::Uav, id));
  EXPECT_THROW(store_->delete_entry(CatalogKind::Uav, id), NotFound);
  EXPECT_EQ(store_->list_entries(CatalogKind::Uav).size(), before);
}

// issue 28: a camera that a UAV carries cannot be deleted, and a UAV cannot name a camera that is gone,
// each checked in the writing transaction, so no race between the two leaves a dangling camera_id
TEST_P(StoreConformance, NoUavIsLeftWithADeletedCamera) {
  const nlohmann::json camera = {{"name", "cam"}, {"sensor_width_mm", 13.2}, {"focal_length_mm", 8.8}};
  auto uav = [&](Id camera_id) {
    return nlohmann::json{{"name", "carrier"},   {"speed_mps", 8},        {"max_accel_mps2", 3},
                          {"endurance_min", 30}, {"cost_per_min_eur", 1}, {"camera_id", camera_id}};
  };
  const Id used = store_->create_entry(CatalogKind::Camera, unique_name("cam"), camera);
  const Id carrier = store_->create_entry(CatalogKind::Uav, unique_name("carrier"), uav(used));
  try {
    store_->delete_entry(CatalogKind::Camera, used);
    ADD_FAILURE() << "a camera a UAV carries was deleted";
  } catch (const Conflict& e) {
    EXPECT_NE(std::string(e.what()).find("used by UAV " + std::to_string(carrier)), std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(store_->get_entry(CatalogKind::Camera, used)) << "the refused delete rolled back";
  const Id gone = store_->create_entry(CatalogKind::Camera, unique_name("cam"), camera);
  store_->delete_entry(CatalogKind::Camera, gone);
  EXPECT_THROW(store_->create_entry(CatalogKind::Uav, unique_name("x"), uav(gone)), Conflict);
  EXPECT_THROW(store_->update_entry(CatalogKind::Uav, carrier, "carrier", uav(gone)), Conflict);
  EXPECT_EQ(store_->get_entry(CatalogKind::Uav, carrier)->data.at("camera_id"), used) << "unchanged";
  // a camera freed by its UAV can go
  store_->update_entry(CatalogKind::Uav, carrier, "carrier", {{"name", "carrier"}, {"speed_mps", 8}});
  store_->delete_entry(CatalogKind::Camera, used);

  // the race: a UAV naming a camera and the camera's delete, at once; exactly one of them wins
  int uavs_won = 0, deletes_won = 0;
  for (int round = 0; round < 40; ++round) {
    const Id k = store_->create_entry(CatalogKind::Camera, unique_name("race"), camera);
    std::optional<Id> made;
    bool deleted = false;
    std::thread a([&] {
      try {
        made = store_->create_entry(CatalogKind::Uav, unique_name("racer"), uav(k));
      } catch (const Conflict&) {
      }
    });
    std::thread b([&] {
      try {
        store_->delete_entry(CatalogKind::Camera, k);
        deleted = true;
      } catch (const Conflict&) {
      }
    });
    a.join();
    b.join();
    ASSERT_NE(made.has_value(), deleted) << "round " << round << ": both or neither won";
    if (made) {
      ++uavs_won;
      EXPECT_TRUE(store_->get_entry(CatalogKind::Camera, k));
      store_->delete_entry(CatalogKind::Uav, *made);
    } else {
      ++deletes_won;
    }
  }
  for (const auto& u : store_->list_entries(CatalogKind::Uav)) {
    if (u.data.contains("camera_id")) {
      EXPECT_TRUE(store_->get_entry(CatalogKind::Camera, u.data["camera_id"].get<Id>())) << u.name;
    }
  }
  EXPECT_EQ(uavs_won + deletes_won, 40);
}

// ---- first start, reopening ----

TEST_P(StoreConformance, FirstStartIsClaimedOnce) {
  std::atomic<int> wins{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&] {
      if (store_->claim_first_start()) ++wins;
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(wins.load(), 1) << "every test has a fresh database";
  EXPECT_FALSE(store_->claim_first_start());
  store_.reset();
  store_ = uavcover::testing::open_test_store(url_);
  EXPECT_FALSE(store_->claim_first_start()) << "the claim outlives the process";
}

TEST_P(StoreConformance, ReopeningKeepsDataAndDoesNotMigrateAgain) {
  EXPECT_GT(store_->schema_version(), 0);
  EXPECT_TRUE(store_->ping());
  const int version = store_->schema_version();
  const std::string name = unique_name("kept");
  const Id id = store_->create_mission(revision(name));
  const std::size_t uavs = store_->list_entries(CatalogKind::Uav).size();
  const std::string backend = store_->backend();
  store_.reset();

  store_ = uavcover::testing::open_test_store(url_);
  EXPECT_EQ(store_->backend(), backend);
  EXPECT_EQ(store_->schema_version(), version);
  EXPECT_EQ(store_->list_entries(CatalogKind::Uav).size(), uavs) << "seeds not inserted twice";
  const auto m = store_->get_mission(id);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->name, name);
}

// ---- concurrency ----

TEST_P(StoreConformance, ConcurrentCreatesAllSucceedWithDistinctIds) {
  const std::int64_t before = store_->count_missions();
  constexpr int kThreads = 8, kEach = 50;
  std::vector<std::vector<Id>> made(kThreads);
  std::vector<std::thread> threads;
  std::atomic<int> errors{0};
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      try {
        for (int i = 0; i < kEach; ++i) {
          made[t].push_back(store_->create_mission(revision(unique_name("concurrent"))));
          if (i % 10 == 0) store_->list_missions({});  // readers alongside writers
        }
      } catch (const std::exception& e) {
        ++errors;
        ADD_FAILURE() << e.what();
      }
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(errors.load(), 0);
  std::set<Id> all;
  for (const auto& v : made) all.insert(v.begin(), v.end());
  EXPECT_EQ(all.size(), static_cast<std::size_t>(kThreads * kEach));
  EXPECT_EQ(store_->count_missions(), before + kThreads * kEach);
  for (Id id : all) ASSERT_TRUE(store_->get_mission(id)) << id;
}

TEST_P(StoreConformance, ConcurrentWorkersClaimEachJobOnce) {
  const Id m = mission();
  std::set<Id> queued;
  for (int i = 0; i < 40; ++i) queued.insert(job(m));
  std::mutex mu;
  std::map<Id, int> claims;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      const std::string worker = "worker-" + std::to_string(t);
      try {
        while (auto j = store_->claim_job(worker, 60s, 3)) {
          {
            std::lock_guard lock(mu);
            ++claims[j->id];
          }
          store_->heartbeat(j->id, worker, 60s, 0.5, "working");
          if (!store_->finish_job(j->id, worker, JobState::Done, {{"by", worker}}, nullptr, {})) {
            ADD_FAILURE() << "finish of " << j->id;
          }
        }
      } catch (const std::exception& e) {
        ADD_FAILURE() << e.what();
      }
    });
  for (auto& t : threads) t.join();
  for (Id id : queued) {
    EXPECT_EQ(claims[id], 1) << "job " << id;
    const auto j = store_->get_job(id);
    EXPECT_EQ(j->state, JobState::Done);
    EXPECT_EQ(j->completions, 1);
    EXPECT_EQ(j->attempts, 1);
  }
}

// ---- flights ----

/// A done plan job of mission `m`.
Id done_plan(Store& s, Id m) {
  NewJob j;
  j.mission_id = m;
  j.revision = 1;
  const Id id = s.enqueue(j, 1000000);
  const auto claimed = s.claim_job("test-plan", 60s, 3);
  EXPECT_TRUE(claimed && claimed->id == id);
  EXPECT_TRUE(s.finish_job(id, "test-plan", JobState::Done, {}, nullptr, {}));
  return id;
}

FlightLogRecord record(std::int64_t t, const std::string& uav, const std::string& kind, nlohmann::json data) {
  FlightLogRecord r;
  r.t_ms = t;
  r.uav = uav;
  r.kind = kind;
  r.data = std::move(data);
  return r;
}

TEST_P(StoreConformance, FlightsBelongToDonePlansAndKeepTheirStateAndSnapshot) {
  const Id m = mission();
  const Id queued = job(m);
  NewFlight nf;
  nf.plan_id = queued;
  EXPECT_THROW(store_->create_flight(nf), Conflict) << "a queued plan cannot fly";
  nf.plan_id = 987654321;
  EXPECT_THROW(store_->create_flight(nf), NotFound);
  store_->request_cancel(queued);

  const Id plan = done_plan(*store_, m);
  nf.plan_id = plan;
  nf.config = {{"vehicles", {{{"uav", "A"}, {"endpoint", "udp:127.0.0.1:14550"}}}}};
  nf.snapshot = {{"state", "created"}, {"uavs", nlohmann::json::array()}};
  nf.simulated = true;
  const Id f1 = store_->create_flight(nf);
  nf.simulated = false;
  const Id f2 = store_->create_flight(nf);
  EXPECT_NE(f1, f2);

  auto got = store_->get_flight(f1);
  ASSERT_TRUE(got);
  EXPECT_EQ(got->plan_id, plan);
  EXPECT_EQ(got->mission_id, m);
  EXPECT_EQ(got->state, "created");
  EXPECT_EQ(got->config, nf.config);
  EXPECT_EQ(got->snapshot, nf.snapshot);
  EXPECT_TRUE(got->simulated);
  EXPECT_FALSE(store_->get_flight(f2)->simulated);
  EXPECT_GT(got->created_ms, 0);
  EXPECT_EQ(got->log_records, 0);
  EXPECT_FALSE(store_->get_flight(987654321));

  const auto listed = store_->list_flights(plan, 10);
  ASSERT_EQ(listed.size(), 2u);
  EXPECT_EQ(listed[0].id, f2) << "newest first";
  EXPECT_EQ(listed[1].id, f1);
  EXPECT_EQ(store_->list_flights(plan, 1).size(), 1u);
  EXPECT_TRUE(store_->list_flights(queued, 10).empty());

  const std::int64_t before = got->updated_ms;
  const nlohmann::json flying = {{"state", "flying"}, {"uavs", {{{"uav", "A"}, {"waypoints", "RRCP"}}}}};
  store_->update_flight(f1, "flying", flying);
  got = store_->get_flight(f1);
  EXPECT_EQ(got->state, "flying");
  EXPECT_EQ(got->snapshot, flying);
  EXPECT_GT(got->updated_ms, before);
  EXPECT_THROW(store_->update_flight(987654321, "done", flying), NotFound);

  auto active = [&] {
    std::set<Id> ids;
    for (const auto& f : store_->list_active_flights()) ids.insert(f.id);
    return ids;
  };
  EXPECT_EQ(active(), (std::set<Id>{f1, f2}));
  store_->update_flight(f2, "aborted", nf.snapshot);
  store_->update_flight(f1, "done", flying);
  EXPECT_TRUE(active().empty());

  store_->delete_flight(f2);
  EXPECT_FALSE(store_->get_flight(f2));
  EXPECT_THROW(store_->delete_flight(f2), NotFound);
  EXPECT_EQ(store_->list_flights(plan, 10).size(), 1u);
}

TEST_P(StoreConformance, FlightLogIsNumberedInOrderAndPages) {
  const Id m = mission();
  NewFlight nf;
  nf.plan_id = done_plan(*store_, m);
  const Id f = store_->create_flight(nf);
  const Id other = store_->create_flight(nf);

  EXPECT_EQ(store_->append_flight_log(f, {}), 0) << "an empty batch is no record";
  std::vector<FlightLogRecord> batch;
  for (int i = 0; i < 25; ++i)
    batch.push_back(record(1000 + i, i % 2 ? "A" : "B", "telemetry", {{"i", i}, {"lat", 39.5 + i * 1e-6}}));
  EXPECT_EQ(store_->append_flight_log(f, batch), 25);
  EXPECT_EQ(store_->append_flight_log(other, {record(5, "", "state", {{"state", "ready"}})}), 1)
      << "every flight numbers its own records";
  // text a vehicle sent: quotes, non-ASCII, and bytes that are not UTF-8 (replaced, never an error)
  const std::string status = std::string("Ελλάδα \"low\" battery \xff\xfe");
  EXPECT_EQ(store_->append_flight_log(f, {record(2000, "A", "statustext", {{"text", status}}),
                                          record(2001, "", "state", {{"state", "done"}})}),
            27);
  EXPECT_EQ(store_->get_flight(f)->log_records, 27);

  std::vector<FlightLogRecord> all;
  std::int64_t after = 0;
  int pages = 0;
  for (;;) {
    const auto page = store_->read_flight_log(f, after, 10);
    ++pages;
    all.insert(all.end(), page.items.begin(), page.items.end());
    if (!page.next_after) break;
    EXPECT_EQ(*page.next_after, page.items.back().seq);
    after = *page.next_after;
  }
  EXPECT_EQ(pages, 3);
  ASSERT_EQ(all.size(), 27u);
  for (std::size_t i = 0; i < all.size(); ++i) EXPECT_EQ(all[i].seq, static_cast<std::int64_t>(i + 1));
  for (int i = 0; i < 25; ++i) {
    EXPECT_EQ(all[i].t_ms, 1000 + i);
    EXPECT_EQ(all[i].uav, i % 2 ? "A" : "B");
    EXPECT_EQ(all[i].kind, "telemetry");
    EXPECT_EQ(all[i].data, batch[i].data);
  }
  EXPECT_EQ(all[25].kind, "statustext");
  const std::string text = all[25].data.at("text").get<std::string>();
  EXPECT_TRUE(text.starts_with("Ελλάδα \"low\" battery ")) << text;
  EXPECT_EQ(all[26].data, (nlohmann::json{{"state", "done"}}));
  EXPECT_TRUE(store_->read_flight_log(f, 27, 10).items.empty());
  EXPECT_FALSE(store_->read_flight_log(f, 27, 10).next_after);
  EXPECT_EQ(store_->read_flight_log(other, 0, 10).items.size(), 1u);
  EXPECT_THROW(store_->append_flight_log(987654321, batch), NotFound);

  store_->delete_flight(f);
  EXPECT_TRUE(store_->read_flight_log(f, 0, 100).items.empty()) << "the log goes with its flight";
  EXPECT_EQ(store_->read_flight_log(other, 0, 10).items.size(), 1u);
}

TEST_P(StoreConformance, ConcurrentAppendsToOneFlightGetDistinctConsecutiveSeqs) {
  NewFlight nf;
  nf.plan_id = done_plan(*store_, mission());
  const Id f = store_->create_flight(nf);
  constexpr int kThreads = 4, kBatches = 20, kEach = 5;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      try {
        for (int b = 0; b < kBatches; ++b) {
          std::vector<FlightLogRecord> batch;
          for (int i = 0; i < kEach; ++i)
            batch.push_back(record(b, "U" + std::to_string(t), "telemetry", {{"b", b}, {"i", i}}));
          store_->append_flight_log(f, batch);
        }
      } catch (const std::exception& e) {
        ADD_FAILURE() << e.what();
      }
    });
  for (auto& t : threads) t.join();
  const auto page = store_->read_flight_log(f, 0, 10000);
  ASSERT_EQ(page.items.size(), static_cast<std::size_t>(kThreads * kBatches * kEach));
  std::map<std::string, int> next;  // per thread: batches stay whole and in order
  for (std::size_t k = 0; k < page.items.size(); ++k) {
    const auto& r = page.items[k];
    EXPECT_EQ(r.seq, static_cast<std::int64_t>(k + 1));
    const int b = r.data.at("b"), i = r.data.at("i");
    EXPECT_EQ(b * kEach + i, next[r.uav]++) << "record " << r.seq << " of " << r.uav;
  }
}

TEST_P(StoreConformance, DeleteMissionRefusesWhileAFlightIsActiveThenTakesItsFlights) {
  const Id m = mission();
  const Id plan = done_plan(*store_, m);
  NewFlight nf;
  nf.plan_id = plan;
  nf.state = "flying";
  const Id f = store_->create_flight(nf);
  store_->append_flight_log(f, {record(1, "A", "telemetry", {{"lat", 1}})});
  EXPECT_THROW(store_->delete_mission(m), Conflict);
  EXPECT_TRUE(store_->get_flight(f));
  store_->update_flight(f, "done", {});
  store_->delete_mission(m);
  EXPECT_FALSE(store_->get_flight(f));
  EXPECT_TRUE(store_->read_flight_log(f, 0, 10).items.empty());
  EXPECT_FALSE(store_->get_job(plan));
}

// A child process appends flight-log batches as fast as it can and reports each acknowledged batch's
// last seq through a pipe; the parent kills it with SIGKILL mid-burst, reopens the store and finds every
// acknowledged record, whole (on every backend: SQLite's synchronous=FULL, PostgreSQL's commit).
TEST_P(StoreConformance, KillNineWhileAppendingLosesNoAcknowledgedFlightRecord) {
  NewFlight nf;
  nf.plan_id = done_plan(*store_, mission());
  const Id f = store_->create_flight(nf);
  store_.reset();  // the child opens its own connections; none are shared across fork()
  std::int64_t acknowledged = 0;
  int batches = 0;
  const auto append_batches = [&](const std::function<void(std::int64_t)>& ack) {
    auto s = uavcover::testing::open_test_store(url_);
    for (int b = 0;; ++b) {
      std::vector<FlightLogRecord> batch;
      for (int i = 0; i < 7; ++i)
        batch.push_back(record(b, "A", "telemetry", {{"b", b}, {"i", i}, {"pad", std::string(40, 'x')}}));
      ack(s->append_flight_log(f, batch));
    }
  };
  ASSERT_TRUE(uavcover::testing::kill_nine_during(append_batches, [&](std::int64_t last) {
    EXPECT_EQ(last, acknowledged + 7);
    acknowledged = last;
    return ++batches >= 60;
  })) << "the child stopped early";

  store_ = uavcover::testing::open_test_store(url_);
  const auto page = store_->read_flight_log(f, 0, 10000);
  ASSERT_GE(static_cast<std::int64_t>(page.items.size()), acknowledged) << "acknowledged records lost";
  EXPECT_EQ(page.items.size() % 7, 0u) << "a batch is all or nothing";
  for (std::size_t k = 0; k < page.items.size(); ++k) {
    EXPECT_EQ(page.items[k].seq, static_cast<std::int64_t>(k + 1));
    EXPECT_EQ(page.items[k].data.at("b"), static_cast<int>(k / 7));
    EXPECT_EQ(page.items[k].data.at("i"), static_cast<int>(k % 7));
  }
  EXPECT_EQ(store_->get_flight(f)->log_records, static_cast<std::int64_t>(page.items.size()));
}

// ---- retention and the export cache (issue 27, docs/cache.md) ----

namespace {

/// A done plan job with the given artifacts.
Id done_plan_with(Store& s, Id m, const Artifacts& artifacts) {
  NewJob j;
  j.mission_id = m;
  j.revision = 1;
  const Id id = s.enqueue(j, 1000000);
  const auto claimed = s.claim_job("test-plan", 60s, 3);
  EXPECT_TRUE(claimed && claimed->id == id);
  EXPECT_TRUE(s.finish_job(id, "test-plan", JobState::Done, {}, nullptr, artifacts));
  return id;
}

Artifacts plan_files(const std::string& plan, const std::string& tag) {
  return {{"plan.json", "application/json", plan},
          {"paths.geojson", "application/geo+json", "{\"paths\":\"" + plan + "\"}"},
          {"plan.png", "image/png", "png of " + tag}};
}

}  // namespace

TEST_P(StoreConformance, DeleteJobTakesItsArtifactsAndCacheAndRefusesWhileAFlightUsesIt) {
  const Id m = mission();
  const auto [blobs0, bytes0] = store_->count_blobs();
  const std::string plan = unique_name("plan");
  const Id a = done_plan_with(*store_, m, plan_files(plan, unique_name("a")));
  const Id b = done_plan_with(*store_, m, plan_files(plan, unique_name("b")));  // the same plan
  const std::string prefix = plan_cache_prefix(store_->get_job(a)->artifacts);
  ASSERT_EQ(prefix.size(), 64u);
  EXPECT_EQ(prefix, plan_cache_prefix(store_->get_job(b)->artifacts)) << "content-addressed";
  const std::string key = prefix + "/qgc";
  ASSERT_TRUE(
      store_->put_cache(key, {{"export/x.plan", "application/json", unique_name("qgc bytes")}}, 1 << 20));
  EXPECT_EQ(store_->count_blobs().first, blobs0 + 5) << "plan.json, paths.geojson, two pictures, one export";

  // a plan a flight uses is refused, until the flight is deleted
  NewFlight nf;
  nf.plan_id = a;
  const Id f = store_->create_flight(nf);
  EXPECT_THROW(store_->delete_job(a), Conflict);
  store_->delete_flight(f);
  store_->delete_job(a);
  EXPECT_FALSE(store_->get_job(a));
  EXPECT_FALSE(store_->get_artifact(a, "plan.json"));
  EXPECT_THROW(store_->delete_job(a), NotFound);
  EXPECT_TRUE(store_->cache_entry(key)) << "job b holds the same plan: its exports stay";
  EXPECT_EQ(store_->count_blobs().first, blobs0 + 4) << "a's own picture is collected";
  EXPECT_TRUE(store_->get_artifact(b, "plan.json"));

  store_->delete_job(b);
  EXPECT_FALSE(store_->cache_entry(key)) << "no job holds the plan any more: its exports go";
  EXPECT_EQ(store_->count_blobs(), std::make_pair(blobs0, bytes0)) << "every blob of theirs is collected";
  EXPECT_EQ(store_->collect_orphan_blobs(), 0) << "nothing left behind";

  // queued and running jobs are cancelled, not deleted
  const Id q = job(m);
  EXPECT_THROW(store_->delete_job(q), Conflict);
  store_->request_cancel(q);
  store_->delete_job(q);  // cancelled: terminal
  EXPECT_FALSE(store_->get_job(q));
  EXPECT_THROW(store_->delete_job(987654321), NotFound);
}

TEST_P(StoreConformance, PrunePlansDeletesTheOldestDonePlansButNeverOneAFlightUses) {
  const Id m = mission();
  const Id other = mission();
  std::vector<Id> plans;
  for (int i = 0; i < 5; ++i)
    plans.push_back(done_plan_with(*store_, m, plan_files(unique_name("p"), unique_name("t"))));
  const Id foreign = done_plan_with(*store_, other, plan_files(unique_name("o"), unique_name("t")));
  const Id failed = job(m);
  ASSERT_EQ(store_->claim_job("w", 60s, 3)->id, failed);
  ASSERT_TRUE(store_->finish_job(failed, "w", JobState::Failed, {}, {{"field", ""}, {"message", "x"}}, {}));
  NewFlight nf;
  nf.plan_id = plans[0];  // the oldest flies
  store_->create_flight(nf);
  const auto blobs = store_->count_blobs().first;

  EXPECT_EQ(store_->prune_plans(m, 2), (std::vector<Id>{plans[1], plans[2]})) << "oldest first";
  for (const Id kept : {plans[0], plans[3], plans[4], foreign, failed})
    EXPECT_TRUE(store_->get_job(kept)) << kept;
  for (const Id gone : {plans[1], plans[2]}) EXPECT_FALSE(store_->get_job(gone)) << gone;
  EXPECT_EQ(store_->count_blobs().first, blobs - 6) << "their blobs are collected";
  EXPECT_TRUE(store_->prune_plans(m, 2).empty()) << "the newest two and the flown one stay";
  EXPECT_EQ(store_->prune_plans(m, 0), (std::vector<Id>{plans[3], plans[4]}));
  EXPECT_TRUE(store_->get_job(plans[0])) << "a plan a flight uses is never pruned";
}

TEST_P(StoreConformance, TheExportCacheEvictsTheLeastRecentlyUsedUnderItsCap) {
  const std::string p = unique_name("cache");
  auto files = [&](const std::string& k, std::size_t n) {
    return Artifacts{{"export/" + k + ".a", "text/plain", std::string(n, 'a') + k},
                     {"export/" + k + ".b", "text/plain", std::string(n, 'b') + k}};
  };
  const std::int64_t cap = 1000;
  ASSERT_TRUE(store_->put_cache(p + "/1", files("1", 200), cap));
  ASSERT_TRUE(store_->put_cache(p + "/2", files("2", 200), cap));
  const auto blobs = store_->count_blobs().first;
  ASSERT_TRUE(store_->cache_entry(p + "/1"));  // used: 2 is now the least recently used
  ASSERT_TRUE(store_->put_cache(p + "/3", files("3", 200), cap));
  EXPECT_FALSE(store_->cache_entry(p + "/2")) << "the least recently used went";
  const auto one = store_->cache_entry(p + "/1");
  ASSERT_TRUE(one);
  ASSERT_EQ(one->size(), 2u);
  EXPECT_EQ((*one)[0].name, "export/1.a");
  EXPECT_EQ((*one)[0].size, 201);
  EXPECT_EQ(store_->cached_file(p + "/1", "export/1.b")->bytes, std::string(200, 'b') + "1");
  EXPECT_TRUE(store_->cache_entry(p + "/3"));
  EXPECT_EQ(store_->count_blobs().first, blobs) << "2's blobs went, 3's came";
  const auto [held, entries] = store_->cache_size();
  EXPECT_LE(held, cap);
  EXPECT_EQ(held, 4 * 201);
  EXPECT_EQ(entries, 2);
  // an entry larger than the cap alone is not stored, and evicts nothing
  EXPECT_FALSE(store_->put_cache(p + "/big", files("big", 600), cap));
  EXPECT_FALSE(store_->cache_entry(p + "/big"));
  EXPECT_EQ(store_->cache_size().second, 2);
  // storing a key again replaces its files
  ASSERT_TRUE(store_->put_cache(p + "/3", {{"export/3.c", "text/plain", "c"}}, cap));
  EXPECT_EQ(store_->cache_entry(p + "/3")->size(), 1u);
  EXPECT_FALSE(store_->cached_file(p + "/3", "export/3.a"));
  EXPECT_EQ(store_->collect_orphan_blobs(), 0);
}

TEST_P(StoreConformance, KillNineWhileCachingLosesNoAcknowledgedEntryAndLeavesNoPartOne) {
  const std::string p = unique_name("k9");
  store_.reset();
  int acknowledged = 0;
  auto files = [](int i) {
    Artifacts a;
    for (int k = 0; k < 4; ++k)
      a.push_back({"export/" + std::to_string(k) + ".x", "text/plain",
                   std::string(5000 + i, static_cast<char>('a' + k)) + std::to_string(i)});
    return a;
  };
  ASSERT_TRUE(uavcover::testing::kill_nine_during(
      [&](const std::function<void(std::int64_t)>& ack) {
        auto s = uavcover::testing::open_test_store(url_);
        for (int i = 0;; ++i) {
          s->put_cache(p + "/" + std::to_string(i), files(i), std::int64_t{1} << 30);
          ack(i);
        }
      },
      [&](std::int64_t last) {
        acknowledged = static_cast<int>(last);
        return last >= 40;
      }))
      << "the child stopped early";
  store_ = uavcover::testing::open_test_store(url_);
  for (int i = 0;; ++i) {
    const auto e = store_->cache_entry(p + "/" + std::to_string(i));
    if (!e) {
      EXPECT_GT(i, acknowledged) << "acknowledged entry " << i << " lost";
      break;
    }
    ASSERT_EQ(e->size(), 4u) << "entry " << i << " is all or nothing";
    for (const auto& f : files(i))
      EXPECT_TRUE(store_->cached_file(p + "/" + std::to_string(i), f.name)->bytes == f.bytes);
  }
  EXPECT_EQ(store_->collect_orphan_blobs(), 0);
}

// Issue 31: elevation models are stored content-addressed: the same bytes twice are one DEM (the first
// name kept), bytes come back exactly (binary, with NUL bytes), and the list is in id order.
TEST_P(StoreConformance, DemsAreContentAddressed) {
  std::string tif("II*\0", 4);
  for (int i = 0; i < 3000; ++i) tif += static_cast<char>(i * 37 % 256);
  const nlohmann::json info{{"width", 10}, {"height", 12}};
  const auto [a, created] = store_->put_dem("hill.tif", tif, info);
  EXPECT_TRUE(created);
  const auto [b, again] = store_->put_dem("copy.tif", tif, info);
  EXPECT_FALSE(again);
  EXPECT_EQ(a, b);
  const auto [c, other] = store_->put_dem("other.tif", tif + "x", info);
  EXPECT_TRUE(other);
  EXPECT_NE(c, a);
  const auto d = store_->get_dem(a);
  ASSERT_TRUE(d.has_value());
  EXPECT_EQ(d->name, "hill.tif");
  EXPECT_EQ(d->size, static_cast<std::int64_t>(tif.size()));
  EXPECT_EQ(d->sha256.size(), 64U);
  EXPECT_EQ(d->info, info);
  EXPECT_EQ(*store_->dem_bytes(a), tif);
  EXPECT_FALSE(store_->get_dem(c + 1000).has_value());
  EXPECT_FALSE(store_->dem_bytes(c + 1000).has_value());
  const auto list = store_->list_dems(1000);
  ASSERT_GE(list.size(), 2U);
  EXPECT_LT(list.front().id, list.back().id);
}

// Two operators upload the same GeoTIFF at once: one row, both get its id, no error (PostgreSQL's
// ON CONFLICT DO NOTHING leaves the waiting insert's snapshot without the other's row).
TEST_P(StoreConformance, ConcurrentUploadsOfOneDemGiveOneRow) {
  constexpr int kThreads = 8, kRounds = 10;
  for (int round = 0; round < kRounds; ++round) {
    std::string tif("II*\0", 4);
    tif += unique_name("dem") + std::to_string(round);
    for (int i = 0; i < 2000; ++i) tif += static_cast<char>((i * 31 + round) % 256);
    std::vector<std::pair<Id, bool>> got(kThreads);
    std::atomic<int> errors{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
      threads.emplace_back([&, t] {
        try {
          got[t] = store_->put_dem("same.tif", tif, nlohmann::json::object());
        } catch (const std::exception& e) {
          ++errors;
          ADD_FAILURE() << e.what();
        }
      });
    for (auto& t : threads) t.join();
    ASSERT_EQ(errors.load(), 0);
    int created = 0;
    for (const auto& [id, made] : got) {
      EXPECT_EQ(id, got[0].first);
      created += made ? 1 : 0;
    }
    EXPECT_EQ(created, 1) << "round " << round;
    EXPECT_EQ(*store_->dem_bytes(got[0].first), tif);
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, StoreConformance,
                         ::testing::ValuesIn(uavcover::testing::store_test_urls()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           return info.param.starts_with("sqlite:") ? std::string("sqlite")
                                                                    : std::string("postgresql");
                         });

}  // namespace
