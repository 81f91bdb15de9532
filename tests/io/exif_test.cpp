// Photo metadata (issue 32, docs/photos.md): JPEGs made with GDAL, tagged with exiv2, read back by the
// project's reader; bad photos are refused naming the photo and the tag.
#include "io/exif.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "support/files.hpp"
#include "support/photos.hpp"
#include "uavcover/error.hpp"

namespace uavcover {
namespace {

using testing::PhotoSpec;

io::PhotoTags read(const std::string& bytes, const std::string& name = "p.jpg") {
  return io::read_photo_tags(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), name);
}

void expect_refused(const std::string& bytes, const std::string& field, const std::string& words) {
  try {
    (void)read(bytes);
    FAIL() << "accepted; expected a refusal of " << field;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.field()), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

// GDAL's JPEG driver writes the EXIF (no XMP at all): an independent writer, as a non-DJI camera's photo.
// First in the file: before any photo of the tests' own writer registers DJI's XMP namespace, so the
// reader must cope without it (a lookup of an unregistered prefix throws in exiv2).
TEST(Exif, GdalWrittenExifReadsBackWithoutXmp) {
  const io::PhotoTags t = read(testing::gdal_jpeg(16, 12,
                                                  {{"EXIF_GPSLatitude", "(40) (36) (1.5)"},
                                                   {"EXIF_GPSLatitudeRef", "N"},
                                                   {"EXIF_GPSLongitude", "(22) (57) (3.25)"},
                                                   {"EXIF_GPSLongitudeRef", "W"},
                                                   {"EXIF_GPSAltitude", "(160.5)"},
                                                   {"EXIF_GPSImgDirection", "(90)"},
                                                   {"EXIF_FocalLengthIn35mmFilm", "24"}}),
                               "gdal.jpg");
  EXPECT_NEAR(t.lat, 40.0 + 36.0 / 60 + 1.5 / 3600, 1e-7);
  EXPECT_NEAR(t.lon, -(22.0 + 57.0 / 60 + 3.25 / 3600), 1e-7);
  ASSERT_TRUE(t.gps_altitude_m);
  EXPECT_NEAR(*t.gps_altitude_m, 160.5, 1e-4);  // GDAL writes its own rational approximation
  EXPECT_FALSE(t.relative_altitude_m) << "no XMP";
  ASSERT_TRUE(t.yaw_deg);
  EXPECT_NEAR(*t.yaw_deg, 90.0, 1e-9);
  ASSERT_TRUE(t.focal_35mm_mm);
  EXPECT_NEAR(*t.focal_35mm_mm, 24.0, 1e-9);
}

TEST(Exif, GeotagAltitudesAndDjiGimbalReadBack) {
  PhotoSpec s;
  s.lat = 40.6012345;
  s.lon = 22.9456789;
  s.gps_altitude_m = 123.4;
  s.relative_altitude_m = 50.3;
  s.gimbal_pitch_deg = -45.0;
  s.gimbal_yaw_deg = -90.0;  // DJI writes -180..180: west
  s.flight_yaw_deg = 10.0;
  s.focal_35mm = 24;
  const io::PhotoTags t = read(testing::photo_jpeg(s), "DJI_0001.JPG");
  EXPECT_EQ(t.name, "DJI_0001.JPG");
  EXPECT_NEAR(t.lat, 40.6012345, 1e-7);
  EXPECT_NEAR(t.lon, 22.9456789, 1e-7);
  ASSERT_TRUE(t.gps_altitude_m);
  EXPECT_NEAR(*t.gps_altitude_m, 123.4, 1e-9);
  ASSERT_TRUE(t.relative_altitude_m);
  EXPECT_NEAR(*t.relative_altitude_m, 50.3, 1e-9);
  ASSERT_TRUE(t.gimbal_pitch_deg);
  EXPECT_NEAR(*t.gimbal_pitch_deg, -45.0, 1e-9);
  ASSERT_TRUE(t.yaw_deg);
  EXPECT_NEAR(*t.yaw_deg, 270.0, 1e-9) << "the gimbal's yaw wins over the aircraft's, normalised to [0, 360)";
  ASSERT_TRUE(t.focal_35mm_mm);
  EXPECT_NEAR(*t.focal_35mm_mm, 24.0, 1e-9);
  EXPECT_EQ(t.width_px, 32);
  EXPECT_EQ(t.height_px, 24);
  EXPECT_EQ(t.time, "2026:12:02 10:00:00");
}

TEST(Exif, SouthWestBelowSeaLevelAndTheYawFallbacks) {
  PhotoSpec s;
  s.lat = -33.5;
  s.lon = -70.25;
  s.gps_altitude_m = -12.5;
  s.flight_yaw_deg = 123.0;
  io::PhotoTags t = read(testing::photo_jpeg(s));
  EXPECT_NEAR(t.lat, -33.5, 1e-7);
  EXPECT_NEAR(t.lon, -70.25, 1e-7);
  EXPECT_NEAR(*t.gps_altitude_m, -12.5, 1e-9);
  EXPECT_FALSE(t.relative_altitude_m);
  EXPECT_FALSE(t.gimbal_pitch_deg);
  EXPECT_NEAR(*t.yaw_deg, 123.0, 1e-9) << "no gimbal yaw: the aircraft's";
  s.flight_yaw_deg.reset();
  s.img_direction_deg = 45.5;
  t = read(testing::photo_jpeg(s));
  EXPECT_NEAR(*t.yaw_deg, 45.5, 1e-9) << "no XMP yaw: EXIF's GPSImgDirection";
  s.img_direction_deg.reset();
  EXPECT_FALSE(read(testing::photo_jpeg(s)).yaw_deg);
}

TEST(Exif, BadPhotosAreRefusedNamingThePhotoAndTheTag) {
  PhotoSpec s;
  s.geotag = false;
  expect_refused(testing::photo_jpeg(s), "p.jpg.GPSLatitude", "no geotag");
  expect_refused("this is no jpeg at all", "p.jpg", "not a");
  expect_refused(testing::plain_jpeg().substr(0, 40), "p.jpg", "not a");
  EXPECT_THROW((void)io::read_photo_tags(nullptr, 0, "empty.jpg"), InputError);
  PhotoSpec far;
  far.lat = 95.0;  // written as 95 degrees: out of range
  expect_refused(testing::photo_jpeg(far), "p.jpg.GPSLatitude", "within");
  PhotoSpec tilt;
  tilt.gimbal_pitch_deg = 500.0;
  expect_refused(testing::photo_jpeg(tilt), "p.jpg.GimbalPitchDegree", "must be in");
}

TEST(Exif, AFolderIsReadByNameJpegsOnly) {
  testing::TempDir dir("exif");
  PhotoSpec s;
  s.lat = 40.0;
  s.lon = 22.0;
  s.relative_altitude_m = 30.0;
  s.lon = 22.002;
  testing::write_bytes(dir.path / "b.JPEG", testing::photo_jpeg(s));
  s.lon = 22.001;
  testing::write_bytes(dir.path / "a.jpg", testing::photo_jpeg(s));
  testing::write_bytes(dir.path / "notes.txt", "not a photo");
  const auto tags = io::read_photo_folder(dir.path, "DIR");
  ASSERT_EQ(tags.size(), 2u);
  EXPECT_EQ(tags[0].name, "a.jpg");
  EXPECT_NEAR(tags[0].lon, 22.001, 1e-7);
  EXPECT_EQ(tags[1].name, "b.JPEG");
  testing::TempDir empty("exif_empty");
  EXPECT_THROW((void)io::read_photo_folder(empty.path, "DIR"), InputError);
  EXPECT_THROW((void)io::read_photo_folder(empty.path / "missing", "DIR"), InputError);
  testing::write_bytes(dir.path / "c.jpg", "garbage");
  try {
    (void)io::read_photo_folder(dir.path, "DIR");
    FAIL() << "a garbage photo was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.field()), "c.jpg") << e.what();
  }
}

}  // namespace
}  // namespace uavcover
