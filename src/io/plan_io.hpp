// Reading and writing a plan directory: DIR/plan.json and DIR/paths.geojson.
#pragma once

#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "uavcover/artifact.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::io {

/// RFC 7946 FeatureCollection: per UAV LineStrings (kind coverage/transit, uav, share_requested,
/// share_actual, length_m, turns) plus Polygon features for the area and no-fly zones (role).
/// With `only_uav`, the lines of that UAV alone (the per-UAV GeoJSON export).
nlohmann::json paths_geojson(const Plan& plan, std::optional<std::size_t> only_uav = std::nullopt);

/// Reads a whole file; throws InputError naming `field` when it cannot be read.
std::string read_text_file(const std::filesystem::path& path, const std::string& field);

/// plan.json: normalised mission, spacing, GSD/footprint, placement, per-UAV and total metrics.
/// `extra` entries (e.g. "coverage", "cost") are merged in at top level.
nlohmann::json plan_json(const Plan& plan, const nlohmann::json& extra = nlohmann::json::object());

/// Writes text to `path` atomically (temp file + rename), creating parent folders.
void write_file_atomic(const std::filesystem::path& path, const std::string& content);

/// Writes the artifacts under `dir` (names are relative, '/'-separated; names with "..", absolute
/// names or empty parts are refused). All files are first written into a staging folder beside
/// `dir` and moved into place only when every one is complete: a failure leaves no partial file.
/// Returns the paths written.
std::vector<std::filesystem::path> write_artifacts(const std::filesystem::path& dir,
                                                   const Artifacts& artifacts);

/// Reads DIR/plan.json and DIR/paths.geojson back into a Plan (mission, UAVs, parts with local
/// and WGS84 coordinates). Throws InputError naming the file and field when they are unusable.
Plan load_plan_dir(const std::filesystem::path& dir);

}  // namespace uavcover::io
