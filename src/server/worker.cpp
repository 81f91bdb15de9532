#include "server/worker.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <random>
#include <stop_token>

#include "engine/test_hold.hpp"
#include "server/terrain_source.hpp"
#include "uavcover/error.hpp"
#include "uavcover/mission.hpp"
#include "usecases/jobs.hpp"

namespace uavcover::server {
namespace {

nlohmann::json error_json(const std::string& field, const std::string& message) {
  return {{"field", field}, {"message", message}};
}

/// What the heartbeat learnt and the progress callback reported, shared with the working thread.
struct RunState {
  std::mutex mutex;
  std::condition_variable cv;
  bool done = false;  ///< the work ended: the heartbeat stops
  std::string stage;
  double progress = 0.0;
  std::atomic<bool> cancel{false};    ///< the client cancelled (DELETE)
  std::atomic<bool> lost{false};      ///< the lease is no longer ours
  std::atomic<bool> shutdown{false};  ///< the pool is stopping
};

}  // namespace

usecases::JobType job_type(store::JobKind kind) {
  switch (kind) {
    case store::JobKind::Study:
      return usecases::JobType::Study;
    case store::JobKind::Comparison:
      return usecases::JobType::Comparison;
    case store::JobKind::Plan:
      break;
  }
  return usecases::JobType::Plan;
}

WorkerPool::WorkerPool(store::Store& store, WorkerConfig config, std::string name)
    : store_(store), config_(std::move(config)), name_(name.empty() ? unique_name() : std::move(name)) {
  config_.threads = std::max(1, config_.threads);
  config_.lease = std::max(config_.lease, std::chrono::milliseconds(100));
  config_.heartbeat = std::clamp(config_.heartbeat, std::chrono::milliseconds(10), config_.lease / 4);
}

WorkerPool::~WorkerPool() { stop(); }

std::string WorkerPool::unique_name() {
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) != 0 || host[0] == '\0') std::snprintf(host, sizeof host, "host");
  std::random_device rd;
  char buf[400];
  std::snprintf(buf, sizeof buf, "%s-%ld-%08x", host, static_cast<long>(getpid()),
                static_cast<unsigned>(rd()));
  return buf;
}

void WorkerPool::start() {
  if (!threads_.empty()) return;
  for (int i = 0; i < config_.threads; ++i)
    threads_.emplace_back([this](const std::stop_token& st) { loop(st); });
  spdlog::info("worker {}: {} planning thread(s)", name_, config_.threads);
}

void WorkerPool::stop() {
  for (auto& t : threads_) t.request_stop();
  wake_.notify_all();
  threads_.clear();  // joins
}

void WorkerPool::loop(const std::stop_token& stop) {
  int failures = 0;  // claims failed in a row (the database is down): wait longer, log once
  while (!stop.stop_requested()) {
    std::optional<store::Job> job;
    try {
      job = store_.claim_job(name_, config_.lease, config_.max_attempts);
      if (failures > 0) spdlog::info("worker {}: the database answers again", name_);
      failures = 0;
    } catch (const std::exception& e) {
      if (failures++ == 0) spdlog::warn("worker {}: cannot take a job: {}", name_, e.what());
    }
    if (job) {
      run(std::move(*job), stop);
      continue;
    }
    const auto wait = failures == 0 ? config_.idle
                                    : std::min(config_.idle * (1 << std::min(failures, 4)),
                                               std::chrono::milliseconds(2000));
    std::unique_lock lock(mutex_);
    wake_.wait_for(lock, stop, wait, [] { return false; });
  }
}

