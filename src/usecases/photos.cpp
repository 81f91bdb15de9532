// What the photos really saw (issue 32, docs/photos.md).
#include "usecases/photos.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <boost/geometry.hpp>
#include <cmath>
#include <numbers>

#include "geodesy/local_frame.hpp"
#include "render/render.hpp"
#include "uavcover/error.hpp"

namespace uavcover::usecases {

namespace bg = boost::geometry;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
/// A ray at or above the horizon sees no ground point: each footprint corner is capped this many camera
/// heights away horizontally (a tilted photo's far edge).
constexpr double kMaxReach = 10.0;
/// Lowest height a photo is projected from (a photo on the ground sees nothing worth mapping).
constexpr double kMinHeightM = 1.0;

struct Vec3 {
  double x, y, z;
};
Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3 operator*(double k, Vec3 a) { return {k * a.x, k * a.y, k * a.z}; }
Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

/// tan(hfov/2), tan(vfov/2) of the photo's camera.
std::array<double, 2> half_fov_tangents(const Mission& m, const io::PhotoTags& t) {
  if (m.footprint_m && m.along_track_footprint_m && m.altitude_m > 0)
    return {*m.footprint_m / (2.0 * m.altitude_m), *m.along_track_footprint_m / (2.0 * m.altitude_m)};
  if (t.focal_35mm_mm)  // a 36 x 24 mm frame behind the 35 mm-equivalent focal length
    return {18.0 / *t.focal_35mm_mm, 12.0 / *t.focal_35mm_mm};
  throw InputError(t.name + ".FocalLengthIn35mmFilm",
                   "the plan's mission has no camera and the photo gives no 35 mm-equivalent focal length: "
                   "the field of view is unknown");
}

/// The ground under the camera, in the camera-centred ENU frame: four corners of the frustum hitting the
/// ground plane `height` below (image width across the heading, its top towards the heading).
std::array<Point, 4> corners(double height, double yaw_deg, double pitch_deg, std::array<double, 2> tans) {
  const double psi = yaw_deg * kDeg, theta = pitch_deg * kDeg;
  const Vec3 heading{std::sin(psi), std::cos(psi), 0.0};
  const Vec3 forward = std::cos(theta) * heading + std::sin(theta) * Vec3{0.0, 0.0, 1.0};
  const Vec3 right{std::cos(psi), -std::sin(psi), 0.0};
  const Vec3 up = cross(right, forward);
  std::array<Point, 4> out;
  const std::array<std::array<double, 2>, 4> signs{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};
  for (std::size_t k = 0; k < 4; ++k) {
    const Vec3 d = forward + (signs[k][0] * tans[0]) * right + (signs[k][1] * tans[1]) * up;
    const double horiz = std::hypot(d.x, d.y);
    const double reach = kMaxReach * height;
    if (d.z < 0.0 && height / -d.z * horiz <= reach) {
      const double t = height / -d.z;
      out[k] = Point(t * d.x, t * d.y);
    } else if (horiz > 0.0) {
      out[k] = Point(d.x / horiz * reach, d.y / horiz * reach);
    } else {
      out[k] = Point(0.0, 0.0);
    }
  }
  return out;
}

}  // namespace

