// The multi-UAV marginal utility study of Apostolidis et al. 2022 §3.2 (Tables 7 and 8): plan the
// mission for each UAV count, evaluate, recommend the count with the least total time.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "evaluation/evaluate.hpp"
#include "uavcover/artifact.hpp"
#include "uavcover/context.hpp"
#include "uavcover/mission.hpp"

namespace uavcover::usecases {

/// "1..15", "1,2,3,5" or a mix ("1..3,5,7,9..15"); counts 1..200. InputError naming `field`.
std::vector<int> parse_uav_counts(const std::string& spec, const std::string& field = "uavs");

/// The mission with n UAVs: the mission's own UAVs first (with their starts), then copies of the
/// first UAV's parameters with seeded random starts; equal shares.
Mission with_uavs(const Mission& mission, int n);

struct StudyRow {
  int uavs = 0;
  bool ok = false;
  std::string error;  ///< when planning failed for this count
  evaluation::Evaluation evaluation;
  double compute_s = 0.0;
  bool complete = true;
  nlohmann::json planner_diagnostics;
  /// With a wind (issue 32): the same plan's flight time (eq. 17) in calm air, for comparison.
  std::optional<double> flight_time_calm_min;
};

struct Study {
  std::string mission;
  std::vector<StudyRow> rows;
  int recommended = 0;         ///< least total time
  int min_single_battery = 0;  ///< fewest UAVs for which every UAV flies on one battery; 0 none
  std::optional<Wind> wind;    ///< the mission's: every time is in it (issue 32)
};

struct StudyOptions {
  std::vector<int> counts;
  std::optional<std::uint64_t> seed;
  evaluation::CostOptions cost;
};

/// Runs the study. Rows that cannot be planned keep their error; when none can, the first error is
/// thrown. ctx reports "N UAVs" stages with the overall fraction.
Study run_study(const Mission& mission, const StudyOptions& options, const Context& ctx = {});

nlohmann::json study_json(const Study& study);
/// study.png: total time, flight time and cost against the UAV count.
Artifact study_picture(const Study& study);

}  // namespace uavcover::usecases
