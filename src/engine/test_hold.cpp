#include "engine/test_hold.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace uavcover::engine {
namespace {

struct HoldPoint {
  std::string stage;
  std::optional<std::string> mission;  ///< only this mission's work is held
};

/// UAVCOVER_TEST_HOLD_STAGE, read once: "stage[@mission name],..."
const std::vector<HoldPoint>& hold_points() {
  static const std::vector<HoldPoint> points = [] {
    std::vector<HoldPoint> list;
    const char* env = std::getenv("UAVCOVER_TEST_HOLD_STAGE");
    if (env == nullptr) return list;
    const std::string text(env);
    std::size_t from = 0;
    while (from < text.size()) {
      const std::size_t comma = std::min(text.find(',', from), text.size());
      const std::string entry = text.substr(from, comma - from);
      from = comma + 1;
      if (entry.empty()) continue;
      const std::size_t at = entry.find('@');
      if (at == std::string::npos)
        list.push_back({entry, std::nullopt});
      else
        list.push_back({entry.substr(0, at), entry.substr(at + 1)});
    }
    return list;
  }();
  return points;
}

}  // namespace

void test_hold(const Context& ctx, std::string_view stage, std::string_view mission_name) {
  const auto& points = hold_points();
  if (points.empty()) return;
  const bool held = std::any_of(points.begin(), points.end(), [&](const HoldPoint& p) {
    return p.stage == stage && (!p.mission || *p.mission == mission_name);
  });
  if (!held) return;
  std::fprintf(stderr, "uavcover: test hold: %.*s\n", static_cast<int>(stage.size()), stage.data());
  std::fflush(stderr);
  // a test hook: polling the Context every 10 ms is plenty (a stop lands within that)
  const auto until = Context::Clock::now() + std::chrono::duration_cast<Context::Clock::duration>(
                                                 std::chrono::duration<double>(kTestHoldMaxS));
  while (!ctx.should_stop() && Context::Clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
}

}  // namespace uavcover::engine
