// What the photos saw (issue 32, docs/photos.md): nadir and tilted footprints from geotagged JPEGs (made
// with GDAL, tagged with exiv2), the coverage of the plan's field, the gap a missing block of photos
// leaves, and the refly of it.
#include "usecases/photos.hpp"

#include <gtest/gtest.h>

#include <boost/geometry.hpp>
#include <cmath>
#include <filesystem>

#include "geodesy/local_frame.hpp"
#include "support/files.hpp"
#include "support/photos.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/rectangle_plan.hpp"

namespace uavcover {
namespace {

namespace bg = boost::geometry;
using testing::PhotoSpec;

using testing::rectangle_plan;

io::PhotoTags tags_of(const PhotoSpec& s, const std::string& name) {
  const std::string bytes = testing::photo_jpeg(s);
  return io::read_photo_tags(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), name);
}

/// A photo at local (x, y) of `frame`, 30 m above take-off, facing north, nadir, 24 mm equivalent (a
/// 45 m x 30 m footprint).
PhotoSpec nadir_at(const geodesy::LocalFrame& frame, double x, double y) {
  return testing::nadir_photo(frame.to_wgs84(Point(x, y)), 30.0);
}

/// The field's south-west corner in the plan's frame.
Point south_west(const geodesy::LocalFrame& frame) { return frame.to_local({9.15, 45.39}); }

/// Photos every 30 m east and 20 m north over the field (x 10..100, y 10..190), less those `skip` says.
template <class Skip>
std::vector<io::PhotoTags> grid(const Plan& p, Skip skip) {
  const geodesy::LocalFrame frame(p.origin);
  const Point sw = south_west(frame);
  std::vector<io::PhotoTags> out;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 10; ++j) {
      const double x = 10.0 + 30.0 * i, y = 10.0 + 20.0 * j;
      if (skip(x, y)) continue;
      out.push_back(
          tags_of(nadir_at(frame, sw.x() + x, sw.y() + y), "p" + std::to_string(i * 10 + j) + ".jpg"));
    }
  return out;
}

TEST(Photos, AFullGridCoversTheFieldAndAMissingBlockIsTheGap) {
  const Plan p = rectangle_plan();
  const auto all = usecases::photo_coverage(p, grid(p, [](double, double) { return false; }));
  EXPECT_EQ(all.photos.size(), 40u);
  EXPECT_GE(all.poc, 0.999);
  EXPECT_GT(all.pooc, 0.3) << "neighbouring footprints overlap (45 m wide every 30 m)";
  EXPECT_LT(all.gaps.area_m2, 1.0) << "nothing left to fly";
  EXPECT_GT(all.planned_poc, 0.99);
  EXPECT_EQ(all.photos[0].height_source, "relative");

  // four photos around (55, 100) missing: no footprint covers x 32.5..77.5, y 85..115 (1 350 m^2)
  const auto holed = usecases::photo_coverage(
      p, grid(p, [](double x, double y) { return (x == 40.0 || x == 70.0) && (y == 90.0 || y == 110.0); }));
  EXPECT_EQ(holed.photos.size(), 36u);
  EXPECT_NEAR(holed.poc, 1.0 - 1350.0 / 20000.0, 0.01);
  ASSERT_EQ(holed.gaps.local.size(), 1u);
  // the gap grown by half the spacing (5 m) for the refly's sweeps: 55 m x 40 m, rounded corners
  EXPECT_GT(holed.gaps.area_m2, 1350.0);
  EXPECT_LT(holed.gaps.area_m2, 55.0 * 40.0 + 1.0);
  const geodesy::LocalFrame frame(p.origin);
  const Point sw = south_west(frame);
  Point c;
  bg::centroid(holed.gaps.local, c);
  EXPECT_NEAR(c.x() - sw.x(), 55.0, 2.0);
  EXPECT_NEAR(c.y() - sw.y(), 100.0, 2.0);

  // the refly flies exactly the gap
  const Mission refly = usecases::refly_mission(p, holed.gaps, {"red"});
  ASSERT_EQ(refly.uavs.size(), 1u);
  const Plan second = plan(refly);
  EXPECT_GT(second.uavs[0].turns, 0);
  const auto summary = usecases::photo_summary(holed);
  EXPECT_EQ(summary["photos"], 36);
  EXPECT_EQ(summary["gaps"]["type"], "MultiPolygon");
  const auto fc = nlohmann::json::parse(usecases::photos_geojson(holed));
  EXPECT_EQ(fc["features"].size(), 37u) << "36 footprints and the gaps";
  EXPECT_EQ(holed.overlay.name, "photo-coverage.png");
  EXPECT_EQ(holed.overlay.bytes.substr(1, 3), "PNG");
}

