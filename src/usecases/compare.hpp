// `compare`: one mission, several planners, one evaluator. Plans the mission with each planner,
// evaluates every plan the same way, and reports the numbers side by side.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "evaluation/evaluate.hpp"
#include "uavcover/artifact.hpp"
#include "uavcover/context.hpp"
#include "uavcover/mission.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::usecases {

struct CompareOptions {
  std::vector<std::string> planners;       ///< registered names; empty = every registered planner
  evaluation::EvaluateOptions evaluation;  ///< the same for every plan (footprint 0 = the mission's)
};

struct CompareRow {
  std::string planner;
  bool ok = false;
  std::string error;  ///< why this planner could not plan the mission
  Plan plan;
  evaluation::Evaluation evaluation;
  double compute_s = 0.0;
  double max_share_deviation = 0.0;  ///< max |actual - requested| over the UAVs
  /// With a wind (issue 32): the same plan's flight time (eq. 17) in calm air, for comparison.
  std::optional<double> flight_time_calm_min;
};

struct Comparison {
  std::string mission;
  std::optional<Wind> wind;  ///< the mission's: every time is in it (issue 32)
  std::vector<CompareRow> rows;
};

/// Plans and evaluates. A planner that refuses the mission (InputError) keeps its message in its
/// row; unknown planner names are refused up front (InputError "planners").
Comparison compare(const Mission& mission, const CompareOptions& options, const Context& ctx = {});

nlohmann::json compare_json(const Comparison& comparison);
std::string compare_markdown(const Comparison& comparison);
/// compare.json, compare.md and (with `images`) compare.png: the plans side by side.
Artifacts compare_outputs(const Comparison& comparison, bool images);

}  // namespace uavcover::usecases
