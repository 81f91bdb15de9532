// The context of long work (planning, evaluation, studies): progress reports, a stop token and a
// time budget. The CLI stops it on Ctrl-C; the server will stop it when a job is cancelled.
#pragma once

#include <chrono>
#include <functional>
#include <optional>
#include <stop_token>
#include <string_view>

namespace uavcover {

/// Progress callback: stage name and fraction done in [0, 1]. Called from the working thread.
using Progress = std::function<void(std::string_view stage, double fraction)>;

class Context {
 public:
  using Clock = std::chrono::steady_clock;

  Context() = default;
  /// `time_limit` counts from construction.
  explicit Context(Progress progress, std::stop_token stop = {},
                   std::optional<Clock::duration> time_limit = std::nullopt);

  /// Reports progress of `stage` (fraction clamped to [0, 1]).
  void report(std::string_view stage, double fraction) const;
  /// A stop was requested (Ctrl-C, a cancelled job).
  [[nodiscard]] bool stop_requested() const noexcept { return stop_.stop_requested(); }
  /// The time budget is spent.
  [[nodiscard]] bool time_up() const noexcept { return deadline_ && Clock::now() >= *deadline_; }
  /// Either of the two: work should end now, returning the best complete result if it has one.
  [[nodiscard]] bool should_stop() const noexcept { return stop_requested() || time_up(); }
  /// Throws Cancelled when a stop was requested, TimeLimitReached when the time is up.
  void check() const;

  /// The same stop token and deadline, with progress sent to `progress` (e.g. mapped into a larger job).
  [[nodiscard]] Context with_progress(Progress progress) const {
    Context c = *this;
    c.progress_ = std::move(progress);
    return c;
  }

  /// The same progress and stop token, with the deadline brought forward to now + `limit` (never later
  /// than the current one).
  [[nodiscard]] Context with_time_limit(Clock::duration limit) const {
    Context c = *this;
    const auto d = Clock::now() + limit;
    if (!c.deadline_ || d < *c.deadline_) c.deadline_ = d;
    return c;
  }

  [[nodiscard]] const std::optional<Clock::time_point>& deadline() const noexcept { return deadline_; }

 private:
  Progress progress_;
  std::stop_token stop_;
  std::optional<Clock::time_point> deadline_;
};

}  // namespace uavcover
