// Everything a finished plan leaves in its folder, shared by the CLI and the server:
// paths.geojson, plan.json (with coverage and cost unless turned off), pictures and exports.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "uavcover/plan.hpp"

namespace uavcover::io {

struct PlanDirOptions {
  bool evaluate = true;  ///< coverage simulation + time/cost model (eq. 15 and trajectories) into plan.json
  bool images = true;    ///< plan.png, plan.svg, heatmap.png, histogram.png
  std::vector<std::string> exports;  ///< export formats (exporting::known_formats())
};

struct PlanDirResult {
  std::vector<std::filesystem::path> files;
  double poc = -1, pooc = -1;  ///< when evaluated
  double flight_time_min = -1, total_time_min = -1, cost_eur = -1;
  double trajectory_flight_time_min = -1;  ///< the same from the time-parameterised trajectories
};

/// Checks export format names up front (InputError naming --export).
void check_export_formats(const std::vector<std::string>& formats);

/// Writes the plan folder. The plan itself is written first, so an export failure loses nothing.
PlanDirResult write_plan_dir(const Plan& plan, const std::filesystem::path& dir,
                             const PlanDirOptions& options);

}  // namespace uavcover::io
