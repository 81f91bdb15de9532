// Missions and plan folders as the command line reads them: with the elevation model the mission names
// (terrain.dem, a relative name resolved against the mission file's folder) read into the mission.
#pragma once

#include <filesystem>
#include <string>

#include "io/dem.hpp"
#include "io/plan_io.hpp"
#include "uavcover/mission.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::cli {

inline Mission read_mission(const std::string& path, const ParseOptions& options = {}) {
  Mission m = parse_mission(io::read_text_file(path, "MISSION"), options);
  io::load_terrain(m, std::filesystem::absolute(path).parent_path());
  return m;
}

inline Plan read_plan_dir(const std::string& dir) {
  Plan p = io::load_plan_dir(dir);
  io::load_terrain(p.mission, std::filesystem::absolute(dir));
  return p;
}

}  // namespace uavcover::cli
