// Mission items with transition altitudes (Hong et al. 2021 §2.3): take-off straight to the UAV's own
// transition altitude, transit legs at it, coverage at mission altitude, climb back, return, RTL/land.
#include "waypoints/waypoints.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
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

}  // namespace

double flight_transit_altitude(const Plan& plan, const AltitudeOptions& resolved, std::size_t index) {
  const double rel = transition_altitude(resolved, altitude_slot(plan, index), plan.mission.altitude_m);
  const HeightGrid* ground = terrain::grid(plan.mission);
  return ground != nullptr ? ground->max_m + rel : rel;
}

std::vector<MissionItem> mission_items(const Plan& plan, std::size_t index, const AltitudeOptions& options) {
  if (index >= plan.uavs.size() || index >= plan.mission.uavs.size())
    throw std::out_of_range("mission_items: no UAV with index " + std::to_string(index));
  const AltitudeOptions opt = resolve_altitudes(options, altitude_slots(plan), plan.mission.altitude_m);
  const UavPlan& up = plan.uavs[index];
  const Uav& uav = plan.mission.uavs[index];
  const double mission_alt = plan.mission.altitude_m;
  const LonLat home = uav.start_resolved;
  // with a DEM (docs/photogrammetry.md): altitudes above mean sea level (MAV_FRAME_GLOBAL); transit at the
  // UAV's transition altitude above the highest ground of the mission's extent; coverage at the camera's
  // height above the ground under each waypoint (follow) or above the ground at take-off (off)
  const HeightGrid* ground = terrain::grid(plan.mission);
  const bool follow = ground != nullptr && plan.mission.terrain->follow();
  const double tolerance = follow ? plan.mission.terrain->tolerance_m : 0.0;
  const double home_ground = ground != nullptr ? ground->at(home) : 0.0;
  const std::uint8_t alt_frame = ground != nullptr ? kFrameGlobal : kFrameGlobalRelativeAlt;
  const double transit_alt = flight_transit_altitude(plan, opt, index);
  auto cover_alt = [&](LonLat p) { return follow ? ground->at(p) + mission_alt : home_ground + mission_alt; };
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

  bool high = true;  // at the transition altitude
  int waypoint = 0;  // coverage waypoints so far
  LonLat here = home;
  for (std::size_t pi = 0; pi < up.parts.size(); ++pi) {
    const PathPart& part = up.parts[pi];
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
      const LonLat entry = part.wgs84.front();
      if (high && !same_place(entry, here)) {  // reach the point above the entry first
        items.push_back(waypoint_at(entry, transit_alt, "transit"));
        here = entry;
      }
      // the first coverage waypoint is the descent to mission altitude
      high = false;
      items.push_back(waypoint_at(entry, cover_alt(entry), "coverage"));
      items.back().waypoint = waypoint++;
      // photogrammetry (src/photo/photo.hpp): every leg shot on its own, nothing in turns or transit
      const bool local = part.local.size() == part.wgs84.size();
      for (std::size_t k = 1; k < part.wgs84.size(); ++k) {
        // a turn or turnaround with the camera off (docs/patterns.md) is flown, not shot
        const bool leg = camera && local && part.camera_on(k - 1) &&
                         photo::leg_images(std::hypot(part.local[k].x() - part.local[k - 1].x(),
                                                      part.local[k].y() - part.local[k - 1].y()),
                                           trigger) > 1;
        if (leg && !hover) {
          shared_corner();
          trigg(trigger);
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
          const std::vector<Point> shots = photo::leg_shots(part.local[k - 1], part.local[k], trigger);
          for (std::size_t s = 1; s + 1 < shots.size(); ++s)
            stops.push_back(
                {std::hypot(shots[s].x() - part.local[k - 1].x(), shots[s].y() - part.local[k - 1].y()),
                 shots[s], true});
        }
        if (follow && local) {
          const auto pts =
              terrain::follow_points(*ground, frame, part.local[k - 1], part.local[k], tolerance);
          for (std::size_t s = 1; s + 1 < pts.size(); ++s) stops.push_back({pts[s].s, pts[s].p, false});
        }
        std::stable_sort(stops.begin(), stops.end(), [](const Stop& a, const Stop& b) { return a.s < b.s; });
        for (const Stop& st : stops) {
          const LonLat g = frame.to_wgs84(st.p);
          items.push_back(waypoint_at(g, cover_alt(g), st.capture ? "capture" : "terrain"));
          if (st.capture) {
            hold_at_last_waypoint();
            capture();
          }
        }
        items.push_back(waypoint_at(part.wgs84[k], cover_alt(part.wgs84[k]), "coverage"));
        items.back().waypoint = waypoint++;
        if (leg && !hover) trigg(0.0);
        if (leg && hover) {
          hold_at_last_waypoint();
          capture();
        }
      }
      here = part.wgs84.back();
    }
    for (std::size_t k = first_new; k < items.size(); ++k)
      if (items[k].role == "transit" || items[k].role == "coverage" || items[k].role == "capture" ||
          items[k].role == "terrain")
        items[k].part = static_cast<int>(pi);
  }
  if (!high) items.push_back(waypoint_at(here, transit_alt, "transition"));
  if (!same_place(here, home)) items.push_back(waypoint_at(home, transit_alt, "transit"));
  if (opt.land_instead_of_rtl) {
    items.push_back(position_item(kNavLand, home, home_ground, "land", alt_frame));
  } else {
    items.push_back(command_item(kNavReturnToLaunch, 0, 0, 0, 0, "rtl"));
  }
  return items;
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

}  // namespace uavcover::waypoints
