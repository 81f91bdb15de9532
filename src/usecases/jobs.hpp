// Jobs as the server runs them: a plan, a study (UAV counts) or a comparison (planners) of a stored
// mission, with validated parameters, producing a JSON result (metrics, warnings) and artifacts. The
// server only queues, leases and stores; everything it computes comes from here, through the same
// facade and use cases the CLI calls, so a plan made through the API equals the CLI's.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "uavcover/artifact.hpp"
#include "uavcover/context.hpp"
#include "uavcover/mission.hpp"

namespace uavcover::usecases {

enum class JobType { Plan, Study, Comparison };

/// Validates and normalises a job's parameters (an HTTP body; may be null or {}), filling defaults:
///  plan:       {planner?, planner_params?, seed?, time_limit_s?}
///  study:      {uavs: "1..5" (required), seed?, time_limit_s?}
///  comparison: {planners?: [names], seed?, time_limit_s?}
/// planner_params are checked against the planner's schema for `mission`. InputError naming the field.
nlohmann::json validate_job_params(JobType type, const Mission& mission, const nlohmann::json& params);

struct JobResult {
  nlohmann::json result;  ///< plan: {planner, complete, compute_time_s, uavs:[...], metrics:{...}, warnings}
  Artifacts artifacts;
};

/// Runs a job on the mission (already parsed) with validated params. ctx: progress, stop token; the
/// params' time_limit_s is applied here. Throws what the facade throws (InputError, Cancelled,
/// TimeLimitReached, OperationError).
/// Plan artifacts: what a plan is, those of the CLI's `plan` (plan.json, paths.geojson, evaluation.json,
/// plan.png, plan.svg, heatmap.png, heatmap-overlay.png, histogram.png). Its exports are made from the
/// stored plan.json and paths.geojson on request (build_export(), docs/cache.md).
JobResult run_job(JobType type, const Mission& mission, const nlohmann::json& params, const Context& ctx);

/// The artifact name serving GET /plans/{id}/exports/{format}?uav=ID: "export/<uav>.plan" for qgc, etc.
/// Empty when the format or UAV is unknown. `uav` may be empty when the plan has one flying UAV.
std::optional<std::string> export_artifact_name(const std::vector<std::string>& artifact_names,
                                                const std::string& format, const std::string& uav);

/// Catalog references in a submitted mission document: "catalog_id" in a UAV entry fills speed_mps,
/// max_accel_mps2 and endurance_min the entry does not give; "catalog_id" in "camera" fills
/// sensor_width_mm, focal_length_mm, image_width_px (and hfov_deg). The lookups return the catalog
/// entry's fields or nullopt (InputError "uavs[i].catalog_id: no such UAV"). Returns the document
/// without the references, ready for parse_mission.
using CatalogLookup = std::function<std::optional<nlohmann::json>(long long id)>;
nlohmann::json resolve_catalog_refs(const nlohmann::json& document, const CatalogLookup& uav,
                                    const CatalogLookup& camera);

}  // namespace uavcover::usecases