PhotoCoverage photo_coverage(const Plan& plan, const std::vector<io::PhotoTags>& photos,
                             const PhotoOptions& options, const Context& ctx) {
  if (photos.empty()) throw InputError("photos", "no photos");
  if (photos.size() > io::kMaxPhotos) throw InputError("photos", fmt::format("more than {}", io::kMaxPhotos));
  const Mission& m = plan.mission;
  evaluation::EvaluateOptions eo;
  eo.coverage.context = &ctx;
  const evaluation::Evaluation planned = evaluation::evaluate_plan(plan, eo);
  const geodesy::LocalFrame frame(plan.origin);
  const HeightGrid* dem = m.terrain && m.terrain->grid ? m.terrain->grid.get() : nullptr;

  PhotoCoverage out;
  out.planned_poc = planned.coverage.total.poc;
  out.lattice = planned.coverage;
  for (int& s : out.lattice.scans)
    if (s > 0) s = 0;
  std::vector<Polygon> shapes;
  for (std::size_t i = 0; i < photos.size(); ++i) {
    if (i % 64 == 0) ctx.check();
    const io::PhotoTags& t = photos[i];
    PhotoFootprint f;
    f.name = t.name;
    double height = 0.0;
    if (dem && t.gps_altitude_m) {
      height = *t.gps_altitude_m - dem->at({t.lon, t.lat});
      f.height_source = "dem";
    } else if (t.relative_altitude_m) {
      height = *t.relative_altitude_m;
      f.height_source = "relative";
    } else if (t.gps_altitude_m && options.takeoff_altitude_m) {
      height = *t.gps_altitude_m - *options.takeoff_altitude_m;
      f.height_source = "takeoff";
    } else {
      throw InputError(t.name + ".RelativeAltitude",
                       t.gps_altitude_m ? "missing: give the take-off's altitude above sea level "
                                          "(--takeoff-alt-m) to use the GPS altitude"
                                        : "missing, and the photo has no GPS altitude either");
    }
    if (!(height >= kMinHeightM)) {
      out.skipped.push_back(fmt::format("{}: {:.1f} m above the ground sees no footprint", t.name, height));
      continue;
    }
    f.height_m = height;
    f.pitch_deg = std::clamp(t.gimbal_pitch_deg.value_or(-90.0), -90.0, 0.0);
    f.yaw_known = t.yaw_deg.has_value();
    f.yaw_deg = t.yaw_deg.value_or(0.0);
    const auto tans = half_fov_tangents(m, t);
    const Point c = frame.to_local({t.lon, t.lat});
    Polygon shape;
    if (f.yaw_known || f.pitch_deg > -89.0) {
      for (const Point& p : corners(height, f.yaw_deg, f.pitch_deg, tans))
        shape.outer().push_back(Point(c.x() + p.x(), c.y() + p.y()));
    } else {
      // a nadir photo that does not say which way it faced: the disc every heading's footprint holds
      const double r = height * std::min(tans[0], tans[1]);
      for (int k = 0; k < 32; ++k) {
        const double a = 2.0 * std::numbers::pi * k / 32.0;
        shape.outer().push_back(Point(c.x() + r * std::cos(a), c.y() + r * std::sin(a)));
      }
    }
    shape.outer().push_back(shape.outer().front());
    bg::correct(shape);
    GeoRing ring;
    for (const Point& p : shape.outer()) ring.push_back(frame.to_wgs84(p));
    f.ground = {ring};
    shapes.push_back(std::move(shape));
    out.photos.push_back(std::move(f));
  }

  // each footprint marks the lattice samples inside it
  evaluation::CoverageResult& L = out.lattice;
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    if (k % 64 == 0) ctx.check();
    bg::model::box<Point> box;
    bg::envelope(shapes[k], box);
    const auto col = [&](double x) { return (x - L.lattice_origin.x()) / L.lattice_m; };
    const auto row = [&](double y) { return (y - L.lattice_origin.y()) / L.lattice_m; };
    const int c0 = std::max(0, static_cast<int>(std::ceil(col(box.min_corner().x()))));
    const int c1 = std::min(L.lattice_cols - 1, static_cast<int>(std::floor(col(box.max_corner().x()))));
    const int r0 = std::max(0, static_cast<int>(std::ceil(row(box.min_corner().y()))));
    const int r1 = std::min(L.lattice_rows - 1, static_cast<int>(std::floor(row(box.max_corner().y()))));
    for (int r = r0; r <= r1; ++r)
      for (int cc = c0; cc <= c1; ++cc) {
        int& s = L.scans[static_cast<std::size_t>(r) * static_cast<std::size_t>(L.lattice_cols) +
                         static_cast<std::size_t>(cc)];
        if (s < 0) continue;
        const Point p(L.lattice_origin.x() + cc * L.lattice_m, L.lattice_origin.y() + r * L.lattice_m);
        if (bg::covered_by(p, shapes[k])) ++s;
      }
  }
  std::size_t inside = 0, once = 0, twice = 0;
  int max_scans = 0;
  for (const int s : L.scans) {
    if (s < 0) continue;
    ++inside;
    once += s >= 1 ? 1 : 0;
    twice += s >= 2 ? 1 : 0;
    max_scans = std::max(max_scans, s);
  }
  out.poc = inside ? static_cast<double>(once) / static_cast<double>(inside) : 0.0;
  out.pooc = inside ? static_cast<double>(twice) / static_cast<double>(inside) : 0.0;
  L.total.poc = out.poc;
  L.total.pooc = out.pooc;
  L.total.max_scans = max_scans;
  L.uavs.clear();
  out.bounds = evaluation::lattice_bounds(L, frame);
  out.overlay = render::heatmap_overlay_png(L, "photo-coverage.png");
  out.gaps = lattice_gaps(plan, L, ctx);
  out.gaps.flown_poc = out.poc;
  out.gaps.planned_poc = out.planned_poc;
  return out;
}

namespace {

nlohmann::json gaps_geometry(const ReflyGaps& gaps) {
  nlohmann::json polys = nlohmann::json::array();
  for (const auto& p : gaps.area) polys.push_back(polygon_coordinates(p));
  return {{"type", "MultiPolygon"}, {"coordinates", std::move(polys)}};
}

}  // namespace

std::string photos_geojson(const PhotoCoverage& c) {
  nlohmann::json features = nlohmann::json::array();
  for (const auto& p : c.photos) {
    nlohmann::json props = {{"kind", "photo"},
                            {"name", p.name},
                            {"height_m", p.height_m},
                            {"pitch_deg", p.pitch_deg},
                            {"height_source", p.height_source}};
    props["yaw_deg"] = p.yaw_known ? nlohmann::json(p.yaw_deg) : nlohmann::json(nullptr);
    features.push_back({{"type", "Feature"},
                        {"properties", std::move(props)},
                        {"geometry", {{"type", "Polygon"}, {"coordinates", polygon_coordinates(p.ground)}}}});
  }
  features.push_back({{"type", "Feature"},
                      {"properties", {{"kind", "gap"}, {"area_m2", c.gaps.area_m2}}},
                      {"geometry", gaps_geometry(c.gaps)}});
  return nlohmann::json({{"type", "FeatureCollection"}, {"features", std::move(features)}}).dump() + "\n";
}

nlohmann::json photo_summary(const PhotoCoverage& c) {
  return {{"photos", c.photos.size()},
          {"skipped", c.skipped},
          {"poc", c.poc},
          {"pooc", c.pooc},
          {"planned_poc", c.planned_poc},
          {"gaps_m2", c.gaps.area_m2},
          {"gaps", gaps_geometry(c.gaps)},
          {"bounds",
           {{"south", c.bounds.south},
            {"west", c.bounds.west},
            {"north", c.bounds.north},
            {"east", c.bounds.east}}}};
}

}  // namespace uavcover::usecases
