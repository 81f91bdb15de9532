// Files: reading input files with a size cap, writing files atomically, writing a set of artifacts into a
// folder, and reading a plan folder (DIR/plan.json and DIR/paths.geojson, decoded by codec/plan_codec.hpp).
#pragma once

#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "uavcover/artifact.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::io {

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