TEST(Photos, ATiltedPhotosFootprintIsTheFrustumOnTheGround) {
  const Plan p = rectangle_plan();
  const geodesy::LocalFrame frame(p.origin);
  PhotoSpec s = nadir_at(frame, 0.0, 0.0);
  s.relative_altitude_m = 100.0;
  s.gimbal_pitch_deg = -45.0;
  s.gimbal_yaw_deg = 90.0;  // facing east
  const auto c = usecases::photo_coverage(p, {tags_of(s, "tilt.jpg")});
  ASSERT_EQ(c.photos.size(), 1u);
  // vfov/2 = atan(0.5) = 26.57 deg: the near edge 100 tan(45 - 26.57) = 33.3 m east, the far edge
  // 100 tan(45 + 26.57) = 300 m; half-widths from hfov (tan 0.75) at the corners' slant ranges
  double xmin = 1e9, xmax = -1e9, ymax_near = 0, ymax_far = 0;
  for (const auto& g : c.photos[0].ground.front()) {
    const Point q = frame.to_local(g);
    xmin = std::min(xmin, q.x());
    xmax = std::max(xmax, q.x());
  }
  for (const auto& g : c.photos[0].ground.front()) {
    const Point q = frame.to_local(g);
    if (std::abs(q.x() - xmin) < 0.5) ymax_near = std::max(ymax_near, std::abs(q.y()));
    if (std::abs(q.x() - xmax) < 0.5) ymax_far = std::max(ymax_far, std::abs(q.y()));
  }
  EXPECT_NEAR(xmin, 100.0 / 3.0, 0.1);
  EXPECT_NEAR(xmax, 300.0, 0.1);
  EXPECT_NEAR(ymax_near, 70.71, 0.1);
  EXPECT_NEAR(ymax_far, 212.13, 0.1);
}

TEST(Photos, HeightsAndTheirRefusals) {
  const Plan p = rectangle_plan();
  const geodesy::LocalFrame frame(p.origin);
  // no yaw: the disc every heading's footprint holds, radius 30 m * min(0.75, 0.5)
  PhotoSpec s = nadir_at(frame, 10.0, 20.0);
  s.gimbal_yaw_deg.reset();
  auto c = usecases::photo_coverage(p, {tags_of(s, "noyaw.jpg")});
  ASSERT_EQ(c.photos.size(), 1u);
  EXPECT_FALSE(c.photos[0].yaw_known);
  for (const auto& g : c.photos[0].ground.front())
    EXPECT_NEAR(bg::distance(frame.to_local(g), Point(10.0, 20.0)), 15.0, 0.05);
  // a GPS altitude only: the take-off's altitude is needed
  PhotoSpec gps = nadir_at(frame, 10.0, 20.0);
  gps.relative_altitude_m.reset();
  gps.gps_altitude_m = 150.0;
  try {
    (void)usecases::photo_coverage(p, {tags_of(gps, "gps.jpg")});
    FAIL() << "a photo without a height above the ground was projected";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.field()), "gps.jpg.RelativeAltitude") << e.what();
  }
  usecases::PhotoOptions po;
  po.takeoff_altitude_m = 120.0;
  c = usecases::photo_coverage(p, {tags_of(gps, "gps.jpg")}, po);
  EXPECT_NEAR(c.photos[0].height_m, 30.0, 1e-6);
  EXPECT_EQ(c.photos[0].height_source, "takeoff");
  // on the ground: skipped with the reason, not projected
  PhotoSpec low = nadir_at(frame, 10.0, 20.0);
  low.relative_altitude_m = 0.2;
  c = usecases::photo_coverage(p, {tags_of(low, "low.jpg"), tags_of(s, "ok.jpg")});
  EXPECT_EQ(c.photos.size(), 1u);
  ASSERT_EQ(c.skipped.size(), 1u);
  EXPECT_EQ(c.skipped[0].rfind("low.jpg", 0), 0u);
  // no camera in the mission and no 35 mm focal length: the field of view is unknown
  PhotoSpec nofocal = nadir_at(frame, 10.0, 20.0);
  nofocal.focal_35mm.reset();
  EXPECT_THROW((void)usecases::photo_coverage(p, {tags_of(nofocal, "nf.jpg")}), InputError);
  EXPECT_THROW((void)usecases::photo_coverage(p, {}), InputError);
}

}  // namespace
}  // namespace uavcover
