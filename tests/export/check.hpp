// Independent readers for the export tests: ZIP archives from bytes (libzip), artifacts by name, and
// PX4's geofence rule re-implemented from PX4's navigator/geofence.cpp (PNPOLY on lat/lon; inside
// when inside some inclusion polygon and no exclusion polygon).
#pragma once

#include <gtest/gtest.h>
#include <zip.h>

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "uavcover/artifact.hpp"

namespace uavcover::check {

/// Every entry of a ZIP archive held in memory.
inline std::map<std::string, std::string> unzip_bytes(const std::string& bytes) {
  std::map<std::string, std::string> out;
  zip_error_t err;
  zip_error_init(&err);
  zip_source_t* src = zip_source_buffer_create(bytes.data(), bytes.size(), 0, &err);
  EXPECT_NE(src, nullptr);
  if (src == nullptr) return out;
  zip_t* za = zip_open_from_source(src, ZIP_RDONLY, &err);
  EXPECT_NE(za, nullptr) << zip_error_strerror(&err);
  if (za == nullptr) {
    zip_source_free(src);
    return out;
  }
  const zip_int64_t n = zip_get_num_entries(za, 0);
  for (zip_int64_t i = 0; i < n; ++i) {
    zip_stat_t st;
    zip_stat_index(za, static_cast<zip_uint64_t>(i), 0, &st);
    zip_file_t* f = zip_fopen_index(za, static_cast<zip_uint64_t>(i), 0);
    std::string data(st.size, '\0');
    EXPECT_EQ(zip_fread(f, data.data(), st.size), static_cast<zip_int64_t>(st.size));
    zip_fclose(f);
    out[st.name] = data;
  }
  zip_close(za);
  return out;
}

/// XML 1.0 Char production over UTF-8 text (pugixml does not check it): no C0 control other than tab,
/// newline and carriage return, no U+FFFE/U+FFFF or surrogates, valid UTF-8 throughout.
inline bool xml_chars_valid(const std::string& s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto b = static_cast<unsigned char>(s[i]);
    if (b < 0x80) {
      if (b < 0x20 && b != 0x09 && b != 0x0A && b != 0x0D) return false;
      ++i;
      continue;
    }
    const std::size_t len = b >= 0xF0 ? 4 : b >= 0xE0 ? 3 : b >= 0xC0 ? 2 : 0;
    if (len == 0 || i + len > s.size()) return false;
    std::uint32_t cp = b & (0x7Fu >> len);
    for (std::size_t k = 1; k < len; ++k) {
      const auto c = static_cast<unsigned char>(s[i + k]);
      if ((c & 0xC0u) != 0x80u) return false;
      cp = (cp << 6) | (c & 0x3Fu);
    }
    const std::uint32_t min = len == 2 ? 0x80 : len == 3 ? 0x800 : 0x10000;
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF) || cp == 0xFFFE || cp == 0xFFFF)
      return false;
    i += len;
  }
  return true;
}

/// The artifact named `name`, or nullptr.
inline const Artifact* find(const Artifacts& artifacts, const std::string& name) {
  for (const auto& a : artifacts)
    if (a.name == name) return &a;
  return nullptr;
}

/// PX4 Geofence::insidePolygon: PNPOLY over [lat, lon] vertices (QGC .plan polygon order).
inline bool px4_inside_polygon(const nlohmann::json& polygon, double lat, double lon) {
  bool c = false;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const double lat_i = polygon[i][0].get<double>(), lon_i = polygon[i][1].get<double>();
    const double lat_j = polygon[j][0].get<double>(), lon_j = polygon[j][1].get<double>();
    if ((lon_i >= lon) != (lon_j >= lon) && lat <= (lat_j - lat_i) * (lon - lon_i) / (lon_j - lon_i) + lat_i)
      c = !c;
  }
  return c;
}

/// PX4 Geofence::isInsidePolygonOrCircle for a .plan geoFence object (polygons only).
inline bool px4_inside_fence(const nlohmann::json& geofence, double lat, double lon) {
  bool had_inclusion = false, inside_inclusion = false, outside_exclusion = true;
  for (const auto& p : geofence["polygons"]) {
    const bool inside = px4_inside_polygon(p["polygon"], lat, lon);
    if (p["inclusion"].get<bool>()) {
      had_inclusion = true;
      inside_inclusion = inside_inclusion || inside;
    } else if (inside) {
      outside_exclusion = false;
    }
  }
  return (!had_inclusion || inside_inclusion) && outside_exclusion;
}

/// Every positioned item of a .plan, home and points every ~1 m along the legs between them
/// (home -> items -> home) pass PX4's fence check. Returns the first failure, empty when none.
inline std::string px4_fence_failure(const nlohmann::json& plan) {
  const auto& home = plan["mission"]["plannedHomePosition"];
  std::vector<std::pair<double, double>> pts{{home[0].get<double>(), home[1].get<double>()}};
  for (const auto& it : plan["mission"]["items"]) {
    const int cmd = it["command"].get<int>();
    if (cmd == 16 || cmd == 21 || cmd == 22)
      pts.emplace_back(it["params"][4].get<double>(), it["params"][5].get<double>());
  }
  pts.push_back(pts.front());
  const auto& fence = plan["geoFence"];
  for (std::size_t k = 0; k < pts.size(); ++k) {
    if (!px4_inside_fence(fence, pts[k].first, pts[k].second)) return "point " + std::to_string(k);
    if (k == 0) continue;
    const double dlat = pts[k].first - pts[k - 1].first, dlon = pts[k].second - pts[k - 1].second;
    const int steps = 1 + static_cast<int>(std::hypot(dlat, dlon) / 1e-5);  // ~1 m
    for (int s = 1; s < steps; ++s) {
      const double t = static_cast<double>(s) / steps;
      if (!px4_inside_fence(fence, pts[k - 1].first + t * dlat, pts[k - 1].second + t * dlon))
        return "leg to point " + std::to_string(k);
    }
  }
  return {};
}

}  // namespace uavcover::check
