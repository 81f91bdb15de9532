#include "uavcover/context.hpp"

#include <algorithm>

#include "uavcover/error.hpp"

namespace uavcover {

Context::Context(Progress progress, std::stop_token stop, std::optional<Clock::duration> time_limit)
    : progress_(std::move(progress)), stop_(std::move(stop)) {
  if (time_limit) deadline_ = Clock::now() + *time_limit;
}

void Context::report(std::string_view stage, double fraction) const {
  if (progress_) progress_(stage, std::clamp(fraction, 0.0, 1.0));
}

void Context::check() const {
  if (stop_requested()) throw Cancelled();
  if (time_up()) throw TimeLimitReached("the time limit was reached before a complete plan was found");
}

}  // namespace uavcover
