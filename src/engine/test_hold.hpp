// A testing hook, not a feature (docs/stops.md): holds a command or a job at a known stage until it is
// stopped, so that tests of stops and time limits never depend on how fast the work is.
#pragma once

#include <string_view>

#include "uavcover/context.hpp"

namespace uavcover::engine {

/// The longest a hold lasts: then the work goes on as if there were no hold (nothing can hang).
constexpr double kTestHoldMaxS = 60.0;

/// When the environment variable UAVCOVER_TEST_HOLD_STAGE lists `stage` (a comma-separated list of
/// entries "stage" or "stage@mission name"; stages: planning, evaluation, pictures, exports, storing),
/// for any mission or for `mission_name`: writes "uavcover: test hold: <stage>" on stderr (the caller
/// has reported the stage through ctx, so a job shows it) and waits until ctx should stop (a stop
/// request or its deadline) or kTestHoldMaxS have passed. The caller's next check then lands the stop.
/// Without the variable it returns at once. The variable is read once per process.
void test_hold(const Context& ctx, std::string_view stage, std::string_view mission_name);

}  // namespace uavcover::engine
