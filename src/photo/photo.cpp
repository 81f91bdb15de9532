#include "photo/photo.hpp"

#include <algorithm>
#include <cmath>

namespace uavcover::photo {

namespace {

double dist(const Point& a, const Point& b) { return std::hypot(b.x() - a.x(), b.y() - a.y()); }

/// Below this a leg counts as one point (a closed loop's repeated vertex, rounding).
constexpr double kMinLeg = 1e-6;

bool same_place(const LonLat& a, const LonLat& b) {
  return std::abs(a.lat - b.lat) < 1e-9 && std::abs(a.lon - b.lon) < 1e-9;
}

}  // namespace

int leg_images(double length_m, double trigger_m) {
  if (!(trigger_m > 0) || !(length_m > kMinLeg)) return 1;
  return static_cast<int>(std::ceil(length_m / trigger_m - 1e-9)) + 1;
}

std::vector<Point> leg_shots(const Point& a, const Point& b, double trigger_m) {
  const double len = dist(a, b);
  const int n = leg_images(len, trigger_m);
  std::vector<Point> shots;
  shots.reserve(static_cast<std::size_t>(n));
  for (int k = 0; k + 1 < n; ++k) {
    const double t = std::min(1.0, k * trigger_m / len);
    shots.emplace_back(a.x() + t * (b.x() - a.x()), a.y() + t * (b.y() - a.y()));
  }
  shots.push_back(b);
  return shots;
}

std::optional<Estimate> estimate(const Plan& plan) {
  const Mission& m = plan.mission;
  if (!m.camera || !m.trigger_distance_m || !m.footprint_m || !m.along_track_footprint_m) return std::nullopt;
  const Camera& cam = *m.camera;
  Estimate e;
  e.capture = cam.capture;
  e.trigger_distance_m = *m.trigger_distance_m;
  e.footprint_across_m = *m.footprint_m;
  e.footprint_along_m = *m.along_track_footprint_m;
  e.gsd_m = m.gsd_m;
  e.gimbal_pitch_deg = cam.gimbal_pitch_deg;
  e.side_overlap = 1.0 - m.spacing_m / e.footprint_across_m;
  double along_fraction = 0.0;  // sum of leg length / the shooting camera's along-track footprint
  int gaps = 0;                 // intervals between consecutive shots of a leg
  for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
    const UavPlan& up = plan.uavs[i];
    // heterogeneous cameras: a UAV with its own camera shoots at its own trigger distance
    const Uav* mu = i < m.uavs.size() ? &m.uavs[i] : nullptr;
    const bool own = mu != nullptr && mu->camera && mu->camera_geometry;
    const Camera& c = own ? *mu->camera : cam;
    const double trigger = own ? mu->camera_geometry->trigger_distance_m : e.trigger_distance_m;
    const double along = own ? mu->camera_geometry->along_track_footprint_m : e.footprint_along_m;
    UavImages u;
    u.id = up.id;
    u.trigger_distance_m = trigger;
    u.footprint_across_m = own ? mu->camera_geometry->footprint_m : e.footprint_across_m;
    // where the last shot leg ended, while nothing else has been flown since (a shared corner follows)
    std::optional<LonLat> corner;
    for (const PathPart& part : up.parts) {
      if (part.wgs84.empty()) continue;
      if (part.kind != PartKind::Coverage) {  // transit: the UAV climbs and leaves
        corner.reset();
        continue;
      }
      const bool local = part.local.size() == part.wgs84.size();
      if (!local) continue;
      if (corner && !same_place(*corner, part.wgs84.front())) corner.reset();
      for (std::size_t k = 1; k < part.local.size(); ++k) {
        const double len = dist(part.local[k - 1], part.local[k]);
        if (!part.camera_on(k - 1)) {  // a turn or turnaround with the camera off (docs/patterns.md)
          corner.reset();
          continue;
        }
        if (len <= kMinLeg) continue;
        // a part with its own trigger distance (oblique passes, docs/patterns.md) shoots at it
        const int n = leg_images(len, part.attitude.trigger_distance_m.value_or(trigger));
        ++u.legs;
        // a leg starting where the previous one ended shares its first image with that one's last
        const bool shared = corner && same_place(*corner, part.wgs84[k - 1]);
        u.images += shared ? n - 1 : n;
        u.shared_corners += shared ? 1 : 0;
        const bool oblique = part.attitude.gimbal_pitch_deg && *part.attitude.gimbal_pitch_deg > -90.0 + 1e-9;
        if (oblique) u.oblique_images += shared ? n - 1 : n;
        if (!oblique) {  // the achieved front overlap is the nadir footprint's
          along_fraction += len / along;
          gaps += n - 1;
        }
        corner = part.wgs84[k];
      }
    }
    const double speed = mu != nullptr ? mu->speed_mps : 0.0;
    u.trigger_interval_s = speed > 0 ? trigger / speed : 0.0;
    u.hover_time_s = c.capture == "hover" ? u.images * kHoverHoldS : 0.0;
    u.storage_mb = u.images * c.image_size_mb;
    e.images += u.images;
    e.oblique_images += u.oblique_images;
    e.storage_mb += u.storage_mb;
    e.uavs.push_back(std::move(u));
  }
  e.front_overlap = gaps > 0 ? 1.0 - along_fraction / gaps : cam.front_overlap;
  return e;
}

nlohmann::json to_json(const Estimate& e) {
  nlohmann::json uavs = nlohmann::json::array();
  for (const UavImages& u : e.uavs)
    uavs.push_back({{"id", u.id},
                    {"legs", u.legs},
                    {"images", u.images},
                    {"shared_corners", u.shared_corners},
                    {"oblique_images", u.oblique_images},
                    {"trigger_distance_m", u.trigger_distance_m},
                    {"footprint_across_m", u.footprint_across_m},
                    {"trigger_interval_s", u.trigger_interval_s},
                    {"hover_time_s", u.hover_time_s},
                    {"storage_mb", u.storage_mb}});
  return {{"capture", e.capture},
          {"trigger_distance_m", e.trigger_distance_m},
          {"footprint_across_m", e.footprint_across_m},
          {"footprint_along_m", e.footprint_along_m},
          {"gsd_m", e.gsd_m ? nlohmann::json(*e.gsd_m) : nlohmann::json(nullptr)},
          {"side_overlap", e.side_overlap},
          {"front_overlap", e.front_overlap},
          {"gimbal_pitch_deg", e.gimbal_pitch_deg},
          {"images", e.images},
          {"oblique_images", e.oblique_images},
          {"storage_mb", e.storage_mb},
          {"uavs", std::move(uavs)}};
}

}  // namespace uavcover::photo
