// `evaluate` as a use case: any tool's paths (GeoJSON LineStrings per UAV) matched to the mission's
// UAVs and evaluated with the same coverage simulation and cost model as our own plans.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "evaluation/evaluate.hpp"
#include "uavcover/artifact.hpp"
#include "uavcover/context.hpp"
#include "uavcover/mission.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::usecases {

struct PathsEvaluation {
  evaluation::Evaluation evaluation;
  std::vector<Uav> uavs;  ///< the UAV parameters each flight was evaluated with
  Plan shown;             ///< the paths as a plan without regions, for pictures
};

/// UAV parameters for flights named `ids`: by id when the mission names it, else by position,
/// else the mission's first UAV.
std::vector<Uav> match_uavs(const Mission& mission, const std::vector<std::string>& ids);

/// Parses the GeoJSON paths, matches them to the mission's UAVs and evaluates them, each flight swept
/// with its UAV's footprint (evaluation::footprint_for(mission, uav): its own camera, else the
/// mission's camera, else 1.5 ds). options.coverage.footprint_m > 0 (`--footprint`) sweeps that one
/// width for every flight.
PathsEvaluation evaluate_paths(const Mission& mission, std::string_view geojson,
                               const evaluation::EvaluateOptions& options, const Context& ctx = {});

/// evaluation.json, and with `images` heatmap.png, histogram.png and paths.png.
Artifacts evaluation_outputs(const PathsEvaluation& result, const std::string& paths_name, bool images);

}  // namespace uavcover::usecases
