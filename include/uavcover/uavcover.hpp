// uavcover facade: parse a mission, plan it with any registered planner, and (in the other facade
// headers) evaluate, render and export the plan. The CLI and the server are thin shells over it.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "uavcover/artifact.hpp"
#include "uavcover/context.hpp"
#include "uavcover/error.hpp"
#include "uavcover/mission.hpp"
#include "uavcover/plan.hpp"

namespace uavcover {

struct PlanOptions {
  std::optional<std::uint64_t> seed;  ///< overrides mission.seed
};

/// Plans the mission with its planner (mission.planner, parameters mission.planner_params).
/// Throws InputError for missions that cannot be planned (no free cell, a capability the planner
/// lacks), Cancelled when ctx is stopped, TimeLimitReached when ctx's time is up before any complete
/// plan exists (planners that can, return their best plan so far with Plan::complete == false).
Plan plan(const Mission& mission, const PlanOptions& options = {}, const Context& ctx = {});

/// A registered planner: name, one-line summary, and its JSON description (parameters with types,
/// defaults and bounds; capabilities).
struct PlannerDescription {
  std::string name;
  std::string summary;
  nlohmann::json schema;
};
std::vector<PlannerDescription> available_planners();

}  // namespace uavcover
