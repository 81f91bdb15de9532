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

/// Default cap on the size of an input file (docs/limits.md).
inline constexpr std::size_t kDefaultMaxInputBytes = std::size_t{64} << 20;

/// The cap read_text_file applies: set_max_input_bytes() if called, else the environment variable
/// UAVCOVER_MAX_INPUT_MB (whole MiB, 1..4096), else kDefaultMaxInputBytes. Throws InputError naming
/// the variable when it is not a valid number.
std::size_t max_input_bytes();
/// Sets the process-wide cap (bytes, > 0), e.g. from a command-line option.
void set_max_input_bytes(std::size_t bytes);

/// Reads a whole regular file of at most `max_bytes` bytes (default: max_input_bytes()). Throws
/// InputError naming `field` and the file when it cannot be opened, is not a regular file (a folder,
/// a device such as /dev/zero, a pipe) or is larger; OperationError when reading fails midway.
std::string read_text_file(const std::filesystem::path& path, const std::string& field);
std::string read_text_file(const std::filesystem::path& path, const std::string& field,
                           std::size_t max_bytes);

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
/// The same from the two documents already parsed (a plan job's artifacts in the server's store).
Plan load_plan(const nlohmann::json& plan_json, const nlohmann::json& paths_geojson);

}  // namespace uavcover::io
