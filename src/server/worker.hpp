// The planning workers: threads that lease jobs from the store's queue, run them through the job use
// cases (never on I/O threads), keep their leases alive with heartbeats (progress, stage) and stop a
// job within a heartbeat when it is cancelled or its lease is lost.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "server/terrain_source.hpp"
#include "store/store.hpp"
#include "usecases/jobs.hpp"

namespace uavcover::server {

/// The use case that runs a stored job of this kind.
usecases::JobType job_type(store::JobKind kind);

struct WorkerConfig {
  int threads = 1;
  std::chrono::milliseconds lease{10000};
  int max_attempts = 3;
  std::chrono::milliseconds heartbeat{200};  ///< at most a quarter of the lease is used
  std::chrono::milliseconds idle{150};       ///< wait between claims when the queue is empty
  /// Retention: after a plan job ends done, its mission's done plans beyond the newest `keep_plans`
  /// are deleted, oldest first, except those a flight uses (store::Store::prune_plans). 0: all kept.
  int keep_plans = 0;
  /// How stored missions are parsed (`serve --max-cells`: the same options as the API's).
  ParseOptions parse = {};
  /// `serve --dem-dir` (issue 31): the tiles of missions with "terrain": {"source": "server"}.
  DemDir dem_dir = {};
  /// Called after a job ended and was recorded (state done, failed or cancelled), with its run time.
  std::function<void(const store::Job& job, store::JobState state, double seconds)> on_job_finished;
};

class WorkerPool {
 public:
  /// `name` empty: hostname-pid-random. The store must outlive the pool.
  WorkerPool(store::Store& store, WorkerConfig config, std::string name = {});
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  /// Starts the threads (once).
  void start();
  /// Stops taking jobs, stops running ones and joins the threads. A job stopped this way is not
  /// recorded: its lease expires and another server (or this one after a restart) runs it again.
  void stop();

  [[nodiscard]] const std::string& name() const noexcept { return name_; }

  /// hostname-pid-random.
  static std::string unique_name();

 private:
  void loop(const std::stop_token& stop);
  void run(store::Job job, const std::stop_token& pool_stop);

  store::Store& store_;
  WorkerConfig config_;
  std::string name_;
  std::mutex mutex_;
  std::condition_variable_any wake_;
  std::vector<std::jthread> threads_;
};

}  // namespace uavcover::server
