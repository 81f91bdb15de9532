// The one table of export formats. The CLI's --format choices, the server's export routes and their
// error text, the OpenAPI enum and GET /api/v1/formats all come from it: adding a format is one row here
// (and its writer in its own file of src/export/).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "export/export.hpp"

namespace uavcover::exporting {

struct Format {
  std::string_view name;        ///< what --format, ?format= and /exports/{format} say: "qgc"
  std::string_view title;       ///< for people: "QGroundControl .plan"
  std::string_view extension;   ///< the main file's: ".plan" (KML may add .kmz, Litchi .1.litchi.csv ...)
  std::string_view media_type;  ///< the main file's
  std::string_view consumers;   ///< who reads it
  bool per_sortie = true;       ///< ExportOptions::per_sortie splits it into one file per sortie
  /// the limits it keeps to (docs/exports.md)
  std::string_view limits;
  /// Appends the files of UAV `index` of `plan` named `base` + extension (base "export/<id>" or
  /// "export/<id>.s<k>"; the trajectory names its own) to `out`. `opt` has resolved altitudes and the
  /// checks of check_plan() have passed.
  void (*write)(const Plan& plan, std::size_t index, const ExportOptions& opt, const std::string& base,
                Artifacts& out);
  /// it reads ExportOptions::trajectory (the trajectory method and its bounds); the others ignore it, so
  /// a cache of exports leaves those options out of their keys
  bool trajectory_options = false;
};

/// Every format, in a fixed order (the order of known_formats() and of an export's files).
const std::vector<Format>& formats();
/// The format of that name, or nullptr.
const Format* find_format(std::string_view name);
/// "geojson, qgc, ..." for error texts.
std::string format_list();
/// The table as JSON for GET /api/v1/formats: [{"name", "title", "extension", "media_type",
/// "consumers", "per_sortie", "limits"}, ...].
nlohmann::json formats_json();

// known_formats() and parse_formats() (export/export.hpp) are the names of this table.

}  // namespace uavcover::exporting
