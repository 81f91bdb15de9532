// The web app's files for `uavcover serve --static DIR`, read once at start (the server serves them
// from memory by exact URL path, so no path is ever built from a request).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include "uavcover/artifact.hpp"

namespace uavcover::io {

/// Media type by file extension (html, js, mjs, css, json, svg, png, ico, woff2, map, txt and a few
/// more pictures and fonts); empty when the extension is not served.
std::string static_media_type(const std::filesystem::path& file);

/// Every regular file under `dir` with a served extension, as artifacts named by their relative
/// '/'-separated path ("index.html", "assets/app.js"). Symbolic links are skipped (nothing outside
/// the folder is read), as are hidden entries (names starting with '.'). InputError naming "--static"
/// when `dir` is not a readable folder or the files together exceed `max_total_bytes`.
Artifacts read_static_dir(const std::filesystem::path& dir, std::size_t max_total_bytes);

}  // namespace uavcover::io
