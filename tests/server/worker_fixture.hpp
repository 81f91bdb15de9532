// The worker tests' fixture: a store, the API router over it and a WorkerPool of one thread that runs
// the jobs queued through the API (worker_test.cpp, terrain_test.cpp).
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <thread>

#include "server/api_fixture.hpp"
#include "server/worker.hpp"

namespace uavcover::server::testing {

class WorkerTest : public ApiTest {
 protected:
  void start_workers() {
    WorkerConfig config;
    config.threads = 1;
    config.lease = std::chrono::milliseconds(2000);
    config.heartbeat = std::chrono::milliseconds(100);
    config.idle = std::chrono::milliseconds(50);
    config.dem_dir = ctx_->config.dem_dir;  // the API's (issue 31)
    config.on_job_finished = [this](const store::Job& job, store::JobState state, double seconds) {
      EXPECT_GE(seconds, 0.0);
      if (job.kind == store::JobKind::Plan && state == store::JobState::Done) ++plans_done_;
    };
    pool_ = std::make_unique<WorkerPool>(*store_, config);
    pool_->start();
  }
  void TearDown() override {
    pool_.reset();
    ApiTest::TearDown();
  }

  /// Polls the job until `until` holds or `timeout` passes; returns the last Job JSON.
  nlohmann::json wait_job(const std::string& url, const std::function<bool(const nlohmann::json&)>& until,
                          std::chrono::seconds timeout = std::chrono::seconds(600)) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    nlohmann::json job;
    while (std::chrono::steady_clock::now() < end) {
      const Answer a = call("GET", url);
      EXPECT_EQ(a.status, 200) << a.body;
      job = a.json();
      if (until(job)) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return job;
  }

  static bool terminal(const nlohmann::json& job) {
    const std::string s = job.at("state");
    return s == "done" || s == "failed" || s == "cancelled";
  }

  std::unique_ptr<WorkerPool> pool_;
  std::atomic<int> plans_done_{0};
};

}  // namespace uavcover::server::testing
