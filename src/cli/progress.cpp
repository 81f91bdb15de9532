#include "cli/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

namespace uavcover::cli {

namespace {
bool g_drawn = false;
}

Progress make_progress_bar(bool quiet) {
  if (quiet || isatty(STDERR_FILENO) == 0) return {};
  auto last = std::make_shared<std::chrono::steady_clock::time_point>();
  auto last_stage = std::make_shared<std::string>();
  return [last, last_stage](std::string_view stage, double fraction) {
    const auto now = std::chrono::steady_clock::now();
    if (stage == *last_stage && fraction < 1.0 && now - *last < std::chrono::milliseconds(50)) return;
    *last = now;
    *last_stage = std::string(stage);
    constexpr int width = 30;
    const int filled = static_cast<int>(std::lround(std::clamp(fraction, 0.0, 1.0) * width));
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(width, '.');
    std::fprintf(stderr, "\r%-16.16s [%s] %3d%%", std::string(stage).c_str(), bar.c_str(),
                 static_cast<int>(std::lround(std::clamp(fraction, 0.0, 1.0) * 100)));
    std::fflush(stderr);
    g_drawn = true;
  };
}

void finish_progress_bar() {
  if (g_drawn) std::fputc('\n', stderr);
  g_drawn = false;
}

}  // namespace uavcover::cli
