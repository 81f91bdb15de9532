#include "export/export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "export/support.hpp"
#include "uavcover/error.hpp"

namespace uavcover::exporting {

using namespace waypoints;  // the waypoint model the formats write
using nlohmann::json;

std::vector<std::string> litchi_csv(const Plan& plan, std::size_t index, const ExportOptions& opt) {
  const auto items = above_takeoff(plan, index, items_of(plan, index, opt, opt.altitude));
  const auto wps = flown_waypoints(items);
  check_heights(plan, index, wps, limits::kLitchiMaxAltitude, "Litchi");
  const double speed = speed_within(plan, index, limits::kLitchiMaxSpeed, "Litchi", opt);
  const bool camera = plan.mission.camera.has_value() && plan.mission.trigger_distance_m.has_value();
  const std::vector<CameraAt> shots = camera_actions(items);
  const double pitch = camera ? gimbal_pitch_of(plan, index) : -90.0;
  std::string header =
      "latitude,longitude,altitude(m),heading(deg),curvesize(m),rotationdir,gimbalmode,gimbalpitchangle";
  for (int k = 1; k <= 15; ++k) header += fmt::format(",actiontype{},actionparam{}", k, k);
  header +=
      ",altitudemode,speed(m/"
      "s),poi_latitude,poi_longitude,poi_altitude(m),poi_altitudemode,photo_timeinterval,"
      "photo_distinterval\n";
  // Litchi actions: type 0 = stay (ms), 1 = take photo; photo_distinterval shoots every so many metres on
  // the way to the next waypoint (a leg's distance capture); altitude relative to take-off (altitudemode 0)
  // the parts' attitude (PathPart::attitude through the items): heading(deg) at the waypoint (0..360),
  // gimbalpitchangle the pitch held there (gimbalmode 2: interpolated between waypoints), and while a
  // region of interest holds the POI columns with gimbalmode 1 (focus POI: Litchi aims the gimbal at it)
  const std::vector<AttitudeAt> att = attitude_actions(items);
  std::vector<double> held(wps.size(), pitch);  // the gimbal pitch when the UAV reaches each waypoint
  for (std::size_t k = 0; k < wps.size(); ++k) {
    held[k] = k == 0 ? pitch : held[k - 1];
    if (k > 0 && k - 1 < att.size() && att[k - 1].gimbal_changed)
      held[k] = degrees(att[k - 1].gimbal_pitch_deg);
  }
  auto row = [&](std::size_t k) {
    const MissionItem& w = *wps[k];
    const AttitudeAt a = k < att.size() ? att[k] : AttitudeAt{};
    std::string heading = "0";
    if (!std::isnan(a.heading_deg)) {
      const double h = degrees(std::fmod(std::fmod(a.heading_deg, 360.0) + 360.0, 360.0));
      heading = num(h >= 360.0 ? 0.0 : h);
    }
    std::string out = fmt::format("{:.8f},{:.8f},{},{},0,0,{},{}", w.lat, w.lon, num(w.alt), heading,
                                  a.roi ? 1 : 2, num(held[k]));
    const CameraAt c = camera && k < shots.size() ? shots[k] : CameraAt{};
    int actions = 0;
    if (c.photos > 0 && c.hold_s > 0) {
      out += fmt::format(",0,{}", static_cast<int>(std::lround(c.hold_s * 1000)));
      ++actions;
    }
    for (int p = 0; p < c.photos && actions < 15; ++p, ++actions) out += ",1,0";
    for (; actions < 15; ++actions) out += ",-1,0";
    const std::string poi =
        a.roi ? fmt::format("{:.8f},{:.8f},{},0", a.roi_lat, a.roi_lon, num(degrees(a.roi_alt))) : "0,0,0,0";
    out += fmt::format(",0,{},{},-1,{}\n", num(speed), poi,
                       c.leg_trigger_m > 0  ? num(c.leg_trigger_m)
                       : c.inside_leg_m > 0 ? num(c.inside_leg_m)
                                            : "-1");
    return out;
  };
  // missions of at most 99 waypoints; each next one starts where the previous one ended
  std::vector<std::string> missions;
  const std::size_t max = limits::kLitchiMaxWaypoints;
  for (std::size_t start = 0; start < wps.size();) {
    const std::size_t end = std::min(wps.size(), start + max);
    std::string text = header;
    for (std::size_t k = start; k < end; ++k) text += row(k);
    missions.push_back(std::move(text));
    if (end == wps.size()) break;
    start = end - 1;
  }
  if (missions.empty()) missions.push_back(header);
  if (missions.size() > 1)
    warn(opt, fmt::format(
                  "uav '{}': {} Litchi waypoints, more than the {} one Litchi mission holds: split into {} "
                  "missions flown one after the other",
                  plan.uavs.at(index).id, wps.size(), max, missions.size()));
  return missions;
}

}  // namespace uavcover::exporting
