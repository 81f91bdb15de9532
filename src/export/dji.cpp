#include "export/export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "export/support.hpp"
#include "export/xml.hpp"
#include "photo/photo.hpp"
#include "terrain/terrain.hpp"
#include "uavcover/error.hpp"

namespace uavcover::exporting {

using namespace waypoints;  // the waypoint model the formats write
using nlohmann::json;

namespace {

/// wpml:payloadEnumValue of the camera a DJI drone comes with (DJI WPML common elements), -1 if none.
int builtin_payload(int drone, int sub) {
  switch (drone) {
    case 67:  // M30 / M30T
      return sub == 1 ? 53 : 52;
    case 77:  // Mavic 3 Enterprise: M3E, M3T, M3M
      return sub == 1 ? 67 : sub == 2 ? 68 : 66;
    case 91:  // Matrice 3D / 3TD
      return sub == 1 ? 81 : 80;
    default:
      return -1;
  }
}

/// wpml:payloadLensIndex for the photos: the wide camera, plus the thermal one on T payloads.
const char* lens_index(int payload) {
  return payload == 53 || payload == 67 || payload == 81 ? "wide,ir" : "wide";
}

/// A file-name-safe suffix for the photos (wpml:fileSuffix): the id's letters, digits, '-' and '_'.
std::string file_suffix(const std::string& id) {
  std::string out;
  for (char c : id)
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') out += c;
  return out.empty() ? "uavcover" : out;
}

}  // namespace

std::map<std::string, std::string> dji_wpml(const Plan& plan, std::size_t index, const ExportOptions& opt) {
  const AltitudeOptions altitudes =
      resolve_altitudes(opt.altitude, altitude_slots(plan), plan.mission.altitude_m);
  const auto items = above_takeoff(plan, index, items_of(plan, index, opt, altitudes));
  const auto wps = flown_waypoints(items);
  const UavPlan& up = plan.uavs.at(index);
  check_heights(plan, index, wps, limits::kDjiMaxHeight, "DJI WPML");
  const double speed = speed_within(plan, index, limits::kDjiMaxSpeed, "DJI WPML", opt);
  const bool camera = plan.mission.camera.has_value() && plan.mission.trigger_distance_m.has_value();
  const double transit_alt =
      flight_transit_altitude(plan, altitudes, index) - terrain::home_ground(plan.mission, index);
  const int payload = opt.dji_payload_enum >= 0 ? opt.dji_payload_enum
                                                : builtin_payload(opt.dji_drone_enum, opt.dji_drone_sub_enum);
  if (payload < 0)
    throw InputError("dji_payload_enum", fmt::format("drone {} has no known built-in camera: give its "
                                                     "wpml:payloadEnumValue",
                                                     opt.dji_drone_enum));
  // safe take-off height and RTH height: the UAV's transition altitude, within WPML's [1.2, 1500] m
  const double safe_height = std::clamp(transit_alt, 1.2, 1500.0);

  const std::string header =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<kml xmlns=\"http://www.opengis.net/kml/2.2\" xmlns:wpml=\"http://www.dji.com/wpmz/1.0.2\">\n  "
      "<Document>\n";
  const std::string mission_config = fmt::format(
      "    <wpml:missionConfig>\n"
      "      <wpml:flyToWaylineMode>safely</wpml:flyToWaylineMode>\n"
      "      <wpml:finishAction>{}</wpml:finishAction>\n"
      "      <wpml:exitOnRCLost>executeLostAction</wpml:exitOnRCLost>\n"
      "      <wpml:executeRCLostAction>goBack</wpml:executeRCLostAction>\n"
      "      <wpml:takeOffSecurityHeight>{}</wpml:takeOffSecurityHeight>\n"
      "      <wpml:globalTransitionalSpeed>{}</wpml:globalTransitionalSpeed>\n"
      "      <wpml:globalRTHHeight>{}</wpml:globalRTHHeight>\n"
      "      <wpml:droneInfo>\n"
      "        <wpml:droneEnumValue>{}</wpml:droneEnumValue>\n"
      "        <wpml:droneSubEnumValue>{}</wpml:droneSubEnumValue>\n"
      "      </wpml:droneInfo>\n"
      "      <wpml:payloadInfo>\n"
      "        <wpml:payloadEnumValue>{}</wpml:payloadEnumValue>\n"
      "        <wpml:payloadPositionIndex>0</wpml:payloadPositionIndex>\n"
      "      </wpml:payloadInfo>\n"
      "    </wpml:missionConfig>\n",
      altitudes.land_instead_of_rtl ? "autoLand" : "goHome", num(safe_height), num(speed), num(safe_height),
      opt.dji_drone_enum, opt.dji_drone_sub_enum, payload);

  // camera (src/photo/photo.hpp): every coverage leg is its own action group shooting every trigger
  // distance from its start (multipleDistance over [k, k+1]); single photos (leg ends, hover-and-capture
  // stops) are reachPoint groups at their waypoint, after a hover when the capture is "hover"
  const std::string suffix = xml_escape(file_suffix(up.id));
  const std::vector<CameraAt> shots = camera_actions(items);
  const std::string take_photo = fmt::format(
      "            <wpml:actionActuatorFunc>takePhoto</wpml:actionActuatorFunc>\n"
      "            <wpml:actionActuatorFuncParam>\n"
      "              <wpml:payloadPositionIndex>0</wpml:payloadPositionIndex>\n"
      "              <wpml:fileSuffix>{}</wpml:fileSuffix>\n"
      "              <wpml:payloadLensIndex>{}</wpml:payloadLensIndex>\n"
      "              <wpml:useGlobalPayloadLensIndex>0</wpml:useGlobalPayloadLensIndex>\n"
      "            </wpml:actionActuatorFuncParam>\n",
      suffix, lens_index(payload));
  auto action = [](int id, const std::string& body) {
    return fmt::format(
        "          <wpml:action>\n            <wpml:actionId>{}</wpml:actionId>\n{}"
        "          </wpml:action>\n",
        id, body);
  };
  auto action_group = [&](std::size_t start, std::size_t end, int id, const std::string& trigger,
                          const std::string& actions) {
    return fmt::format(
        "        <wpml:actionGroup>\n"
        "          <wpml:actionGroupId>{}</wpml:actionGroupId>\n"
        "          <wpml:actionGroupStartIndex>{}</wpml:actionGroupStartIndex>\n"
        "          <wpml:actionGroupEndIndex>{}</wpml:actionGroupEndIndex>\n"
        "          <wpml:actionGroupMode>sequence</wpml:actionGroupMode>\n"
        "          <wpml:actionTrigger>\n{}"
        "          </wpml:actionTrigger>\n{}"
        "        </wpml:actionGroup>\n",
        id, start, end, trigger, actions);
  };
  auto groups_at = [&](std::size_t k, int& group) {
    std::string out;
    if (!camera || k >= shots.size()) return out;
    const CameraAt& c = shots[k];
    if (c.photos > 0) {
      std::string acts;
      int id = 0;
      if (c.hold_s > 0)
        acts +=
            action(id++, fmt::format("            <wpml:actionActuatorFunc>hover</wpml:actionActuatorFunc>\n"
                                     "            <wpml:actionActuatorFuncParam>\n"
                                     "              <wpml:hoverTime>{}</wpml:hoverTime>\n"
                                     "            </wpml:actionActuatorFuncParam>\n",
                                     num(c.hold_s)));
      for (int p = 0; p < c.photos; ++p) acts += action(id++, take_photo);
      out += action_group(k, k, group++,
                          "            <wpml:actionTriggerType>reachPoint</wpml:actionTriggerType>\n", acts);
    }
    if (c.leg_trigger_m > 0 && k + 1 < wps.size())
      out += action_group(
          k, std::max(k + 1, c.leg_end), group++,
          fmt::format("            <wpml:actionTriggerType>multipleDistance</wpml:actionTriggerType>\n"
                      "            <wpml:actionTriggerParam>{}</wpml:actionTriggerParam>\n",
                      num(c.leg_trigger_m)),
          action(0, take_photo));
    return out;
  };
  const double pitch = camera ? gimbal_pitch_of(plan, index) : -90.0;
  // the parts' attitude (PathPart::attitude through the items): a heading per waypoint (smoothTransition:
  // the heading at the waypoint, turned evenly to the next one's; WPML's waypointHeadingAngle is in
  // [-180, 180]), towardPOI while a region of interest holds, a gimbalRotate action where the pitch changes
  const std::vector<AttitudeAt> att = attitude_actions(items);
  auto heading_param = [&](std::size_t k, const char* indent) -> std::string {
    const AttitudeAt a = k < att.size() ? att[k] : AttitudeAt{};
    if (a.roi)
      return fmt::format(
          "{0}<wpml:waypointHeadingParam>\n"
          "{0}  <wpml:waypointHeadingMode>towardPOI</wpml:waypointHeadingMode>\n"
          "{0}  <wpml:waypointHeadingAngle>0</wpml:waypointHeadingAngle>\n"
          "{0}  <wpml:waypointPoiPoint>{1},{2},{3}</wpml:waypointPoiPoint>\n"
          "{0}  <wpml:waypointHeadingPathMode>followBadArc</wpml:waypointHeadingPathMode>\n"
          "{0}</wpml:waypointHeadingParam>\n",
          indent, coord(a.roi_lat), coord(a.roi_lon), num(a.roi_alt));
    if (!std::isnan(a.heading_deg))
      return fmt::format(
          "{0}<wpml:waypointHeadingParam>\n"
          "{0}  <wpml:waypointHeadingMode>smoothTransition</wpml:waypointHeadingMode>\n"
          "{0}  <wpml:waypointHeadingAngle>{1}</wpml:waypointHeadingAngle>\n"
          "{0}  <wpml:waypointHeadingPathMode>followBadArc</wpml:waypointHeadingPathMode>\n"
          "{0}</wpml:waypointHeadingParam>\n",
          indent, num(degrees(std::remainder(a.heading_deg, 360.0))));
    return fmt::format(
        "{0}<wpml:waypointHeadingParam>\n"
        "{0}  <wpml:waypointHeadingMode>followWayline</wpml:waypointHeadingMode>\n"
        "{0}  <wpml:waypointHeadingPathMode>followBadArc</wpml:waypointHeadingPathMode>\n"
        "{0}</wpml:waypointHeadingParam>\n",
        indent);
  };
  auto own_heading = [&](std::size_t k) {
    return k < att.size() && (att[k].roi || !std::isnan(att[k].heading_deg));
  };
  // the pitch the camera has when the UAV reaches waypoint k (template.kml's gimbalPitchAngle)
  auto pitch_at = [&](std::size_t k) {
    for (std::size_t j = std::min(k, att.size()); j-- > 0;)
      if (att[j].gimbal_changed) return degrees(att[j].gimbal_pitch_deg);
    return pitch;
  };
  auto gimbal_group = [&](std::size_t k, int& group) {
    std::string out;
    if (k >= att.size() || !att[k].gimbal_changed) return out;
    return action_group(
        k, k, group++, "            <wpml:actionTriggerType>reachPoint</wpml:actionTriggerType>\n",
        action(0,
               fmt::format("            <wpml:actionActuatorFunc>gimbalRotate</wpml:actionActuatorFunc>\n"
                           "            <wpml:actionActuatorFuncParam>\n"
                           "              <wpml:gimbalHeadingYawBase>aircraft</wpml:gimbalHeadingYawBase>\n"
                           "              <wpml:gimbalRotateMode>absoluteAngle</wpml:gimbalRotateMode>\n"
                           "              <wpml:gimbalPitchRotateEnable>1</wpml:gimbalPitchRotateEnable>\n"
                           "              <wpml:gimbalPitchRotateAngle>{}</wpml:gimbalPitchRotateAngle>\n"
                           "              <wpml:gimbalRollRotateEnable>0</wpml:gimbalRollRotateEnable>\n"
                           "              <wpml:gimbalRollRotateAngle>0</wpml:gimbalRollRotateAngle>\n"
                           "              <wpml:gimbalYawRotateEnable>0</wpml:gimbalYawRotateEnable>\n"
                           "              <wpml:gimbalYawRotateAngle>0</wpml:gimbalYawRotateAngle>\n"
                           "              <wpml:gimbalRotateTimeEnable>0</wpml:gimbalRotateTimeEnable>\n"
                           "              <wpml:gimbalRotateTime>0</wpml:gimbalRotateTime>\n"
                           "              <wpml:payloadPositionIndex>0</wpml:payloadPositionIndex>\n"
                           "            </wpml:actionActuatorFuncParam>\n",
                           num(degrees(att[k].gimbal_pitch_deg)))));
  };

  std::string tpl = header + "    <wpml:author>uavcover</wpml:author>\n" + mission_config;
  // heights are relative to the take-off point (heightMode relativeToStartPoint), whose ellipsoid height
  // is not known here: wpml:ellipsoidHeight, required next to wpml:height when useGlobalHeight is 0,
  // repeats the relative height (as DJI Pilot 2 writes it for relativeToStartPoint routes)
  tpl += fmt::format(
      "    <Folder>\n"
      "      <wpml:templateType>waypoint</wpml:templateType>\n"
      "      <wpml:templateId>0</wpml:templateId>\n"
      "      <wpml:waylineCoordinateSysParam>\n"
      "        <wpml:coordinateMode>WGS84</wpml:coordinateMode>\n"
      "        <wpml:heightMode>relativeToStartPoint</wpml:heightMode>\n"
      "      </wpml:waylineCoordinateSysParam>\n"
      "      <wpml:autoFlightSpeed>{}</wpml:autoFlightSpeed>\n"
      "      <wpml:globalHeight>{}</wpml:globalHeight>\n"
      "      <wpml:gimbalPitchMode>usePointSetting</wpml:gimbalPitchMode>\n"
      "      "
      "<wpml:globalWaypointTurnMode>toPointAndStopWithDiscontinuityCurvature</wpml:globalWaypointTurnMode>\n"
      "      <wpml:globalUseStraightLine>1</wpml:globalUseStraightLine>\n"
      "      <wpml:globalWaypointHeadingParam>\n"
      "        <wpml:waypointHeadingMode>followWayline</wpml:waypointHeadingMode>\n"
      "        <wpml:waypointHeadingPathMode>followBadArc</wpml:waypointHeadingPathMode>\n"
      "      </wpml:globalWaypointHeadingParam>\n"
      "      <wpml:payloadParam>\n"
      "        <wpml:payloadPositionIndex>0</wpml:payloadPositionIndex>\n"
      "        <wpml:imageFormat>{}</wpml:imageFormat>\n"
      "      </wpml:payloadParam>\n",
      num(speed), num(plan.mission.altitude_m), lens_index(payload));
  std::string wl = header + mission_config;
  double distance = 0;
  {
    const geodesy::LocalFrame frame(plan.origin);
    for (std::size_t k = 1; k < wps.size(); ++k) {
      const Point a = frame.to_local({wps[k - 1]->lon, wps[k - 1]->lat});
      const Point b = frame.to_local({wps[k]->lon, wps[k]->lat});
      const double dz = static_cast<double>(wps[k]->alt) - static_cast<double>(wps[k - 1]->alt);
      distance += std::sqrt(bg::comparable_distance(a, b) + dz * dz);
    }
  }
  wl += fmt::format(
      "    <Folder>\n"
      "      <wpml:templateId>0</wpml:templateId>\n"
      "      <wpml:executeHeightMode>relativeToStartPoint</wpml:executeHeightMode>\n"
      "      <wpml:waylineId>0</wpml:waylineId>\n"
      "      <wpml:distance>{:.1f}</wpml:distance>\n"
      "      <wpml:duration>{:.1f}</wpml:duration>\n"
      "      <wpml:autoFlightSpeed>{}</wpml:autoFlightSpeed>\n",
      distance, speed > 0 ? distance / speed : 0.0, num(speed));
  int group = 0;
  for (std::size_t k = 0; k < wps.size(); ++k) {
    const MissionItem& w = *wps[k];
    const std::string point =
        fmt::format("        <Point><coordinates>{},{}</coordinates></Point>\n", coord(w.lon), coord(w.lat));
    tpl += "      <Placemark>\n" + point +
           fmt::format(
               "        <wpml:index>{}</wpml:index>\n"
               "        <wpml:ellipsoidHeight>{}</wpml:ellipsoidHeight>\n"
               "        <wpml:height>{}</wpml:height>\n"
               "        <wpml:useGlobalHeight>0</wpml:useGlobalHeight>\n"
               "        <wpml:useGlobalSpeed>1</wpml:useGlobalSpeed>\n"
               "        <wpml:useGlobalHeadingParam>{}</wpml:useGlobalHeadingParam>\n"
               "{}"
               "        <wpml:useGlobalTurnParam>1</wpml:useGlobalTurnParam>\n"
               "        <wpml:useStraightLine>1</wpml:useStraightLine>\n"
               "        <wpml:gimbalPitchAngle>{}</wpml:gimbalPitchAngle>\n",
               k, num(w.alt), num(w.alt), own_heading(k) ? 0 : 1,
               own_heading(k) ? heading_param(k, "        ") : std::string(), num(pitch_at(k)));
    wl += "      <Placemark>\n" + point +
          fmt::format(
              "        <wpml:index>{}</wpml:index>\n"
              "        <wpml:executeHeight>{}</wpml:executeHeight>\n"
              "        <wpml:waypointSpeed>{}</wpml:waypointSpeed>\n"
              "{}"
              "        <wpml:waypointTurnParam>\n"
              "          "
              "<wpml:waypointTurnMode>toPointAndStopWithDiscontinuityCurvature</wpml:waypointTurnMode>\n"
              "          <wpml:waypointTurnDampingDist>0</wpml:waypointTurnDampingDist>\n"
              "        </wpml:waypointTurnParam>\n"
              "        <wpml:useStraightLine>1</wpml:useStraightLine>\n",
              k, num(w.alt), num(speed), heading_param(k, "        "));
    const std::string g = gimbal_group(k, group) + groups_at(k, group);
    tpl += g;
    wl += g;
    tpl += "      </Placemark>\n";
    wl += "      </Placemark>\n";
  }
  tpl += "    </Folder>\n  </Document>\n</kml>\n";
  wl += "    </Folder>\n  </Document>\n</kml>\n";
  return {{"wpmz/template.kml", tpl}, {"wpmz/waylines.wpml", wl}};
}

}  // namespace uavcover::exporting
