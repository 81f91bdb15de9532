// Photo metadata (issue 32, docs/photos.md): where a drone photo was taken and how the camera pointed,
// from its EXIF and XMP tags, read with exiv2. The only code that links exiv2 (target uavcover_exif).
// Photos are untrusted input: every refusal is an InputError naming the photo and the tag.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace uavcover::io {

struct PhotoTags {
  std::string name;                           ///< the file's name (no folder), or the name given
  double lat = 0.0, lon = 0.0;                ///< Exif.GPSInfo.GPSLatitude/Longitude with their Refs
  std::optional<double> gps_altitude_m;       ///< Exif.GPSInfo.GPSAltitude (Ref 1: below sea level)
  std::optional<double> relative_altitude_m;  ///< Xmp.drone-dji.RelativeAltitude: above take-off
  std::optional<double> gimbal_pitch_deg;     ///< Xmp.drone-dji.GimbalPitchDegree: -90 looks down
  /// Where the camera faces, degrees clockwise from north: Xmp.drone-dji.GimbalYawDegree, else
  /// FlightYawDegree, else Exif.GPSInfo.GPSImgDirection.
  std::optional<double> yaw_deg;
  std::optional<double> focal_length_mm;  ///< Exif.Photo.FocalLength
  std::optional<double> focal_35mm_mm;    ///< Exif.Photo.FocalLengthIn35mmFilm
  int width_px = 0, height_px = 0;        ///< the image's pixel size (0: unknown)
  std::string time;                       ///< Exif.Photo.DateTimeOriginal, as written
};

constexpr std::size_t kMaxPhotoBytes = std::size_t{64} << 20;  ///< one photo file
constexpr std::size_t kMaxPhotos = 20000;                      ///< photos in one folder or upload

/// Range checks of the tags, and the heading normalised to [0, 360): what read_photo_tags applies
/// (InputError "<prefix>.GimbalPitchDegree": the tag) and photo_tags_from_json too (json_names:
/// "<prefix>.gimbal_pitch_deg"). In src/io/photo_tags.cpp, part of the core (no exiv2).
void check_photo_tags(PhotoTags& tags, const std::string& prefix, bool json_names);

/// The tags as JSON (the server's POST /photos/tags answer; absent tags are null), and back: untrusted
/// input, every field checked, InputError naming `field` ("photos[3].lat").
nlohmann::json to_json(const PhotoTags& tags);
PhotoTags photo_tags_from_json(const nlohmann::json& j, const std::string& field);

/// The tags of one photo held in memory. InputError("<name>", ...) when it is no image exiv2 reads, or
/// "<name>.GPSLatitude" etc. when a geotag is missing or out of range.
PhotoTags read_photo_tags(const std::uint8_t* data, std::size_t size, const std::string& name);

/// Every *.jpg / *.jpeg (any case) directly in `dir`, by name; InputError naming `field` for a missing
/// folder, no photos, too many or too large files, and each photo's own refusals.
std::vector<PhotoTags> read_photo_folder(const std::filesystem::path& dir, const std::string& field);

}  // namespace uavcover::io
