#include "export/support.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "photo/photo.hpp"
#include "terrain/terrain.hpp"
#include "uavcover/error.hpp"
#include "waypoints/ardupilot.hpp"

namespace uavcover::exporting {

using namespace waypoints;  // the waypoint model the formats write
using nlohmann::json;

std::vector<MissionItem> items_of(const Plan& plan, std::size_t index, const ExportOptions& opt,
                                  const AltitudeOptions& altitudes) {
  if (opt.items != nullptr) return *opt.items;
  return mission_items(plan, index, altitudes);
}

/// Positioned items a waypoint-only format (DJI, Litchi) flies: everything but take-off and landing.
std::vector<const MissionItem*> flown_waypoints(const std::vector<MissionItem>& items) {
  std::vector<const MissionItem*> out;
  for (const auto& it : items)
    if (it.command == kNavWaypoint) out.push_back(&it);
  return out;
}

std::vector<CameraAt> camera_actions(const std::vector<MissionItem>& items) {
  std::vector<CameraAt> out;
  std::size_t open = 0;  // the waypoint whose leg is being shot, + 1 (0 = none)
  for (const auto& it : items) {
    if (it.command == kNavWaypoint) {
      out.push_back({});
      out.back().hold_s = it.param1;
      continue;
    }
    if (out.empty()) continue;
    if (it.command == kDoSetCamTriggDist) {
      if (it.param1 > 0) {
        out.back().leg_trigger_m = it.param1;  // its immediate image is the distance shooting's first
        open = out.size();
      } else {
        if (it.param3 > 0) ++out.back().photos;
        if (open > 0) {
          out[open - 1].leg_end = out.size() - 1;
          for (std::size_t k = open; k + 1 < out.size(); ++k)
            out[k].inside_leg_m = out[open - 1].leg_trigger_m;
        }
        open = 0;
      }
    } else if (it.command == kImageStartCapture) {
      ++out.back().photos;
    }
  }
  return out;
}

double degrees(double v) { return std::round(v * 1000.0) / 1000.0 + 0.0; }

std::vector<AttitudeAt> attitude_actions(const std::vector<MissionItem>& items) {
  std::vector<AttitudeAt> out;
  AttitudeAt now;  // what holds after the items so far
  for (const auto& it : items) {
    if (it.command == kNavWaypoint) {
      now.heading_deg = it.param4;
      now.gimbal_changed = false;
      out.push_back(now);
      continue;
    }
    if (it.command == kDoGimbalManagerPitchyaw) {
      now.gimbal_pitch_deg = it.param1;
      now.gimbal_changed = true;
    } else if (it.command == kDoSetRoi) {
      now.roi = it.param1 == 3.0f;  // MAV_ROI_LOCATION; MAV_ROI_NONE (0) switches it off
      now.roi_lat = now.roi ? it.lat : 0.0;
      now.roi_lon = now.roi ? it.lon : 0.0;
      now.roi_alt = now.roi ? static_cast<double>(it.alt) : 0.0;
    } else {
      continue;
    }
    if (!out.empty()) {  // the change happens when the last waypoint is reached
      const double h = out.back().heading_deg;
      out.back() = now;
      out.back().heading_deg = h;
    }
  }
  return out;
}

/// Shortest round-trip text of a number; NaN as "NaN" (how Mission Planner and pymavlink read it).
std::string num(double v) { return std::isnan(v) ? std::string("NaN") : fmt::format("{}", v); }
std::string coord(double v) { return fmt::format("{:.9f}", v); }
/// A JSON number, or null for NaN (QGroundControl's own convention, e.g. yaw "keep heading").
json jnum(double v) { return std::isnan(v) ? json(nullptr) : json(v); }
/// JSON text; invalid UTF-8 in names (a tampered plan) is replaced rather than thrown on.
std::string dump(const json& doc, int indent) {
  return doc.dump(indent, ' ', false, json::error_handler_t::replace) + "\n";
}

void warn(const ExportOptions& opt, std::string message) {
  if (opt.warnings != nullptr) opt.warnings->push_back(std::move(message));
}

/// The UAV's speed within a consumer's maximum: clamped with a warning.
double speed_within(const Plan& plan, std::size_t index, double max_mps, const char* consumer,
                    const ExportOptions& opt) {
  const double v = plan.mission.uavs.at(index).speed_mps;
  if (v <= max_mps) return v;
  warn(opt, fmt::format("uav '{}': speed {} m/s clamped to {} m/s, the most {} accepts",
                        plan.uavs.at(index).id, v, max_mps, consumer));
  return max_mps;
}

/// The items with heights above take-off, for the consumers that take those (DJI WPML relativeToStartPoint,
/// Litchi altitudemode 0): with a DEM, the AMSL altitudes minus the DEM's ground at take-off.
std::vector<MissionItem> above_takeoff(const Plan& plan, std::size_t index, std::vector<MissionItem> items) {
  const double g = terrain::home_ground(plan.mission, index);
  for (auto& it : items)
    if (it.frame == kFrameGlobal) {
      it.alt = static_cast<float>(static_cast<double>(it.alt) - g);
      it.frame = kFrameGlobalRelativeAlt;
    }
  return items;
}

/// Refuses waypoint heights above a consumer's maximum (clamping an altitude would break separation).
void check_heights(const Plan& plan, std::size_t index, const std::vector<const MissionItem*>& wps,
                   double max_m, const char* consumer) {
  for (const MissionItem* w : wps)
    if (static_cast<double>(w->alt) > max_m)
      throw InputError("altitude",
                       fmt::format("uav '{}': waypoint at {} m above take-off, {} accepts at most {} "
                                   "m: lower the mission altitude or the transition altitudes",
                                   plan.uavs.at(index).id, num(w->alt), consumer, max_m));
}

/// The gimbal pitch of the camera UAV `index` carries: its own (uavs[i].camera), else the mission's.
double gimbal_pitch_of(const Plan& plan, std::size_t index) {
  const Uav* u = index < plan.mission.uavs.size() ? &plan.mission.uavs[index] : nullptr;
  return u != nullptr && u->camera ? u->camera->gimbal_pitch_deg : plan.mission.camera->gimbal_pitch_deg;
}

}  // namespace uavcover::exporting
