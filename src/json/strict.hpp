// The one JSON reader for every input (mission files, paths GeoJSON, plan folders, server bodies).
// Built on nlohmann's SAX parser, which does not recurse: nesting is bounded before any value is
// built, so no later copy, comparison or destruction of the document can exhaust the stack.
// Documented in docs/limits.md.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace uavcover::strict {

struct JsonLimits {
  /// Arrays and objects nested deeper than this are refused (the document itself is level 1).
  /// uavcover's own formats need at most 8 (a MultiPolygon inside plan.json).
  std::size_t max_depth = 64;
  /// Texts longer than this are refused; 0 = no limit here (files are bounded by
  /// io::read_text_file, request bodies by the server).
  std::size_t max_bytes = 0;
};

/// Parses one JSON document strictly: RFC 8259 syntax (no comments, no trailing commas, valid
/// UTF-8, finite numbers), at most `limits.max_depth` levels, no key twice in an object. Throws
/// InputError: the field is `what` (the input's name, e.g. "mission" or "paths.geojson") for
/// syntax, size and depth errors, and the JSON path of the key for duplicate keys.
nlohmann::json parse_json(std::string_view text, const std::string& what, const JsonLimits& limits = {});

}  // namespace uavcover::strict
