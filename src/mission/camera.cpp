// The camera block of a mission (or of a UAV) and its ground geometry: footprint, line spacing,
// trigger distance, GSD.
#include <cmath>
#include <numbers>

#include "mission/parse_internal.hpp"
#include "uavcover/error.hpp"

namespace uavcover::mission::detail {

namespace {

/// Along-track footprint over across-track footprint when the camera block gives no height (4:3, the
/// image format of most survey cameras, in landscape across the flight direction).
constexpr double kDefaultAspect = 0.75;

}  // namespace

// A camera block at `field` ("camera", or "uavs[i].camera" for a UAV's own).
Camera parse_camera(const json& j, const std::string& field) {
  if (!j.is_object()) throw InputError(field, "expected an object");
  reject_unknown(j,
                 {"altitude_m", "hfov_deg", "overlap", "sensor_width_mm", "focal_length_mm", "image_width_px",
                  "side_overlap", "front_overlap", "vfov_deg", "sensor_height_mm", "image_height_px",
                  "min_trigger_interval_s", "gimbal_pitch_deg", "capture", "image_size_mb"},
                 field + ".");
  if (!j.contains("altitude_m")) throw InputError(field + ".altitude_m", "missing");
  Camera c;
  c.altitude_m = positive(j["altitude_m"], field + ".altitude_m");
  const bool fov = j.contains("hfov_deg") || j.contains("overlap") || j.contains("vfov_deg");
  // image_width_px belongs to both: the paper's GSD (eq. 23) is the footprint over it
  const bool qgc = j.contains("sensor_width_mm") || j.contains("focal_length_mm") ||
                   (j.contains("image_width_px") && !fov) || j.contains("side_overlap") ||
                   j.contains("sensor_height_mm") || j.contains("image_height_px");
  if (fov == qgc)
    throw InputError(field,
                     "give either hfov_deg and overlap, or sensor_width_mm, focal_length_mm, "
                     "image_width_px and side_overlap");
  auto need = [&](const char* k) -> const json& {
    if (!j.contains(k)) throw InputError(field + "." + k, "missing");
    return j[k];
  };
  if (fov) {
    c.hfov_deg = number(need("hfov_deg"), field + ".hfov_deg");
    if (*c.hfov_deg <= 0 || *c.hfov_deg >= 180) throw InputError(field + ".hfov_deg", "must be in (0, 180)");
    // the paper's percentage of overlap po (eq. 13-14): the overlap on both sides of an image, so in
    // [0, 2); its search-and-rescue mission flew 160 % (po 1.6, ds = 0.4·h·tan(HFOV/2))
    c.overlap = in_range(need("overlap"), field + ".overlap", 0.0, 2.0, true);
    if (j.contains("image_width_px"))
      c.image_width_px = positive(j["image_width_px"], field + ".image_width_px");
    if (j.contains("vfov_deg")) {
      c.vfov_deg = number(j["vfov_deg"], field + ".vfov_deg");
      if (*c.vfov_deg <= 0 || *c.vfov_deg >= 180)
        throw InputError(field + ".vfov_deg", "must be in (0, 180)");
    }
  } else {
    c.sensor_width_mm = positive(need("sensor_width_mm"), field + ".sensor_width_mm");
    c.focal_length_mm = positive(need("focal_length_mm"), field + ".focal_length_mm");
    c.image_width_px = positive(need("image_width_px"), field + ".image_width_px");
    c.side_overlap = in_range(need("side_overlap"), field + ".side_overlap", 0.0, 1.0, true);
    if (j.contains("sensor_height_mm"))
      c.sensor_height_mm = positive(j["sensor_height_mm"], field + ".sensor_height_mm");
    if (j.contains("image_height_px"))
      c.image_height_px = positive(j["image_height_px"], field + ".image_height_px");
  }
  if (j.contains("front_overlap"))
    c.front_overlap = in_range(j["front_overlap"], field + ".front_overlap", 0.0, 0.95);
  if (j.contains("min_trigger_interval_s"))
    c.min_trigger_interval_s = positive(j["min_trigger_interval_s"], field + ".min_trigger_interval_s");
  if (j.contains("gimbal_pitch_deg"))
    c.gimbal_pitch_deg = in_range(j["gimbal_pitch_deg"], field + ".gimbal_pitch_deg", -90.0, 0.0);
  if (j.contains("capture")) {
    const json& cap = j["capture"];
    if (!cap.is_string() || (cap != "distance" && cap != "hover"))
      throw InputError(field + ".capture", "must be \"distance\" or \"hover\", got " + cap.dump());
    c.capture = cap.get<std::string>();
  }
  if (j.contains("image_size_mb"))
    c.image_size_mb = in_range(j["image_size_mb"], field + ".image_size_mb", 1e-3, 1e4);
  return c;
}

// The ground geometry of camera `c` at `field` (paper eq. 14, or QGroundControl's formulas).
CameraGeometry camera_geometry(const Camera& c, const std::string& field) {
  CameraGeometry g;
  if (c.hfov_deg) {
    const double t = std::tan(*c.hfov_deg * std::numbers::pi / 360.0);
    g.footprint_m = 2.0 * c.altitude_m * t;
    g.spacing_m = (2.0 - *c.overlap) * c.altitude_m * t;                // paper eq. 14
    if (c.image_width_px) g.gsd_m = g.footprint_m / *c.image_width_px;  // paper eq. 23: d / hRes
    g.along_track_footprint_m = c.vfov_deg
                                    ? 2.0 * c.altitude_m * std::tan(*c.vfov_deg * std::numbers::pi / 360.0)
                                    : g.footprint_m * kDefaultAspect;
  } else {
    g.gsd_m = c.altitude_m * *c.sensor_width_mm / (*c.focal_length_mm * *c.image_width_px);
    g.footprint_m = *c.image_width_px * *g.gsd_m;
    g.spacing_m = g.footprint_m * (1.0 - *c.side_overlap);
    // QGroundControl: image height * GSD, or the sensor height's ground extent
    if (c.image_height_px)
      g.along_track_footprint_m = *c.image_height_px * *g.gsd_m;
    else if (c.sensor_height_mm)
      g.along_track_footprint_m = c.altitude_m * *c.sensor_height_mm / *c.focal_length_mm;
    else
      g.along_track_footprint_m = g.footprint_m * kDefaultAspect;
  }
  g.trigger_distance_m = g.along_track_footprint_m * (1.0 - c.front_overlap);
  if (!(g.trigger_distance_m > 0) || !std::isfinite(g.trigger_distance_m))
    throw InputError(field + ".front_overlap", "gives a non-positive trigger distance");
  if (!(g.spacing_m > 0) || !std::isfinite(g.spacing_m))
    throw InputError(field, "gives a non-positive line spacing");
  return g;
}

}  // namespace uavcover::mission::detail
