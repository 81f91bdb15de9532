#include "export/export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "autopilot/fence.hpp"
#include "export/support.hpp"
#include "terrain/terrain.hpp"
#include "uavcover/error.hpp"
#include "uavcover/vehicle.hpp"
#include "waypoints/ardupilot.hpp"

namespace uavcover::exporting {

using namespace waypoints;  // the waypoint model the formats write
using autopilot::inclusion_fence;
using autopilot::kPx4MaxFenceVertices;
using nlohmann::json;

std::string export_autopilot(const Plan& plan, const ExportOptions& opt) {
  if (opt.autopilot.empty()) return plan.mission.autopilot.empty() ? "px4" : plan.mission.autopilot;
  if (vehicle_profile(opt.autopilot) != nullptr) return opt.autopilot;
  std::string shown = opt.autopilot.substr(0, 64);
  for (char& c : shown)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  throw InputError("autopilot", "expected one of " + vehicle_profile_names() + ", got '" + shown + "'");
}

int qgc_firmware_type(const Plan& plan, const ExportOptions& opt) {
  const std::string autopilot = export_autopilot(plan, opt);  // validated even when overridden
  if (opt.qgc_firmware_type >= 0) return opt.qgc_firmware_type;
  return autopilot == "ardupilot" ? 3 : 12;
}

namespace {
json rally_points(const Plan& plan, std::size_t index) {
  // QGC's RallyPointController: [lat, lon, alt] with the altitude relative to home, the height the
  // vehicle returns at (this UAV's transition altitude)
  json points = json::array();
  const double alt = plan.uavs.at(index).transition_altitude_m;
  for (const auto& p : plan.rally) points.push_back({p.lat, p.lon, alt});
  return points;
}
}  // namespace

json qgc_plan(const Plan& plan, std::size_t index, const ExportOptions& opt) {
  const int firmware = qgc_firmware_type(plan, opt);
  const auto items = items_of(plan, index, opt, opt.altitude);
  const Uav& uav = plan.mission.uavs.at(index);
  json jitems = json::array();
  int seq = 1;
  for (const auto& it : items) {
    json j;
    j["type"] = "SimpleItem";
    j["autoContinue"] = it.autocontinue;
    j["command"] = it.command;
    j["doJumpId"] = seq++;
    j["frame"] = it.frame;
    // DO_SET_ROI carries its location in params 5-7 too (QGC's ROI items specify a coordinate)
    if (has_position(it) || it.command == kDoSetRoi) {
      j["params"] = {jnum(it.param1), jnum(it.param2), jnum(it.param3), jnum(it.param4),
                     it.lat,          it.lon,          it.alt};
      j["Altitude"] = it.alt;
      // QGC AltMode: 2 absolute (AMSL), 4 terrain frame (MAV_FRAME_GLOBAL_TERRAIN_ALT), 1 relative
      j["AltitudeMode"] = it.frame == kFrameGlobal ? 2 : it.frame == kFrameGlobalTerrainAlt ? 4 : 1;
      j["AMSLAltAboveTerrain"] = nullptr;
    } else {
      j["params"] = {jnum(it.param1), jnum(it.param2), jnum(it.param3), jnum(it.param4), 0, 0, 0};
    }
    jitems.push_back(j);
  }
  const bool px4 = firmware == 12;
  const bool ardupilot = firmware == 3;
  if (px4 && uav.speed_mps > limits::kPx4DefaultMaxSpeed)
    warn(opt,
         fmt::format("uav '{}': speed {} m/s is above PX4's default MPC_XY_VEL_MAX ({} m/s), which caps it",
                     uav.id, uav.speed_mps, limits::kPx4DefaultMaxSpeed));
  if (ardupilot && uav.speed_mps > limits::kArduPilotMaxSpeed)
    warn(opt, fmt::format("uav '{}': speed {} m/s is above ArduPilot's WPNAV_SPEED range (at most {} m/s)",
                          uav.id, uav.speed_mps, limits::kArduPilotMaxSpeed));
  const LonLat home = uav.start_resolved;
  // geofence: one convex inclusion polygon around everything flown (area, home, take-off, transit and
  // coverage waypoints, with a margin), the no-fly zones as exclusions; [lat, lon] vertices, not closed
  json polygons = json::array();
  auto fence = [&](const GeoRing& ring, bool inclusion) {
    json pts = json::array();
    std::size_t n = ring.size();
    if (n >= 2 && ring.front().lat == ring.back().lat && ring.front().lon == ring.back().lon) --n;
    if (n < 3) return std::size_t{0};
    for (std::size_t k = 0; k < n; ++k) pts.push_back({ring[k].lat, ring[k].lon});
    polygons.push_back({{"inclusion", inclusion}, {"polygon", pts}, {"version", 1}});
    return n;
  };
  std::size_t vertices = fence(inclusion_fence(plan, index, items, opt.geofence_margin_m), true);
  for (const auto& poly : plan.mission.no_fly_zones)
    if (!poly.empty()) vertices += fence(poly.front(), false);
  if (px4 && vertices > kPx4MaxFenceVertices)
    warn(opt, fmt::format("uav '{}': the geofence has {} vertices, PX4 stores at most {}", uav.id, vertices,
                          kPx4MaxFenceVertices));
  return {{"fileType", "Plan"},
          {"version", 1},
          {"groundStation", "QGroundControl"},
          {"mission",
           {{"version", 2},
            {"firmwareType", firmware},
            {"vehicleType", opt.qgc_vehicle_type},
            // 0 mixed: the terrain frame's items beside AMSL take-off and transit (each item says)
            {"globalPlanAltitudeMode", opt.altitude.terrain_frame               ? 0
                                       : terrain::grid(plan.mission) != nullptr ? 2
                                                                                : 1},
            {"cruiseSpeed", uav.speed_mps},
            {"hoverSpeed", uav.speed_mps},
            {"plannedHomePosition", {home.lat, home.lon, terrain::home_ground(plan.mission, index)}},
            {"items", jitems}}},
          {"geoFence", {{"version", 2}, {"circles", json::array()}, {"polygons", polygons}}},
          {"rallyPoints", {{"version", 2}, {"points", rally_points(plan, index)}}}};
}

}  // namespace uavcover::exporting
