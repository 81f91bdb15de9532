#include "evaluation/facade.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "photo/photo.hpp"

namespace uavcover::evaluation {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
/// Along-track over across-track when the camera block gives no height (camera.cpp's default aspect).
constexpr double kDefaultAspect = 0.75;
constexpr double kBucketM = 2.0;
/// Steeper views than this from a wall's normal give no texture photogrammetry can match.
constexpr double kMaxIncidenceDeg = 60.0;

struct V3 {
  double x = 0, y = 0, z = 0;
};
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator*(double k, V3 a) { return {k * a.x, k * a.y, k * a.z}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

struct Sample {
  V3 p, n;
  bool wall = true;
};

struct Photo {
  V3 c, f, r, u;
};

/// The camera at `c` with heading `heading_deg` (clockwise from north) and `pitch_deg` (-90 nadir).
Photo make_photo(V3 c, double heading_deg, double pitch_deg) {
  const double t = heading_deg * kDeg, p = pitch_deg * kDeg;
  Photo ph;
  ph.c = c;
  ph.f = {std::sin(t) * std::cos(p), std::cos(t) * std::cos(p), std::sin(p)};
  ph.r = {std::cos(t), -std::sin(t), 0};
  ph.u = {-std::sin(t) * std::sin(p), -std::cos(t) * std::sin(p), std::cos(p)};
  return ph;
}

double bearing_of(Point a, Point b) {
  double d = std::atan2(b.x() - a.x(), b.y() - a.y()) / kDeg;
  return d < 0 ? d + 360 : d;
}

/// Heading between h0 and h1 (degrees) at fraction t, the short way round.
double interpolate_heading(double h0, double h1, double t) {
  double d = std::fmod(h1 - h0 + 540.0, 360.0) - 180.0;
  double h = h0 + t * d;
  h = std::fmod(h, 360.0);
  return h < 0 ? h + 360 : h;
}

FacadeStats stats_of(const std::vector<std::uint16_t>& views, int images) {
  FacadeStats s;
  s.samples = static_cast<int>(views.size());
  s.images = images;
  for (std::uint16_t v : views) ++s.views[std::min<std::size_t>(v, 3)];
  if (s.samples > 0) {
    for (std::size_t k = 0; k < 4; ++k) s.shares[k] = static_cast<double>(s.views[k]) / s.samples;
    s.covered_share = 1.0 - s.shares[0];
    s.share_3plus = s.shares[3];
  }
  return s;
}

nlohmann::json stats_json(const FacadeStats& s) {
  return {{"samples", s.samples},
          {"covered_share", s.covered_share},
          {"share_3plus", s.share_3plus},
          {"views", {{"0", s.views[0]}, {"1", s.views[1]}, {"2", s.views[2]}, {"3+", s.views[3]}}},
          {"view_shares", {{"0", s.shares[0]}, {"1", s.shares[1]}, {"2", s.shares[2]}, {"3+", s.shares[3]}}},
          {"images", s.images}};
}

}  // namespace

double FacadeCamera::width_at(double d) const { return 2.0 * d * std::tan(hfov_rad / 2); }
double FacadeCamera::height_at(double d) const { return 2.0 * d * std::tan(vfov_rad / 2); }
std::optional<double> FacadeCamera::gsd_at(double d) const {
  if (!image_width_px || !(*image_width_px > 0)) return std::nullopt;
  return width_at(d) / *image_width_px;
}

FacadeCamera facade_camera(const Camera& c) {
  FacadeCamera fc;
  fc.front_overlap = c.front_overlap;
  fc.image_width_px = c.image_width_px;
  if (c.hfov_deg) {
    fc.hfov_rad = *c.hfov_deg * kDeg;
    fc.vfov_rad =
        c.vfov_deg ? *c.vfov_deg * kDeg : 2.0 * std::atan(kDefaultAspect * std::tan(fc.hfov_rad / 2));
    fc.side_overlap = c.overlap.value_or(0.0) / 2.0;  // the paper's po counts both sides of an image
  } else if (c.sensor_width_mm && c.focal_length_mm && *c.focal_length_mm > 0) {
    const double sw = *c.sensor_width_mm, f = *c.focal_length_mm;
    const double sh = c.image_height_px && c.image_width_px ? sw * *c.image_height_px / *c.image_width_px
                      : c.sensor_height_mm                  ? *c.sensor_height_mm
                                                            : sw * kDefaultAspect;
    fc.hfov_rad = 2.0 * std::atan(sw / (2 * f));
    fc.vfov_rad = 2.0 * std::atan(sh / (2 * f));
    fc.side_overlap = c.side_overlap.value_or(0.0);
  }
  return fc;
}

std::optional<FacadeCoverage> evaluate_facade(const Plan& plan, const FacadeOptions& options) {
  const Mission& m = plan.mission;
  if (!m.structure || !m.camera) return std::nullopt;
  const Structure& st = *m.structure;
  const geodesy::LocalFrame frame(plan.origin);
  Polygon fp = geometry::to_local(st.footprint, frame);
  bg::correct(fp);
  const double step = options.sample_m > 0 ? options.sample_m : 0.5;
  const FacadeCamera cam = facade_camera(*m.camera);

  FacadeCoverage out;
  out.sample_m = step;
  out.standoff_m = st.standoff_m;
  out.max_range_m = 2.0 * std::max(st.standoff_m, st.top ? m.camera->altitude_m : 0.0);
  out.gsd_wall_m = cam.gsd_at(st.standoff_m);
  out.footprint_width_m = cam.width_at(st.standoff_m);
  out.footprint_height_m = cam.height_at(st.standoff_m);

  // the wall: counter-clockwise from the footprint's first vertex (Boost's rings are clockwise)
  std::vector<Point> ring(fp.outer().begin(), fp.outer().end());
  std::reverse(ring.begin(), ring.end());
  std::vector<Sample> samples;
  out.rows = std::max(1, static_cast<int>(std::ceil(st.height_m / step - 1e-9)));
  std::vector<std::pair<std::size_t, int>> cols;  // per column: its edge and its index on the edge
  std::vector<int> edge_cols;
  for (std::size_t e = 1; e < ring.size(); ++e) {
    const double len = std::hypot(ring[e].x() - ring[e - 1].x(), ring[e].y() - ring[e - 1].y());
    if (len < 1e-9) continue;
    const int nc = std::max(1, static_cast<int>(std::ceil(len / step - 1e-9)));
    out.wall_start_col.push_back(static_cast<int>(cols.size()));
    edge_cols.push_back(nc);
    for (int k = 0; k < nc; ++k) cols.emplace_back(e, k);
    out.wall_area_m2 += len * st.height_m;
  }
  out.cols = static_cast<int>(cols.size());
  samples.reserve(static_cast<std::size_t>(out.cols) * static_cast<std::size_t>(out.rows));
  for (int r = 0; r < out.rows; ++r) {
    const double z = (r + 0.5) * st.height_m / out.rows;
    std::size_t edge_index = 0;
    for (int c = 0; c < out.cols; ++c) {
      const auto [e, k] = cols[static_cast<std::size_t>(c)];
      while (edge_index + 1 < out.wall_start_col.size() && out.wall_start_col[edge_index + 1] <= c)
        ++edge_index;
      const Point a = ring[e - 1], b = ring[e];
      const double len = std::hypot(b.x() - a.x(), b.y() - a.y());
      const double t = (k + 0.5) / edge_cols[edge_index];
      // the outward normal of a counter-clockwise ring is on the right of each edge
      samples.push_back({{a.x() + t * (b.x() - a.x()), a.y() + t * (b.y() - a.y()), z},
                         {(b.y() - a.y()) / len, -(b.x() - a.x()) / len, 0},
                         true});
    }
  }
  out.wall_samples = static_cast<int>(samples.size());
  bg::model::box<Point> box;
  bg::envelope(fp, box);
  if (st.top) {
    for (double y = box.min_corner().y() + step / 2; y < box.max_corner().y(); y += step)
      for (double x = box.min_corner().x() + step / 2; x < box.max_corner().x(); x += step)
        if (bg::within(Point(x, y), fp)) samples.push_back({{x, y, st.height_m}, {0, 0, 1}, false});
    out.roof_samples = static_cast<int>(samples.size()) - out.wall_samples;
    out.roof_area_m2 = std::abs(bg::area(fp));
  }
  if (samples.empty()) return out;

  // the samples in 2 m buckets over the footprint's box
  const double bx0 = box.min_corner().x() - 1, by0 = box.min_corner().y() - 1;
  const int nbx = static_cast<int>(std::ceil((box.max_corner().x() + 1 - bx0) / kBucketM)) + 1;
  const int nby = static_cast<int>(std::ceil((box.max_corner().y() + 1 - by0) / kBucketM)) + 1;
  std::vector<std::vector<std::uint32_t>> buckets(static_cast<std::size_t>(nbx) *
                                                  static_cast<std::size_t>(nby));
  for (std::size_t s = 0; s < samples.size(); ++s) {
    const int ix = std::clamp(static_cast<int>((samples[s].p.x - bx0) / kBucketM), 0, nbx - 1);
    const int iy = std::clamp(static_cast<int>((samples[s].p.y - by0) / kBucketM), 0, nby - 1);
    buckets[static_cast<std::size_t>(iy) * nbx + ix].push_back(static_cast<std::uint32_t>(s));
  }
  const bool convex = [&] {
    Polygon hull;
    bg::convex_hull(fp, hull);
    return std::abs(bg::area(hull)) - std::abs(bg::area(fp)) <= 1e-6 * std::abs(bg::area(fp));
  }();

  const std::size_t nu = plan.uavs.size();
  std::vector<std::uint16_t> total(samples.size(), 0);
  std::vector<std::vector<std::uint16_t>> per(nu, std::vector<std::uint16_t>(samples.size(), 0));
  std::vector<int> images(nu, 0);
  const double R = out.max_range_m;

  auto shoot = [&](std::size_t u, const Photo& ph, const FacadeCamera& fc) {
    const double th = std::tan(fc.hfov_rad / 2), tv = std::tan(fc.vfov_rad / 2);
    double x0 = ph.c.x, x1 = ph.c.x, y0 = ph.c.y, y1 = ph.c.y;
    for (double sr : {-1.0, 1.0})
      for (double su : {-1.0, 1.0}) {
        const V3 q = ph.c + R * ph.f + (R * th * sr) * ph.r + (R * tv * su) * ph.u;
        x0 = std::min(x0, q.x), x1 = std::max(x1, q.x), y0 = std::min(y0, q.y), y1 = std::max(y1, q.y);
      }
    const int ix0 = std::max(0, static_cast<int>(std::floor((x0 - bx0) / kBucketM)));
    const int ix1 = std::min(nbx - 1, static_cast<int>(std::floor((x1 - bx0) / kBucketM)));
    const int iy0 = std::max(0, static_cast<int>(std::floor((y0 - by0) / kBucketM)));
    const int iy1 = std::min(nby - 1, static_cast<int>(std::floor((y1 - by0) / kBucketM)));
    for (int iy = iy0; iy <= iy1; ++iy)
      for (int ix = ix0; ix <= ix1; ++ix)
        for (std::uint32_t s : buckets[static_cast<std::size_t>(iy) * nbx + ix]) {
          const Sample& sm = samples[s];
          const V3 v = sm.p - ph.c;
          const double d = dot(v, ph.f);
          if (d <= 1e-6 || d > R) continue;
          if (std::abs(dot(v, ph.r)) > d * th || std::abs(dot(v, ph.u)) > d * tv) continue;
          // the sample faces the camera, at most kMaxIncidenceDeg from its normal
          if (-dot(sm.n, v) < std::cos(kMaxIncidenceDeg * kDeg) * std::sqrt(dot(v, v))) continue;
          if (sm.wall && !convex) {
            // hidden by another part of the building: the sight line crosses the footprint below its top
            const Point c2(ph.c.x, ph.c.y), p2(sm.p.x + 0.01 * sm.n.x, sm.p.y + 0.01 * sm.n.y);
            const bg::model::linestring<Point> sight{c2, p2};
            if (bg::intersects(sight, fp)) {
              bg::model::multi_linestring<bg::model::linestring<Point>> inside;
              bg::intersection(sight, fp, inside);
              const double full = std::hypot(p2.x() - c2.x(), p2.y() - c2.y());
              bool hidden = false;
              for (const auto& piece : inside)
                for (const Point& q : piece) {
                  const double t = full > 0 ? std::hypot(q.x() - c2.x(), q.y() - c2.y()) / full : 1.0;
                  if (t < 0.999 && ph.c.z + t * (sm.p.z - ph.c.z) < st.height_m - 1e-6) hidden = true;
                }
              if (hidden) continue;
            }
          }
          if (total[s] < 65535) ++total[s];
          if (per[u][s] < 65535) ++per[u][s];
        }
  };

  for (std::size_t u = 0; u < nu; ++u) {
    const Uav* uav = u < m.uavs.size() ? &m.uavs[u] : nullptr;
    const FacadeCamera fc = uav != nullptr && uav->camera ? facade_camera(*uav->camera) : cam;
    const double own_trigger = uav != nullptr && uav->camera_geometry
                                   ? uav->camera_geometry->trigger_distance_m
                                   : m.trigger_distance_m.value_or(0.0);
    for (const auto& part : plan.uavs[u].parts) {
      if (part.kind != PartKind::Coverage || part.local.size() < 2) continue;
      const Attitude& at = part.attitude;
      const double z = at.altitude_m.value_or(m.altitude_m);
      const double pitch = at.gimbal_pitch_deg.value_or(m.camera->gimbal_pitch_deg);
      const double trigger = at.trigger_distance_m.value_or(own_trigger);
      const bool headings = at.heading_deg.size() == part.local.size();
      bool prev_shot = false;
      for (std::size_t k = 0; k + 1 < part.local.size(); ++k) {
        if (!part.camera_on(k)) {
          prev_shot = false;
          continue;
        }
        const Point a = part.local[k], b = part.local[k + 1];
        const double len = std::hypot(b.x() - a.x(), b.y() - a.y());
        const std::vector<Point> shots = photo::leg_shots(a, b, trigger);
        for (std::size_t j = prev_shot ? 1 : 0; j < shots.size(); ++j) {
          const Point& p = shots[j];
          const double t = len > 0 ? std::hypot(p.x() - a.x(), p.y() - a.y()) / len : 0.0;
          const double h =
              headings ? interpolate_heading(at.heading_deg[k], at.heading_deg[k + 1], t) : bearing_of(a, b);
          shoot(u, make_photo({p.x(), p.y(), z}, h, pitch), fc);
          ++images[u];
        }
        prev_shot = true;
      }
    }
  }

  int all_images = 0;
  for (std::size_t u = 0; u < nu; ++u) {
    out.uavs.push_back(stats_of(per[u], images[u]));
    out.uav_ids.push_back(plan.uavs[u].id);
    all_images += images[u];
  }
  out.total = stats_of(total, all_images);
  out.views.assign(total.begin(), total.begin() + out.wall_samples);
  return out;
}

nlohmann::json to_json(const FacadeCoverage& f, bool unrolled) {
  nlohmann::json j = stats_json(f.total);
  j["sample_m"] = f.sample_m;
  j["wall_samples"] = f.wall_samples;
  j["roof_samples"] = f.roof_samples;
  j["wall_area_m2"] = f.wall_area_m2;
  j["roof_area_m2"] = f.roof_area_m2;
  j["standoff_m"] = f.standoff_m;
  j["max_range_m"] = f.max_range_m;
  j["max_incidence_deg"] = kMaxIncidenceDeg;
  j["photo_width_m"] = f.footprint_width_m;
  j["photo_height_m"] = f.footprint_height_m;
  j["gsd_wall_m"] = f.gsd_wall_m ? nlohmann::json(*f.gsd_wall_m) : nlohmann::json(nullptr);
  j["gsd_wall_cm_per_px"] = f.gsd_wall_m ? nlohmann::json(*f.gsd_wall_m * 100) : nlohmann::json(nullptr);
  nlohmann::json uavs = nlohmann::json::array();
  for (std::size_t u = 0; u < f.uavs.size(); ++u) {
    nlohmann::json ju = stats_json(f.uavs[u]);
    ju["id"] = u < f.uav_ids.size() ? f.uav_ids[u] : "";
    uavs.push_back(std::move(ju));
  }
  j["uavs"] = std::move(uavs);
  if (unrolled && f.cols > 0 && f.rows > 0 && f.views.size() == static_cast<std::size_t>(f.cols) * f.rows) {
    nlohmann::json rows = nlohmann::json::array();
    for (int r = f.rows - 1; r >= 0; --r) {
      std::string line(static_cast<std::size_t>(f.cols), '0');
      for (int c = 0; c < f.cols; ++c)
        line[static_cast<std::size_t>(c)] =
            static_cast<char>('0' + std::min<int>(9, f.views[static_cast<std::size_t>(r) * f.cols + c]));
      rows.push_back(std::move(line));
    }
    j["unrolled"] = {{"cols", f.cols},
                     {"rows", f.rows},
                     {"wall_start_col", f.wall_start_col},
                     {"order",
                      "columns counter-clockwise from the footprint's first vertex; rows top first; "
                      "views per sample, capped at 9"},
                     {"views", std::move(rows)}};
  }
  return j;
}

}  // namespace uavcover::evaluation
