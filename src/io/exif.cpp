// Photo metadata with exiv2 (issue 32, docs/photos.md).
#include "io/exif.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <exiv2/exiv2.hpp>
#include <mutex>
#include <system_error>

#include "io/plan_io.hpp"
#include "uavcover/error.hpp"

namespace uavcover::io {

namespace {

/// exiv2's XMP toolkit must be initialised once before threads parse XMP (XmpParser::initialize).
void init_exiv2() {
  static std::once_flag once;
  std::call_once(once, [] {
    Exiv2::XmpParser::initialize();
    // DJI's namespace: looking up an unregistered prefix throws (a photo without DJI's XMP included)
    Exiv2::XmpProperties::registerNs("http://www.dji.com/drone-dji/1.0/", "drone-dji");
    Exiv2::LogMsg::setLevel(Exiv2::LogMsg::mute);  // warnings on odd files go to our errors, not stderr
  });
}

std::optional<double> exif_number(const Exiv2::ExifData& exif, const char* key, long index = 0) {
  const auto it = exif.findKey(Exiv2::ExifKey(key));
  if (it == exif.end() || it->count() <= index) return std::nullopt;
  double x = 0.0;
  const Exiv2::Value& v = it->value();
  if (v.typeId() == Exiv2::unsignedRational) {
    // unsigned 32-bit parts (a writer may use a large denominator: GDAL writes 3.25 as 3250000000/1e9),
    // which Value::toRational would read as signed
    const auto& r = static_cast<const Exiv2::URationalValue&>(v).value_.at(static_cast<std::size_t>(index));
    if (r.second == 0) return std::nullopt;
    x = static_cast<double>(r.first) / static_cast<double>(r.second);
  } else {
    const Exiv2::Rational r = it->toRational(index);
    if (r.second == 0) return std::nullopt;
    x = static_cast<double>(r.first) / static_cast<double>(r.second);
  }
  return std::isfinite(x) ? std::optional<double>(x) : std::nullopt;
}

std::optional<std::string> exif_text(const Exiv2::ExifData& exif, const char* key) {
  const auto it = exif.findKey(Exiv2::ExifKey(key));
  if (it == exif.end()) return std::nullopt;
  return it->toString();
}

/// An XMP value such as DJI's "+50.30"; absent, empty or not a number: nullopt.
std::optional<double> xmp_number(const Exiv2::XmpData& xmp, const char* key) {
  const auto it = xmp.findKey(Exiv2::XmpKey(key));
  if (it == xmp.end()) return std::nullopt;
  const std::string s = it->toString();
  if (s.empty() || s.size() > 64) return std::nullopt;
  char* end = nullptr;
  const double x = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0' || !std::isfinite(x)) return std::nullopt;
  return x;
}

/// Degrees, minutes, seconds (three rationals) with the hemisphere's Ref.
double coordinate(const Exiv2::ExifData& exif, const std::string& name, const char* key, const char* ref_key,
                  char negative, double limit, const char* tag) {
  const auto it = exif.findKey(Exiv2::ExifKey(key));
  const std::string field = name + "." + tag;
  if (it == exif.end()) throw InputError(field, "missing: the photo has no geotag");
  double deg = 0.0;
  for (long i = 0; i < 3 && i < it->count(); ++i) {
    const auto part = exif_number(exif, key, i);
    if (!part || *part < 0.0) throw InputError(field, "expected degrees, minutes and seconds >= 0");
    deg += *part / std::pow(60.0, static_cast<double>(i));
  }
  const auto ref = exif_text(exif, ref_key);
  if (ref && !ref->empty() && std::toupper(static_cast<unsigned char>(ref->front())) == negative) deg = -deg;
  if (!(std::abs(deg) <= limit)) throw InputError(field, fmt::format("must be within ±{}°", limit));
  return deg;
}

}  // namespace

PhotoTags read_photo_tags(const std::uint8_t* data, std::size_t size, const std::string& name) {
  init_exiv2();
  if (size == 0) throw InputError(name, "empty file");
  if (size > kMaxPhotoBytes) throw InputError(name, fmt::format("larger than {} MiB", kMaxPhotoBytes >> 20));
  PhotoTags t;
  t.name = name;
  try {
    auto image = Exiv2::ImageFactory::open(data, static_cast<long>(size));
    if (image.get() == nullptr) throw InputError(name, "not an image exiv2 can read");
    image->readMetadata();
    const Exiv2::ExifData& exif = image->exifData();
    const Exiv2::XmpData& xmp = image->xmpData();
    t.width_px = image->pixelWidth();
    t.height_px = image->pixelHeight();
    t.lat = coordinate(exif, name, "Exif.GPSInfo.GPSLatitude", "Exif.GPSInfo.GPSLatitudeRef", 'S', 90.0,
                       "GPSLatitude");
    t.lon = coordinate(exif, name, "Exif.GPSInfo.GPSLongitude", "Exif.GPSInfo.GPSLongitudeRef", 'W', 180.0,
                       "GPSLongitude");
    t.gps_altitude_m = exif_number(exif, "Exif.GPSInfo.GPSAltitude");
    if (t.gps_altitude_m) {
      const auto ref = exif.findKey(Exiv2::ExifKey("Exif.GPSInfo.GPSAltitudeRef"));
      if (ref != exif.end() && ref->count() > 0 && ref->toLong() == 1) *t.gps_altitude_m = -*t.gps_altitude_m;
    }
    t.relative_altitude_m = xmp_number(xmp, "Xmp.drone-dji.RelativeAltitude");
    t.gimbal_pitch_deg = xmp_number(xmp, "Xmp.drone-dji.GimbalPitchDegree");
    t.yaw_deg = xmp_number(xmp, "Xmp.drone-dji.GimbalYawDegree");
    if (!t.yaw_deg) t.yaw_deg = xmp_number(xmp, "Xmp.drone-dji.FlightYawDegree");
    if (!t.yaw_deg) t.yaw_deg = exif_number(exif, "Exif.GPSInfo.GPSImgDirection");
    t.focal_length_mm = exif_number(exif, "Exif.Photo.FocalLength");
    t.focal_35mm_mm = exif_number(exif, "Exif.Photo.FocalLengthIn35mmFilm");
    if (const auto time = exif_text(exif, "Exif.Photo.DateTimeOriginal")) t.time = time->substr(0, 64);
  } catch (const Exiv2::AnyError& e) {
    throw InputError(name, std::string("not a photo exiv2 can read: ") + e.what());
  }
  check_photo_tags(t, name, false);
  return t;
}

std::vector<PhotoTags> read_photo_folder(const std::filesystem::path& dir, const std::string& field) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) throw InputError(field, "not a folder: " + dir.string());
  std::vector<std::filesystem::path> files;
  for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_regular_file(ec)) continue;
    std::string ext = it->path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ext != ".jpg" && ext != ".jpeg") continue;
    files.push_back(it->path());
    if (files.size() > kMaxPhotos) throw InputError(field, fmt::format("more than {} photos", kMaxPhotos));
  }
  if (ec) throw InputError(field, "cannot list " + dir.string() + ": " + ec.message());
  if (files.empty()) throw InputError(field, "no .jpg or .jpeg photos in " + dir.string());
  std::sort(files.begin(), files.end());
  std::vector<PhotoTags> out;
  out.reserve(files.size());
  for (const auto& f : files) {
    const std::string bytes = read_text_file(f, field, kMaxPhotoBytes);
    out.push_back(read_photo_tags(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(),
                                  f.filename().string()));
  }
  return out;
}

}  // namespace uavcover::io
