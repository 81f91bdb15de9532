// Photo tags without exiv2 (docs/photos.md): their range checks and their JSON form, in the core so that
// the server's photo routes and the use cases share them with the exiv2 reader (src/io/exif.cpp).
#include <fmt/format.h>

#include <cmath>

#include "io/exif.hpp"
#include "uavcover/error.hpp"

namespace uavcover::io {

namespace {

void check_range(const std::optional<double>& v, const std::string& field, double lo, double hi) {
  if (v && !(*v >= lo && *v <= hi))
    throw InputError(field, fmt::format("must be in [{}, {}], got {}", lo, hi, *v));
}

std::optional<double> optional_number(const nlohmann::json& j, const char* key, const std::string& field) {
  const auto it = j.find(key);
  if (it == j.end() || it->is_null()) return std::nullopt;
  if (!it->is_number() || !std::isfinite(it->get<double>()))
    throw InputError(field + "." + key, "expected a finite number or null");
  return it->get<double>();
}

nlohmann::json opt(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

}  // namespace

void check_photo_tags(PhotoTags& t, const std::string& prefix, bool json_names) {
  const auto f = [&](const char* tag, const char* key) { return prefix + "." + (json_names ? key : tag); };
  if (!(std::abs(t.lat) <= 90.0)) throw InputError(f("GPSLatitude", "lat"), "must be within ±90°");
  if (!(std::abs(t.lon) <= 180.0)) throw InputError(f("GPSLongitude", "lon"), "must be within ±180°");
  check_range(t.gps_altitude_m, f("GPSAltitude", "gps_altitude_m"), -1000.0, 20000.0);
  check_range(t.relative_altitude_m, f("RelativeAltitude", "relative_altitude_m"), -1000.0, 10000.0);
  check_range(t.gimbal_pitch_deg, f("GimbalPitchDegree", "gimbal_pitch_deg"), -180.0, 180.0);
  check_range(t.yaw_deg, f("GimbalYawDegree", "yaw_deg"), -360.0, 360.0);
  check_range(t.focal_length_mm, f("FocalLength", "focal_length_mm"), 0.1, 2000.0);
  check_range(t.focal_35mm_mm, f("FocalLengthIn35mmFilm", "focal_35mm_mm"), 1.0, 5000.0);
  if (t.yaw_deg) t.yaw_deg = std::fmod(*t.yaw_deg + 360.0, 360.0);
}

nlohmann::json to_json(const PhotoTags& t) {
  return {{"name", t.name},
          {"lat", t.lat},
          {"lon", t.lon},
          {"gps_altitude_m", opt(t.gps_altitude_m)},
          {"relative_altitude_m", opt(t.relative_altitude_m)},
          {"gimbal_pitch_deg", opt(t.gimbal_pitch_deg)},
          {"yaw_deg", opt(t.yaw_deg)},
          {"focal_length_mm", opt(t.focal_length_mm)},
          {"focal_35mm_mm", opt(t.focal_35mm_mm)},
          {"width_px", t.width_px},
          {"height_px", t.height_px},
          {"time", t.time}};
}

PhotoTags photo_tags_from_json(const nlohmann::json& j, const std::string& field) {
  if (!j.is_object())
    throw InputError(field, "expected a photo's tags (an object, as POST /photos/tags gives)");
  static const char* const kKeys[] = {"name",
                                      "lat",
                                      "lon",
                                      "gps_altitude_m",
                                      "relative_altitude_m",
                                      "gimbal_pitch_deg",
                                      "yaw_deg",
                                      "focal_length_mm",
                                      "focal_35mm_mm",
                                      "width_px",
                                      "height_px",
                                      "time"};
  for (const auto& [key, value] : j.items()) {
    bool known = false;
    for (const char* k : kKeys) known = known || key == k;
    if (!known) throw InputError(field + "." + key.substr(0, 64), "unknown field");
    (void)value;
  }
  PhotoTags t;
  const auto name = j.find("name");
  if (name == j.end() || !name->is_string() || name->get<std::string>().empty() ||
      name->get<std::string>().size() > 255)
    throw InputError(field + ".name", "expected the photo's file name (1 to 255 characters)");
  t.name = name->get<std::string>();
  for (const char* k : {"lat", "lon"}) {
    const auto v = optional_number(j, k, field);
    if (!v) throw InputError(field + "." + k, "missing: the photo has no geotag");
    (std::string(k) == "lat" ? t.lat : t.lon) = *v;
  }
  t.gps_altitude_m = optional_number(j, "gps_altitude_m", field);
  t.relative_altitude_m = optional_number(j, "relative_altitude_m", field);
  t.gimbal_pitch_deg = optional_number(j, "gimbal_pitch_deg", field);
  t.yaw_deg = optional_number(j, "yaw_deg", field);
  t.focal_length_mm = optional_number(j, "focal_length_mm", field);
  t.focal_35mm_mm = optional_number(j, "focal_35mm_mm", field);
  for (const char* k : {"width_px", "height_px"}) {
    const auto v = optional_number(j, k, field);
    if (v && !(*v >= 0 && *v <= 1e6 && std::floor(*v) == *v))
      throw InputError(field + "." + k, "expected a whole number of pixels");
    (std::string(k) == "width_px" ? t.width_px : t.height_px) = v ? static_cast<int>(*v) : 0;
  }
  if (const auto time = j.find("time"); time != j.end() && !time->is_null()) {
    if (!time->is_string() || time->get<std::string>().size() > 64)
      throw InputError(field + ".time", "expected a text of at most 64 characters");
    t.time = time->get<std::string>();
  }
  check_photo_tags(t, field, true);
  return t;
}

}  // namespace uavcover::io
