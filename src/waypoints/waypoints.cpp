// Mission items with transition altitudes (Hong et al. 2021 §2.3): take-off straight to the UAV's own
// transition altitude, transit legs at it, coverage at mission altitude, climb back, return, RTL/land.
#include "waypoints/waypoints.hpp"

#include "waypoints/ardupilot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "geodesy/local_frame.hpp"
#include "photo/photo.hpp"
#include "terrain/terrain.hpp"
#include "uavcover/error.hpp"

namespace uavcover::waypoints {

std::size_t altitude_slots(const Plan& plan) {
  const auto& s = plan.separation;
  if (plan.mission.transition_altitudes == "layers" && s.is_object() && s.contains("layers"))
    return s.at("layers").get<std::size_t>();
  return plan.uavs.size();
}

std::size_t altitude_slot(const Plan& plan, std::size_t index) {
  const auto& s = plan.separation;
  if (plan.mission.transition_altitudes == "layers" && s.is_object() && s.contains("layer") &&
      index < s.at("layer").size())
    return s.at("layer").at(index).get<std::size_t>();
  return index;
}

double transition_altitude(const AltitudeOptions& opt, std::size_t index, double mission_altitude_m) {
  const double base =
      opt.transition_base_m > 0.0 ? opt.transition_base_m : std::max(60.0, mission_altitude_m + 20.0);
  return base + static_cast<double>(index) * opt.transition_step_m;
}

AltitudeOptions resolve_altitudes(const AltitudeOptions& opt, std::size_t uav_count,
                                  double mission_altitude_m, std::vector<std::string>* warnings) {
  AltitudeOptions r = opt;
  if (!std::isfinite(opt.transition_base_m) || opt.transition_base_m < 0)
    throw InputError("altitude.transition_base_m", "must be >= 0 (0 = automatic)");
  if (!std::isfinite(opt.transition_step_m) || opt.transition_step_m < 0)
    throw InputError("altitude.transition_step_m", "must be >= 0");
  if (!std::isfinite(opt.transition_ceiling_m) || opt.transition_ceiling_m < 0)
    throw InputError("altitude.transition_ceiling_m", "must be >= 0 (0 = no ceiling)");
  if (!std::isfinite(opt.min_vertical_separation_m) || opt.min_vertical_separation_m < 0)
    throw InputError("altitude.min_vertical_separation_m", "must be >= 0");
  r.transition_base_m = transition_altitude(opt, 0, mission_altitude_m);
  const double ceiling = opt.transition_ceiling_m;
  if (ceiling <= 0 || uav_count == 0) return r;
  const double base = r.transition_base_m;
  if (base > ceiling)
    throw InputError(
        "altitude.transition_ceiling_m",
        fmt::format("the first UAV's transition altitude {} m (mission altitude {} m) is above the {} "
                    "m ceiling: lower the mission altitude or the transition base, or raise the "
                    "ceiling",
                    base, mission_altitude_m, ceiling));
  const double n1 = static_cast<double>(uav_count - 1);
  const double top = base + n1 * opt.transition_step_m;
  if (top <= ceiling + 1e-9) return r;
  const double fit = (ceiling - base) / n1;  // the largest step that fits (uav_count >= 2 here)
  if (fit + 1e-9 < opt.min_vertical_separation_m)
    throw InputError(
        "altitude.transition_ceiling_m",
        fmt::format(
            "{} UAVs need transition altitudes {}..{} m but the ceiling is {} m, and fitting them under it "
            "would leave only {:.2f} m between UAVs (minimum vertical separation {} m): use fewer UAVs, a "
            "smaller transition step, a lower mission altitude or transition base, or a higher ceiling",
            uav_count, base, top, ceiling, fit, opt.min_vertical_separation_m));
  r.transition_step_m = std::floor(fit * 100.0) / 100.0;  // a round step, still under the ceiling
  if (r.transition_step_m < opt.min_vertical_separation_m) r.transition_step_m = fit;
  if (warnings != nullptr)
    warnings->push_back(
        fmt::format("transition altitudes {}..{} m would exceed the {} m ceiling: step compressed "
                    "from {} m to {} m ({}..{} m)",
                    base, top, ceiling, opt.transition_step_m, r.transition_step_m, base,
                    base + n1 * r.transition_step_m));
  return r;
}

namespace {

constexpr float kKeepHeading = std::numeric_limits<float>::quiet_NaN();

MissionItem position_item(std::uint16_t command, LonLat p, double alt, std::string role,
                          std::uint8_t frame = kFrameGlobalRelativeAlt) {
  MissionItem it;
  it.command = command;
  it.frame = frame;
  it.lat = p.lat;
  it.lon = p.lon;
  it.alt = static_cast<float>(alt);
  it.param4 = kKeepHeading;  // yaw: keep the vehicle's heading mode
  it.role = std::move(role);
  return it;
}

MissionItem command_item(std::uint16_t command, float p1, float p2, float p3, float p4, std::string role) {
  MissionItem it;
  it.command = command;
  it.frame = kFrameMission;
  it.param1 = p1;
  it.param2 = p2;
  it.param3 = p3;
  it.param4 = p4;
  it.role = std::move(role);
  return it;
}

bool same_place(LonLat a, LonLat b) {
  return std::abs(a.lat - b.lat) < 1e-9 && std::abs(a.lon - b.lon) < 1e-9;
}

/// A heading in [0, 360).
double wrap360(double deg) {
  const double h = std::fmod(deg, 360.0);
  return h < 0 ? h + 360.0 : (h >= 360.0 ? 0.0 : h);
}

/// The heading a fraction `t` of the way from `a` to `b`, turning the short way round.
double heading_between(double a, double b, double t) {
  double d = std::fmod(wrap360(b) - wrap360(a) + 540.0, 360.0) - 180.0;
  if (d == -180.0) d = 180.0;
  return wrap360(a + t * d);
}

}  // namespace

double flight_transit_altitude(const Plan& plan, const AltitudeOptions& resolved, std::size_t index) {
  const double rel = transition_altitude(resolved, altitude_slot(plan, index), plan.mission.altitude_m);
  const HeightGrid* ground = terrain::grid(plan.mission);
  return ground != nullptr ? ground->max_m + rel : rel;
}

namespace {

/// Climb and descent limits (issue 31, terrain.max_climb_mps / max_descent_mps): a leg whose ground
/// climbs or falls faster than the limit at cruise speed is flown slower, a MAV_CMD_DO_CHANGE_SPEED
/// before it and the cruise speed again after.
void slow_steep_legs(std::vector<MissionItem>& items, const Plan& plan, std::size_t index) {
  std::vector<SteepLeg> legs = steep_legs(plan, index, items);
  legs.erase(std::remove_if(legs.begin(), legs.end(),
                            [](const SteepLeg& s) { return !(s.speed_mps < s.cruise_mps); }),
             legs.end());
  if (legs.empty()) return;
  const double v = plan.mission.uavs.at(index).speed_mps;
  auto speed = [](double mps) {
    MissionItem it;
    it.command = kDoChangeSpeed;
    it.frame = kFrameMission;
    it.param1 = 1.0f;  // ground speed
    it.param2 = static_cast<float>(mps);
    it.param3 = -1.0f;
    it.param4 = 0.0f;
    it.role = "speed";
    return it;
  };
  std::map<std::size_t, double> slowed;  // item where a slowed leg starts -> its speed
  for (const auto& s : legs) slowed[s.from_item] = s.speed_mps;
  std::vector<MissionItem> out;
  out.reserve(items.size() + 2 * legs.size());
  double current = v;
  for (std::size_t k = 0; k < items.size(); ++k) {
    out.push_back(items[k]);
    const MissionItem& it = items[k];
    if (it.command != kNavWaypoint && it.command != kNavTakeoff) continue;
    // the speed of the leg that starts here: set when it differs from the one flown so far
    const auto f = slowed.find(k);
    const double want = f != slowed.end() ? f->second : v;
    if (want != current) {
      out.push_back(speed(want));
      current = want;
    }
  }
  items = std::move(out);
}

/// mission_items(), with CONDITION_YAW items for ArduPilot when `condition_yaw`; `own_parts`: the parts
/// flown, null for the UAV's own.
std::vector<MissionItem> make_items(const Plan& plan, std::size_t index,
                                    const std::vector<PathPart>* own_parts, const AltitudeOptions& options,
                                    bool condition_yaw) {
  if (index >= plan.uavs.size() || index >= plan.mission.uavs.size())
    throw std::out_of_range("mission_items: no UAV with index " + std::to_string(index));
  const std::vector<PathPart>& parts = own_parts != nullptr ? *own_parts : plan.uavs[index].parts;
  const AltitudeOptions opt = resolve_altitudes(options, altitude_slots(plan), plan.mission.altitude_m);
  const Uav& uav = plan.mission.uavs[index];
  const double mission_alt = plan.mission.altitude_m;
  const LonLat home = uav.start_resolved;
  // with a DEM (docs/photogrammetry.md): altitudes above mean sea level (MAV_FRAME_GLOBAL); transit at the
  // UAV's transition altitude above the highest ground of the mission's extent; coverage at the camera's
  // height above the ground under each waypoint (follow) or above the ground at take-off (off)
  const HeightGrid* ground = terrain::grid(plan.mission);
  const bool follow = ground != nullptr && plan.mission.terrain->follow();
  const double tolerance = follow ? plan.mission.terrain->tolerance_m : 0.0;
  const bool terrain_frame = follow && options.terrain_frame;
  const double home_ground = ground != nullptr ? ground->at(home) : 0.0;
  const std::uint8_t alt_frame = ground != nullptr ? kFrameGlobal : kFrameGlobalRelativeAlt;
  const double transit_alt = flight_transit_altitude(plan, opt, index);
  auto waypoint_at = [&](LonLat p, double alt, std::string role) {
    return position_item(kNavWaypoint, p, alt, std::move(role), alt_frame);
  };
  // heterogeneous cameras: a UAV with its own camera (uavs[i].camera) shoots with it
  const bool own = uav.camera.has_value() && uav.camera_geometry.has_value();
  const bool camera = own || (plan.mission.camera.has_value() && plan.mission.trigger_distance_m.has_value());
  const Camera* cam = own ? &*uav.camera : (camera ? &*plan.mission.camera : nullptr);
  const bool hover = camera && cam->capture == "hover";
  const double trigger =
      own ? uav.camera_geometry->trigger_distance_m : (camera ? *plan.mission.trigger_distance_m : 0.0);
  const geodesy::LocalFrame frame(plan.origin);

  std::vector<MissionItem> items;
  // take-off: climb straight to the transition altitude above home
  items.push_back(position_item(kNavTakeoff, home, transit_alt, "takeoff", alt_frame));
  // MAV_CMD_DO_CHANGE_SPEED: param1 1 = ground speed, param2 speed, param3 -1 = throttle unchanged
  items.push_back(
      command_item(kDoChangeSpeed, 1.0f, static_cast<float>(uav.speed_mps), -1.0f, 0.0f, "speed"));
  if (camera) {
    // MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW: param1 pitch, param2 yaw (0: ahead, follow mode), param3/4
    // rates 0 (the angles are given, so the rates are not used), param5 flags 0, param7 gimbal device 0
    // (all). Not NaN: ArduPilot refuses NaN in any param of this command (AP_Mission::sanity_check_params,
    // MAV_MISSION_INVALID_PARAM3; issue 34). PX4 >= 1.13 and ArduPilot >= 4.3 run it in missions; it
    // replaces the deprecated MAV_CMD_DO_MOUNT_CONTROL.
    items.push_back(command_item(kDoGimbalManagerPitchyaw, static_cast<float>(cam->gimbal_pitch_deg), 0.0f,
                                 0.0f, 0.0f, "gimbal"));
  }
  // MAV_CMD_IMAGE_START_CAPTURE: param1 camera 0 (all), param2 interval 0, param3 one image, param4 0
  auto capture = [&] { items.push_back(command_item(kImageStartCapture, 0.0f, 0.0f, 1.0f, 0.0f, "camera")); };
  // MAV_CMD_DO_SET_CAM_TRIGG_DIST: param1 distance (0 stops), param3 1 = one image now
  auto trigg = [&](double d) {
    items.push_back(command_item(kDoSetCamTriggDist, static_cast<float>(d), 0.0f, 1.0f, 0.0f, "camera"));
  };
  // The hold of hover-and-capture belongs to the waypoint where the UAV stops (NAV_WAYPOINT param1), never
  // to a command item: IMAGE_START_CAPTURE's param1 is the camera instance (issue 34).
  auto hold_at_last_waypoint = [&] {
    for (auto it = items.rbegin(); it != items.rend(); ++it)
      if (it->command == kNavWaypoint) {
        it->param1 = static_cast<float>(photo::kHoverHoldS);
        return;
      }
  };
  // A leg that starts where the previous shot leg ended, with nothing flown in between (a shared corner):
  // the previous leg's last image is this leg's first. The camera cannot take both (it refuses a trigger
  // while its shutter is held, ArduPilot's CAMx_DURATION), so the corner is shot once: the stop trigger
  // there takes no image (0, 0, 0) and the new leg's start takes it; in hover capture the corner's capture
  // is not repeated. Returns true when the corner is shared (photo::estimate() counts it once too).
  auto shared_corner = [&] {
    // the last camera item, and nothing but waypoints at the same position and height after it
    for (std::size_t k = items.size(); k-- > 0;) {
      const MissionItem& it = items[k];
      if (it.command == kDoSetCamTriggDist || it.command == kImageStartCapture) {
        if (it.command == kDoSetCamTriggDist && !(it.param1 == 0.0f && it.param3 > 0.0f)) return false;
        // the waypoint the image was taken at
        std::size_t w = k;
        while (w > 0 && items[w - 1].command != kNavWaypoint) --w;
        if (w == 0) return false;
        const MissionItem& at = items[w - 1];
        for (std::size_t j = k + 1; j < items.size(); ++j)
          if (items[j].command == kNavWaypoint &&
              (!same_place({items[j].lon, items[j].lat}, {at.lon, at.lat}) || items[j].alt != at.alt))
            return false;
        if (it.command == kDoSetCamTriggDist) items[k].param3 = 0.0f;  // the stop takes no image
        return true;
      }
      if (it.command != kNavWaypoint) return false;
    }
    return false;
  };

  // the gimbal pitch last commanded (the camera's, from the item above), for the parts' own pitches
  std::optional<double> gimbal;
  if (camera) gimbal = cam->gimbal_pitch_deg;
  bool high = true;  // at the transition altitude
  int waypoint = 0;  // coverage waypoints so far
  LonLat here = home;
  for (std::size_t pi = 0; pi < parts.size(); ++pi) {
    const PathPart& part = parts[pi];
    if (part.wgs84.empty()) continue;
    const std::size_t first_new = items.size();
    if (part.kind == PartKind::Transit) {
      if (!high) {  // climb on the spot before leaving the region
        items.push_back(waypoint_at(here, transit_alt, "transition"));
        high = true;
      }
      for (std::size_t k = 0; k < part.wgs84.size(); ++k) {
        if (k == 0 && same_place(part.wgs84[k], here)) continue;
        items.push_back(waypoint_at(part.wgs84[k], transit_alt, "transit"));
        here = part.wgs84[k];
      }
    } else {
      // the part's attitude (PathPart::attitude, docs/exports.md): its own height, heading per vertex,
      // gimbal pitch, region of interest and trigger distance; empty: the mission's
      const Attitude& att = part.attitude;
      const double part_alt = att.altitude_m ? *att.altitude_m : mission_alt;
      auto part_alt_at = [&](LonLat p) { return follow ? ground->at(p) + part_alt : home_ground + part_alt; };
      const double part_trigger = att.trigger_distance_m ? *att.trigger_distance_m : trigger;
      const bool headings = att.heading_deg.size() == part.wgs84.size();
      const bool yaw_items = headings && condition_yaw && !att.roi;
      // a waypoint of the part: NAV_WAYPOINT param4 = the heading (PX4); with condition_yaw a
      // CONDITION_YAW just before it (ArduCopter: run when the previous waypoint is reached, so the
      // vehicle turns on the way to this one; param2 0 = default rate, param3 0 = the short way, param4 0 =
      // absolute)
      auto part_waypoint = [&](LonLat p, std::optional<double> heading, std::string role) {
        if (heading && yaw_items)
          items.push_back(
              command_item(kConditionYaw, static_cast<float>(*heading), 0.0f, 0.0f, 0.0f, "heading"));
        items.push_back(waypoint_at(p, part_alt_at(p), std::move(role)));
        if (terrain_frame) {  // the height above the ground under it, which the vehicle keeps itself
          items.back().frame = kFrameGlobalTerrainAlt;
          items.back().alt = static_cast<float>(part_alt);
        }
        if (heading) items.back().param4 = static_cast<float>(*heading);
      };
      auto heading_at = [&](std::size_t k) -> std::optional<double> {
        if (!headings) return std::nullopt;
        return wrap360(att.heading_deg[k]);
      };
      const LonLat entry = part.wgs84.front();
      if (high && !same_place(entry, here)) {  // reach the point above the entry first
        items.push_back(waypoint_at(entry, transit_alt, "transit"));
        here = entry;
      }
      // the camera set for the part before its first waypoint (run when the point before it is reached):
      // MAV_CMD_DO_SET_ROI param1 3 = MAV_ROI_LOCATION at the ROI, at the part's height (a facade orbit
      // looks level at its centre); a gimbal pitch of its own (GIMBAL_MANAGER_PITCHYAW, as above)
      if (att.roi) {
        const LonLat r = frame.to_wgs84(*att.roi);
        MissionItem roi = position_item(kDoSetRoi, r, part_alt_at(r), "roi", alt_frame);
        roi.param1 = 3.0f;  // MAV_ROI_LOCATION
        roi.param4 = 0.0f;  // not NaN: ArduPilot refuses NaN outside NAV commands' param4
        items.push_back(roi);
      }
      if (att.gimbal_pitch_deg && (!gimbal || *gimbal != *att.gimbal_pitch_deg)) {
        items.push_back(command_item(kDoGimbalManagerPitchyaw, static_cast<float>(*att.gimbal_pitch_deg),
                                     0.0f, 0.0f, 0.0f, "gimbal"));
        gimbal = *att.gimbal_pitch_deg;
      }
      // the first coverage waypoint is the descent to mission altitude
      high = false;
      // a lead-in (issue 31, PathPart::lead_in) re-flies the stretch before the sortie's first waypoint
      // like coverage, without counting its vertices as coverage waypoints
      part_waypoint(entry, heading_at(0), part.lead_in > 0 ? "lead_in" : "coverage");
      if (part.lead_in == 0) items.back().waypoint = waypoint++;
      // photogrammetry (src/photo/photo.hpp): every leg shot on its own, nothing in turns or transit
      const bool local = part.local.size() == part.wgs84.size();
      for (std::size_t k = 1; k < part.wgs84.size(); ++k) {
        // a turn or turnaround with the camera off (docs/patterns.md) is flown, not shot
        const double leg_length = local ? std::hypot(part.local[k].x() - part.local[k - 1].x(),
                                                     part.local[k].y() - part.local[k - 1].y())
                                        : 0.0;
        const bool leg =
            camera && local && part.camera_on(k - 1) && photo::leg_images(leg_length, part_trigger) > 1;
        if (leg && !hover) {
          shared_corner();
          trigg(part_trigger);
        }
        // between the leg's ends: hover-and-capture stops and, following the terrain, the points where the
        // ground departs from the straight line by more than the tolerance, in order along the leg
        struct Stop {
          double s;
          Point p;
          bool capture;
        };
        std::vector<Stop> stops;
        if (leg && hover) {
          if (!shared_corner()) {  // hold at the leg's start and shoot (unless the corner was just shot)
            hold_at_last_waypoint();
            capture();
          }
          const std::vector<Point> shots = photo::leg_shots(part.local[k - 1], part.local[k], part_trigger);
          for (std::size_t s = 1; s + 1 < shots.size(); ++s)
            stops.push_back(
                {std::hypot(shots[s].x() - part.local[k - 1].x(), shots[s].y() - part.local[k - 1].y()),
                 shots[s], true});
        }
        if (follow && local && !terrain_frame) {
          const auto pts =
              terrain::follow_points(*ground, frame, part.local[k - 1], part.local[k], tolerance);
          for (std::size_t s = 1; s + 1 < pts.size(); ++s) stops.push_back({pts[s].s, pts[s].p, false});
        }
        std::stable_sort(stops.begin(), stops.end(), [](const Stop& a, const Stop& b) { return a.s < b.s; });
        for (const Stop& st : stops) {
          const LonLat g = frame.to_wgs84(st.p);
          // inside the leg: the heading turned the short way between its ends, in proportion
          std::optional<double> h;
          if (headings)
            h = heading_between(att.heading_deg[k - 1], att.heading_deg[k],
                                leg_length > 0 ? std::clamp(st.s / leg_length, 0.0, 1.0) : 0.0);
          part_waypoint(g, h, st.capture ? "capture" : "terrain");
          if (st.capture) {
            hold_at_last_waypoint();
            capture();
          }
        }
        part_waypoint(part.wgs84[k], heading_at(k), k < part.lead_in ? "lead_in" : "coverage");
        if (k >= part.lead_in) items.back().waypoint = waypoint++;
        if (leg && !hover) trigg(0.0);
        if (leg && hover) {
          hold_at_last_waypoint();
          capture();
        }
      }
      // the part's camera set back after its last waypoint: ROI off (DO_SET_ROI param1 0 = MAV_ROI_NONE at
      // no location, what ArduCopter's do_roi and PX4 read as "none"), the camera's own gimbal pitch
      if (att.roi) {
        MissionItem none = command_item(kDoSetRoi, 0.0f, 0.0f, 0.0f, 0.0f, "roi");
        none.frame = alt_frame;  // a global frame: ArduPilot stores DO_SET_ROI with a location
        items.push_back(none);
      }
      if (att.gimbal_pitch_deg && camera && *gimbal != cam->gimbal_pitch_deg) {
        items.push_back(command_item(kDoGimbalManagerPitchyaw, static_cast<float>(cam->gimbal_pitch_deg),
                                     0.0f, 0.0f, 0.0f, "gimbal"));
        gimbal = cam->gimbal_pitch_deg;
      }
      here = part.wgs84.back();
    }
    for (std::size_t k = first_new; k < items.size(); ++k)
      if (items[k].role == "transit" || in_coverage_leg(items[k])) items[k].part = static_cast<int>(pi);
  }
  if (!high) items.push_back(waypoint_at(here, transit_alt, "transition"));
  if (!same_place(here, home)) items.push_back(waypoint_at(home, transit_alt, "transit"));
  if (opt.land_instead_of_rtl) {
    items.push_back(position_item(kNavLand, home, home_ground, "land", alt_frame));
  } else {
    items.push_back(command_item(kNavReturnToLaunch, 0, 0, 0, 0, "rtl"));
  }
  if (follow && !terrain_frame) slow_steep_legs(items, plan, index);
  return items;
}

}  // namespace

std::vector<SteepLeg> steep_legs(const Plan& plan, std::size_t index, const std::vector<MissionItem>& items) {
  std::vector<SteepLeg> out;
  const auto& t = plan.mission.terrain;
  if (!t || !(t->max_climb_mps || t->max_descent_mps || t->max_grade)) return out;
  const double v = plan.mission.uavs.at(index).speed_mps;
  const geodesy::LocalFrame frame(plan.origin);
  auto in_leg = [](const MissionItem& it) { return it.command == kNavWaypoint && in_coverage_leg(it); };
  const MissionItem* prev = nullptr;
  std::size_t prev_k = 0;
  for (std::size_t k = 0; k < items.size(); ++k) {
    const MissionItem& it = items[k];
    if (!has_position(it)) continue;
    if (prev != nullptr && in_leg(*prev) && in_leg(it) && prev->part == it.part) {
      const Point a = frame.to_local({prev->lon, prev->lat}), b = frame.to_local({it.lon, it.lat});
      const double d = std::hypot(b.x() - a.x(), b.y() - a.y());
      const double dz = static_cast<double>(it.alt) - static_cast<double>(prev->alt);
      if (d > 1e-6 && std::fabs(dz) > 1e-6) {
        SteepLeg s{prev_k, k, {prev->lon, prev->lat}, {it.lon, it.lat}, d, dz, v, v, false};
        const double rate = std::fabs(dz) * v / d;  // m/s at cruise speed
        const std::optional<double> lim = dz > 0 ? t->max_climb_mps : t->max_descent_mps;
        if (lim && rate > *lim) s.speed_mps = std::max(0.1, *lim * d / std::fabs(dz));
        s.over_grade = t->max_grade && std::fabs(dz) / d > *t->max_grade;
        if (s.speed_mps < v || s.over_grade) out.push_back(s);
      }
    }
    prev = &it;
    prev_k = k;
  }
  return out;
}

std::string describe(const SteepLeg& s, const Plan& plan) {
  const auto& t = *plan.mission.terrain;
  std::string what;
  if (s.speed_mps < s.cruise_mps)
    what = fmt::format(
        "{} {:.1f} m over {:.1f} m, {:.2f} m/s at {:g} m/s, more than {} {:g} m/s: flown at "
        "{:.2f} m/s",
        s.dz_m > 0 ? "climbs" : "descends", std::fabs(s.dz_m), s.length_m,
        std::fabs(s.dz_m) * s.cruise_mps / s.length_m, s.cruise_mps,
        s.dz_m > 0 ? "max_climb_mps" : "max_descent_mps", s.dz_m > 0 ? *t.max_climb_mps : *t.max_descent_mps,
        s.speed_mps);
  if (s.over_grade)
    what += fmt::format(
        "{}a grade of {:.0f} %, more than max_grade {:.0f} %: the ground is too steep to follow "
        "at a constant height there",
        what.empty() ? "" : "; ", 100.0 * std::fabs(s.dz_m) / s.length_m, 100.0 * *t.max_grade);
  return fmt::format("the leg from ({:.6f}, {:.6f}) to ({:.6f}, {:.6f}) {}", s.from.lon, s.from.lat, s.to.lon,
                     s.to.lat, what);
}

std::vector<MissionItem> mission_items(const Plan& plan, std::size_t index, const AltitudeOptions& opt) {
  return make_items(plan, index, nullptr, opt, false);
}

std::vector<MissionItem> mission_items(const Plan& plan, std::size_t index,
                                       const std::vector<PathPart>& parts, const AltitudeOptions& opt) {
  return make_items(plan, index, &parts, opt, false);
}

std::vector<MissionItem> ardupilot_mission_items(const Plan& plan, std::size_t index,
                                                 const AltitudeOptions& opt) {
  return make_items(plan, index, nullptr, opt, true);
}

std::optional<LegProfile> leg_profile(const Plan& plan, std::size_t index, const AltitudeOptions& opt) {
  const HeightGrid* ground = terrain::grid(plan.mission);
  if (ground == nullptr || index >= plan.uavs.size()) return std::nullopt;
  const auto items = mission_items(plan, index, opt);
  const geodesy::LocalFrame frame(plan.origin);
  std::vector<const MissionItem*> wps;
  for (const auto& it : items)
    if (it.command == kNavWaypoint) wps.push_back(&it);
  std::optional<LegProfile> best;
  for (std::size_t i = 0; i < wps.size(); ++i) {
    if (wps[i]->role != "coverage") continue;
    // the leg: up to the next coverage waypoint of the same part, through terrain and capture points
    std::size_t j = i + 1;
    while (j < wps.size() && (wps[j]->role == "terrain" || wps[j]->role == "capture")) ++j;
    if (j >= wps.size() || wps[j]->role != "coverage" || wps[j]->part != wps[i]->part) continue;
    LegProfile lp;
    lp.uav = plan.uavs[index].id;
    lp.first_waypoint = wps[i]->waypoint;
    lp.altitude_m = plan.mission.altitude_m;
    lp.tolerance_m = plan.mission.terrain->follow() ? plan.mission.terrain->tolerance_m : 0.0;
    const Point a = frame.to_local({wps[i]->lon, wps[i]->lat});
    const Point b = frame.to_local({wps[j]->lon, wps[j]->lat});
    for (std::size_t k = i; k <= j; ++k) {
      const Point p = frame.to_local({wps[k]->lon, wps[k]->lat});
      lp.flight.emplace_back(std::hypot(p.x() - a.x(), p.y() - a.y()), static_cast<double>(wps[k]->alt));
      lp.terrain_waypoints += wps[k]->role == "terrain" ? 1 : 0;
    }
    for (const auto& s : terrain::profile(*ground, frame, a, b)) lp.ground.emplace_back(s.s, s.ground);
    lp.length_m = lp.flight.back().first;
    if (!best || lp.terrain_waypoints > best->terrain_waypoints ||
        (lp.terrain_waypoints == best->terrain_waypoints && lp.length_m > best->length_m))
      best = std::move(lp);
  }
  return best;
}

std::optional<PathProfile> path_profile(const Plan& plan, std::size_t index, std::size_t max_samples,
                                        const AltitudeOptions& opt) {
  const HeightGrid* ground = terrain::grid(plan.mission);
  if (ground == nullptr) return std::nullopt;
  const auto items = mission_items(plan, index, opt);
  const LonLat home = plan.mission.uavs.at(index).start_resolved;
  const double home_ground = ground->at(home);
  const geodesy::LocalFrame frame(plan.origin);
  struct Node {
    Point p;
    double alt;
    bool coverage;
  };
  std::vector<Node> nodes{{frame.to_local(home), home_ground, false}};
  for (const auto& it : items) {
    if (it.command == kNavReturnToLaunch) {
      nodes.push_back({frame.to_local(home), nodes.back().alt, false});
      nodes.push_back({frame.to_local(home), home_ground, false});
      continue;
    }
    if (!has_position(it)) continue;
    const bool cov = in_coverage_leg(it);
    const LonLat ll{it.lon, it.lat};
    double alt = it.alt;
    if (it.frame == kFrameGlobalRelativeAlt) alt += home_ground;
    if (it.frame == kFrameGlobalTerrainAlt) alt += ground->at(ll);
    nodes.push_back({frame.to_local(ll), alt, cov});
  }
  PathProfile out;
  out.uav = plan.uavs.at(index).id;
  out.altitude_m = plan.mission.altitude_m;
  out.tolerance_m =
      plan.mission.terrain && plan.mission.terrain->follow() ? plan.mission.terrain->tolerance_m : 0.0;
  std::vector<double> cum{0.0};
  for (std::size_t k = 1; k < nodes.size(); ++k)
    cum.push_back(cum.back() + bg::distance(nodes[k - 1].p, nodes[k].p));
  out.length_m = cum.back();
  const std::size_t n = std::max<std::size_t>(max_samples, 2);
  const double step = out.length_m > 0 ? out.length_m / static_cast<double>(n - 1) : 1.0;
  bool any = false;
  auto add = [&](double s, Point p, double flight, bool cov) {
    const double g = ground->at(frame.to_wgs84(p));
    out.samples.push_back({s, g, flight, cov});
    if (cov) {
      const double agl = flight - g;
      out.agl_min_m = any ? std::min(out.agl_min_m, agl) : agl;
      out.agl_max_m = any ? std::max(out.agl_max_m, agl) : agl;
      any = true;
    }
  };
  for (std::size_t k = 0; k + 1 < nodes.size(); ++k) {
    const Node& a = nodes[k];
    const Node& b = nodes[k + 1];
    const double len = cum[k + 1] - cum[k];
    const bool cov = a.coverage && b.coverage;
    add(cum[k], a.p, a.alt, cov && a.coverage);
    if (len <= 0) continue;
    for (double s = std::ceil(cum[k] / step) * step; s < cum[k + 1]; s += step) {
      if (s <= cum[k]) continue;
      const double t = (s - cum[k]) / len;
      add(s, Point(a.p.x() + t * (b.p.x() - a.p.x()), a.p.y() + t * (b.p.y() - a.p.y())),
          a.alt + t * (b.alt - a.alt), cov);
      if (out.samples.size() > 4 * n) break;  // bounded whatever the path
    }
  }
  add(out.length_m, nodes.back().p, nodes.back().alt, false);
  return out;
}

}  // namespace uavcover::waypoints
