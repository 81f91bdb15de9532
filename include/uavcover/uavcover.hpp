// uavcover facade: plan(mission, options, progress) -> plan.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string_view>

#include "uavcover/error.hpp"
#include "uavcover/mission.hpp"
#include "uavcover/plan.hpp"

namespace uavcover {

/// Progress callback: stage name and fraction done in [0, 1]. Called from the planning thread.
using Progress = std::function<void(std::string_view stage, double fraction)>;

struct PlanOptions {
  std::optional<std::uint64_t> seed;  ///< overrides mission.seed
  int darp_max_iterations = 4000;     ///< per DARP attempt
  int placement_evaluations = 1500;   ///< grid placement budget (annealing steps in total)
  bool optimise_placement = true;
};

/// Plans the mission. Throws InputError for inputs that cannot be planned
/// (e.g. no free cell), std::runtime_error for internal failures.
Plan plan(const Mission& mission, const PlanOptions& options = {}, const Progress& progress = {});

}  // namespace uavcover