void WorkerPool::run(store::Job job, const std::stop_token& pool_stop) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string label = store::to_string(job.kind) + " job " + std::to_string(job.id);
  spdlog::info("worker {}: {} (mission {} revision {}), attempt {}", name_, label, job.mission_id,
               job.revision, job.attempts);

  auto finish = [&](store::JobState state, const nlohmann::json& result, const nlohmann::json& error,
                    const Artifacts& artifacts) {
    try {
      if (!store_.finish_job(job.id, name_, state, result, error, artifacts)) {
        spdlog::warn("worker {}: {} ended but its lease was lost; result dropped", name_, label);
        return;
      }
      if (state == store::JobState::Done) {
        // the store records a done as cancelled when the cancel came while storing
        if (const auto recorded = store_.get_job(job.id)) state = recorded->state;
      }
    } catch (const std::exception& e) {
      spdlog::error("worker {}: {}: cannot record the end: {}", name_, label, e.what());
      return;
    }
    if (state == store::JobState::Done && job.kind == store::JobKind::Plan && config_.keep_plans > 0) {
      try {
        const auto gone = store_.prune_plans(job.mission_id, config_.keep_plans);
        if (!gone.empty())
          spdlog::info("worker {}: mission {}: {} older plan(s) deleted (--keep-plans {})", name_,
                       job.mission_id, gone.size(), config_.keep_plans);
      } catch (const std::exception& e) {
        spdlog::warn("worker {}: mission {}: retention failed: {}", name_, job.mission_id, e.what());
      }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    spdlog::info("worker {}: {} {} in {:.3f} s", name_, label, store::to_string(state), seconds);
    if (config_.on_job_finished) config_.on_job_finished(job, state, seconds);
  };

  Mission mission;
  try {
    const auto rev = store_.get_mission(job.mission_id, job.revision);
    if (!rev) {
      finish(store::JobState::Failed, nlohmann::json::object(),
             error_json("revision", "mission " + std::to_string(job.mission_id) + " revision " +
                                        std::to_string(job.revision) + " no longer exists"),
             {});
      return;
    }
    mission = parse_mission(rev->document, config_.parse);
  } catch (const InputError& e) {
    finish(store::JobState::Failed, nlohmann::json::object(), error_json(e.field(), e.what()), {});
    return;
  } catch (const std::exception& e) {
    // the database failed: leave the job, its lease expires and it runs again
    spdlog::error("worker {}: {}: cannot load the mission: {}", name_, label, e.what());
    return;
  }

  RunState st;
  std::stop_source source;
  std::stop_callback on_shutdown(pool_stop, [&] {
    st.shutdown = true;
    source.request_stop();
  });
  const auto interval = config_.heartbeat;
  std::thread heartbeat([&] {
    std::unique_lock lock(st.mutex);
    while (!st.done) {
      st.cv.wait_for(lock, interval, [&] { return st.done; });
      if (st.done) break;
      const std::string stage = st.stage;
      const double progress = st.progress;
      lock.unlock();
      try {
        const store::LeaseStatus s = store_.heartbeat(job.id, name_, config_.lease, progress, stage);
        if (!s.held) {
          st.lost = true;
          source.request_stop();
        } else if (s.cancel_requested && !st.cancel) {
          st.cancel = true;
          source.request_stop();
        }
      } catch (const std::exception& e) {
        spdlog::warn("worker {}: {}: heartbeat failed: {}", name_, label, e.what());
      }
      lock.lock();
      if (st.lost) break;
    }
  });

  const Context ctx(
      [&st](std::string_view stage, double fraction) {
        std::lock_guard lock(st.mutex);
        if (st.stage != stage) st.stage.assign(stage);
        st.progress = fraction;
      },
      source.get_token());

  enum class Outcome { Done, Cancelled, Failed, Drop };
  Outcome outcome = Outcome::Failed;
  usecases::JobResult result;
  nlohmann::json error;
  try {
    // the ground heights of a stored DEM or the server's tiles (issue 31), read on this pool
    ctx.report("terrain", 0.0);
    load_server_terrain(mission, store_, config_.dem_dir);
    if (ctx.stop_requested()) throw Cancelled();
    result = usecases::run_job(job_type(job.kind), mission, job.params, ctx);
    // storing: a cancel that came meanwhile wins (the store also records a late one as cancelled)
    ctx.report("storing", 1.0);
    engine::test_hold(ctx, "storing", mission.name);
    if (ctx.stop_requested()) throw Cancelled();
    outcome = Outcome::Done;
  } catch (const Cancelled&) {
    outcome = st.cancel || !(st.shutdown || st.lost) ? Outcome::Cancelled : Outcome::Drop;
  } catch (const TimeLimitReached& e) {
    error = error_json("time_limit_s", e.what());
  } catch (const InputError& e) {
    error = error_json(e.field(), e.what());
  } catch (const std::exception& e) {
    spdlog::error("worker {}: {} failed: {}", name_, label, e.what());
    error = error_json("", "internal error");
  } catch (...) {
    spdlog::error("worker {}: {} failed with an unknown exception", name_, label);
    error = error_json("", "internal error");
  }
  {
    std::lock_guard lock(st.mutex);
    st.done = true;
  }
  st.cv.notify_all();
  heartbeat.join();

  if (st.lost) {
    spdlog::warn("worker {}: {} lost its lease; result dropped", name_, label);
    return;
  }
  switch (outcome) {
    case Outcome::Done:
      finish(store::JobState::Done, result.result, nullptr, result.artifacts);
      break;
    case Outcome::Cancelled:
      finish(store::JobState::Cancelled, nlohmann::json::object(), nullptr, {});
      break;
    case Outcome::Failed:
      if (st.shutdown && !st.cancel) {
        // stopped by the shutdown midway: leave it for the next lease
        spdlog::info("worker {}: {} interrupted by the shutdown; left for another run", name_, label);
        break;
      }
      finish(store::JobState::Failed, nlohmann::json::object(), error, {});
      break;
    case Outcome::Drop:
      spdlog::info("worker {}: {} interrupted by the shutdown; left for another run", name_, label);
      break;
  }
}

}  // namespace uavcover::server
