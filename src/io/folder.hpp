// Reading every JSON file of a folder (the server's --seed-dir).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace uavcover::io {

/// The regular files named *.json directly in `dir`, sorted by name. Throws InputError naming `field`
/// when `dir` is not a readable folder.
std::vector<std::filesystem::path> list_json_files(const std::filesystem::path& dir,
                                                   const std::string& field);

}  // namespace uavcover::io
