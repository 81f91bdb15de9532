// The thesis rectangle (Mondinelli 2025 Table 5.3: 100 m east-west, 200 m north-south, ds 10 m, no camera
// block, 3 UAVs) planned by boustrophedon: the field the refly and photo tests fly over.
#pragma once

#include <filesystem>

#include "support/files.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover::testing {

inline Plan rectangle_plan() {
  Mission m = parse_mission(
      slurp(std::filesystem::path(UAVCOVER_BENCH_DATA) / "mondinelli2025" / "rectangle_3uav.json"));
  m.planner = "boustrophedon";
  m.planner_params = nlohmann::json::object();
  return plan(m);
}

}  // namespace uavcover::testing
