// The plan codec: a Plan to and from its two documents, plan.json and paths.geojson. Bytes in memory
// only; reading and writing the files is io/plan_io.hpp's (load_plan_dir, write_artifacts).
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>

#include "uavcover/plan.hpp"

namespace uavcover::codec {

/// RFC 7946 FeatureCollection: per UAV LineStrings (kind coverage/transit, uav, share_requested,
/// share_actual, length_m, turns) plus Polygon features for the area and no-fly zones (role).
/// With `only_uav`, the lines of that UAV alone (the per-UAV GeoJSON export).
nlohmann::json paths_geojson(const Plan& plan, std::optional<std::size_t> only_uav = std::nullopt);

/// plan.json: normalised mission, spacing, GSD/footprint, placement, per-UAV and total metrics.
/// `extra` entries (e.g. "coverage", "cost") are merged in at top level.
nlohmann::json plan_json(const Plan& plan, const nlohmann::json& extra = nlohmann::json::object());

/// A Plan (mission, UAVs, parts with local and WGS84 coordinates) from plan.json and paths.geojson
/// already parsed (a plan folder's files, or a plan job's artifacts in the server's store). Throws
/// InputError naming the document and field when they are unusable.
Plan load_plan(const nlohmann::json& plan_json, const nlohmann::json& paths_geojson);

}  // namespace uavcover::codec
