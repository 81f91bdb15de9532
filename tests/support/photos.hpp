// Test photos (issue 32, docs/photos.md): small JPEGs written with GDAL's JPEG driver, their EXIF GPS
// and DJI XMP tags written with exiv2, as a drone's camera would leave them.
#pragma once

#include <gdal_priv.h>

#include <cmath>
#include <cstdint>
#include <exiv2/exiv2.hpp>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "uavcover/geometry.hpp"

namespace uavcover::testing {

struct PhotoSpec {
  double lat = 0.0, lon = 0.0;
  std::optional<double> gps_altitude_m;
  std::optional<double> relative_altitude_m;
  std::optional<double> gimbal_pitch_deg;
  std::optional<double> gimbal_yaw_deg;
  std::optional<double> flight_yaw_deg;
  std::optional<double> img_direction_deg;
  std::optional<int> focal_35mm;
  bool geotag = true;
};

/// A w x h grey-gradient JPEG made by GDAL (MEM -> JPEG in /vsimem/), its EXIF written by GDAL's JPEG driver
/// from "EXIF_*" metadata items (e.g. {"EXIF_GPSLatitude", "(40) (36) (1.5)"}): a writer independent of
/// exiv2.
inline std::string gdal_jpeg(int w, int h,
                             const std::vector<std::pair<std::string, std::string>>& exif = {}) {
  GDALAllRegister();
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDriver* jpeg = GetGDALDriverManager()->GetDriverByName("JPEG");
  if (!mem || !jpeg) throw std::runtime_error("GDAL has no MEM or JPEG driver");
  GDALDataset* src = mem->Create("", w, h, 3, GDT_Byte, nullptr);
  std::vector<std::uint8_t> px(static_cast<std::size_t>(w * h));
  for (std::size_t i = 0; i < px.size(); ++i) px[i] = static_cast<std::uint8_t>(i % 251);
  for (int b = 1; b <= 3; ++b)
    if (src->GetRasterBand(b)->RasterIO(GF_Write, 0, 0, w, h, px.data(), w, h, GDT_Byte, 0, 0) != CE_None)
      throw std::runtime_error("GDAL RasterIO failed");
  for (const auto& [k, v] : exif) src->SetMetadataItem(k.c_str(), v.c_str());
  const char* path = "/vsimem/uavcover-test-photo.jpg";
  GDALDataset* out = jpeg->CreateCopy(path, src, FALSE, nullptr, nullptr, nullptr);
  GDALClose(src);
  if (!out) throw std::runtime_error("GDAL could not write a JPEG");
  GDALClose(out);
  vsi_l_offset n = 0;
  GByte* data = VSIGetMemFileBuffer(path, &n, TRUE);
  std::string bytes(reinterpret_cast<const char*>(data), static_cast<std::size_t>(n));
  CPLFree(data);
  return bytes;
}

inline std::string plain_jpeg() { return gdal_jpeg(32, 24); }

/// "d/1 m/1 s*100/100" for EXIF's degrees-minutes-seconds rationals.
inline std::string dms(double deg) {
  deg = std::abs(deg);
  const int d = static_cast<int>(deg);
  const double mf = (deg - d) * 60.0;
  const int m = static_cast<int>(mf);
  const auto s = static_cast<long long>(std::llround((mf - m) * 60.0 * 10000.0));
  return std::to_string(d) + "/1 " + std::to_string(m) + "/1 " + std::to_string(s) + "/10000";
}

inline std::string signed_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%+.2f", x);
  return buf;
}

/// A JPEG with the spec's tags (EXIF GPS; DJI's drone-dji XMP namespace for altitude and gimbal).
inline std::string photo_jpeg(const PhotoSpec& s) {
  static const bool ns = [] {
    Exiv2::XmpParser::initialize();
    Exiv2::XmpProperties::registerNs("http://www.dji.com/drone-dji/1.0/", "drone-dji");
    return true;
  }();
  (void)ns;
  const std::string plain = plain_jpeg();
  auto image = Exiv2::ImageFactory::open(reinterpret_cast<const Exiv2::byte*>(plain.data()),
                                         static_cast<long>(plain.size()));
  image->readMetadata();
  Exiv2::ExifData exif;
  Exiv2::XmpData xmp;
  if (s.geotag) {
    exif["Exif.GPSInfo.GPSLatitudeRef"] = s.lat < 0 ? "S" : "N";
    exif["Exif.GPSInfo.GPSLatitude"] = dms(s.lat);
    exif["Exif.GPSInfo.GPSLongitudeRef"] = s.lon < 0 ? "W" : "E";
    exif["Exif.GPSInfo.GPSLongitude"] = dms(s.lon);
  }
  if (s.gps_altitude_m) {
    exif["Exif.GPSInfo.GPSAltitudeRef"] = Exiv2::byte(*s.gps_altitude_m < 0 ? 1 : 0);
    exif["Exif.GPSInfo.GPSAltitude"] =
        std::to_string(std::llround(std::abs(*s.gps_altitude_m) * 100)) + "/100";
  }
  if (s.img_direction_deg)
    exif["Exif.GPSInfo.GPSImgDirection"] = std::to_string(std::llround(*s.img_direction_deg * 100)) + "/100";
  if (s.focal_35mm) exif["Exif.Photo.FocalLengthIn35mmFilm"] = static_cast<std::uint16_t>(*s.focal_35mm);
  exif["Exif.Photo.DateTimeOriginal"] = "2026:12:02 10:00:00";
  if (s.relative_altitude_m) xmp["Xmp.drone-dji.RelativeAltitude"] = signed_text(*s.relative_altitude_m);
  if (s.gimbal_pitch_deg) xmp["Xmp.drone-dji.GimbalPitchDegree"] = signed_text(*s.gimbal_pitch_deg);
  if (s.gimbal_yaw_deg) xmp["Xmp.drone-dji.GimbalYawDegree"] = signed_text(*s.gimbal_yaw_deg);
  if (s.flight_yaw_deg) xmp["Xmp.drone-dji.FlightYawDegree"] = signed_text(*s.flight_yaw_deg);
  image->setExifData(exif);
  image->setXmpData(xmp);
  image->writeMetadata();
  Exiv2::BasicIo& io = image->io();
  io.seek(0, Exiv2::BasicIo::beg);
  const Exiv2::DataBuf buf = io.read(static_cast<long>(io.size()));
  return std::string(reinterpret_cast<const char*>(buf.pData_), static_cast<std::size_t>(buf.size_));
}

/// A nadir photo `height` m above take-off at `g`, facing `yaw` (default north), 24 mm equivalent: a
/// 1.5 h x h footprint (the image's width across the heading).
inline PhotoSpec nadir_photo(LonLat g, double height, double yaw = 0.0) {
  PhotoSpec s;
  s.lat = g.lat;
  s.lon = g.lon;
  s.relative_altitude_m = height;
  s.gimbal_pitch_deg = -90.0;
  s.gimbal_yaw_deg = yaw;
  s.focal_35mm = 24;
  return s;
}

inline void write_bytes(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream f(p, std::ios::binary);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace uavcover::testing
