#include "export/export.hpp"

#include <zip.h>

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <stdexcept>

#include "export/separation.hpp"
#include "geodesy/local_frame.hpp"
#include "io/plan_io.hpp"
#include "uavcover/error.hpp"

namespace uavcover::exporting {

namespace fs = std::filesystem;
using nlohmann::json;

const std::vector<std::string>& known_formats() {
  static const std::vector<std::string> formats{"geojson", "qgc",    "wpl", "kml",
                                                "dji",     "litchi", "csv", "trajectory"};
  return formats;
}

namespace {

constexpr std::size_t kLitchiMaxWaypoints = 99;  // Litchi missions hold at most 99 waypoints

bool has_position(const MissionItem& it) {
  return it.command == kNavWaypoint || it.command == kNavTakeoff || it.command == kNavLand;
}

/// Positioned items a waypoint-only format (DJI, Litchi) flies: everything but take-off and landing.
std::vector<const MissionItem*> flown_waypoints(const std::vector<MissionItem>& items) {
  std::vector<const MissionItem*> out;
  for (const auto& it : items)
    if (it.command == kNavWaypoint) out.push_back(&it);
  return out;
}

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string num(double v) { return fmt::format("{}", v); }
std::string coord(double v) { return fmt::format("{:.9f}", v); }

/// A file-system-safe version of a UAV id.
std::string safe_name(const std::string& id) {
  std::string out;
  for (char c : id)
    out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.') ? c : '_';
  if (out.empty() || out == "." || out == "..") out = "uav";
  return out;
}

// signed area of a lon/lat ring (shoelace), positive when counter-clockwise
double signed_area(const json& ring) {
  double s = 0;
  for (std::size_t i = 0; i + 1 < ring.size(); ++i)
    s += ring[i][0].get<double>() * ring[i + 1][1].get<double>() -
         ring[i + 1][0].get<double>() * ring[i][1].get<double>();
  return s / 2.0;
}

void check_position(const json& p, const std::string& where, std::vector<std::string>& problems) {
  if (!p.is_array() || p.size() < 2 || p.size() > 3 || !p[0].is_number() || !p[1].is_number()) {
    problems.push_back(where + ": a position must be [lon, lat] or [lon, lat, alt]");
    return;
  }
  const double lon = p[0].get<double>(), lat = p[1].get<double>();
  if (!(lon >= -180 && lon <= 180)) problems.push_back(where + ": longitude out of range");
  if (!(lat >= -90 && lat <= 90)) problems.push_back(where + ": latitude out of range");
}

void check_geometry(const json& g, const std::string& where, std::vector<std::string>& problems) {
  if (!g.is_object() || !g.contains("type") || !g.contains("coordinates")) {
    problems.push_back(where + ": geometry needs type and coordinates");
    return;
  }
  const std::string type = g["type"].get<std::string>();
  const json& c = g["coordinates"];
  auto check_polygon = [&](const json& rings, const std::string& w) {
    if (!rings.is_array() || rings.empty()) {
      problems.push_back(w + ": a polygon needs at least one ring");
      return;
    }
    for (std::size_t r = 0; r < rings.size(); ++r) {
      const json& ring = rings[r];
      const std::string rw = fmt::format("{} ring {}", w, r);
      if (!ring.is_array() || ring.size() < 4) {
        problems.push_back(rw + ": a linear ring needs at least 4 positions");
        continue;
      }
      std::size_t bad = problems.size();
      for (std::size_t k = 0; k < ring.size(); ++k)
        check_position(ring[k], fmt::format("{} position {}", rw, k), problems);
      if (problems.size() != bad) continue;
      if (ring.front()[0] != ring.back()[0] || ring.front()[1] != ring.back()[1])
        problems.push_back(rw + ": ring is not closed");
      const double a = signed_area(ring);
      if (r == 0 && !(a > 0)) problems.push_back(rw + ": exterior ring is not counter-clockwise");
      if (r > 0 && !(a < 0)) problems.push_back(rw + ": hole is not clockwise");
    }
  };
  if (type == "Polygon") {
    check_polygon(c, where);
  } else if (type == "MultiPolygon") {
    for (std::size_t i = 0; i < c.size(); ++i) check_polygon(c[i], fmt::format("{} polygon {}", where, i));
  } else if (type == "LineString") {
    if (!c.is_array() || c.size() < 2)
      problems.push_back(where + ": a LineString needs at least 2 positions");
    else
      for (std::size_t k = 0; k < c.size(); ++k)
        check_position(c[k], fmt::format("{} position {}", where, k), problems);
  } else if (type == "MultiLineString") {
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (!c[i].is_array() || c[i].size() < 2)
        problems.push_back(where + ": a LineString needs at least 2 positions");
      else
        for (std::size_t k = 0; k < c[i].size(); ++k)
          check_position(c[i][k], fmt::format("{} line {} position {}", where, i, k), problems);
    }
  } else if (type == "Point") {
    check_position(c, where, problems);
  } else if (type == "MultiPoint") {
    for (std::size_t k = 0; k < c.size(); ++k)
      check_position(c[k], fmt::format("{} position {}", where, k), problems);
  } else {
    problems.push_back(where + ": unknown geometry type '" + type + "'");
  }
}

}  // namespace

json uav_geojson(const Plan& plan, std::size_t index) {
  if (index >= plan.uavs.size())
    throw std::out_of_range("uav_geojson: no UAV with index " + std::to_string(index));
  return io::paths_geojson(plan, index);
}

std::vector<std::string> validate_geojson(const json& doc) {
  std::vector<std::string> problems;
  if (!doc.is_object() || doc.value("type", "") != "FeatureCollection" || !doc.contains("features") ||
      !doc["features"].is_array()) {
    problems.emplace_back("not a FeatureCollection with a features array");
    return problems;
  }
  const json& features = doc["features"];
  for (std::size_t i = 0; i < features.size(); ++i) {
    const json& f = features[i];
    const std::string where = fmt::format("features[{}]", i);
    if (!f.is_object() || f.value("type", "") != "Feature" || !f.contains("geometry")) {
      problems.push_back(where + ": not a Feature with a geometry");
      continue;
    }
    if (f["geometry"].is_null()) continue;
    check_geometry(f["geometry"], where + ".geometry", problems);
  }
  return problems;
}

json qgc_plan(const Plan& plan, std::size_t index, const ExportOptions& opt) {
  const auto items = mission_items(plan, index, opt.altitude);
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
    if (has_position(it)) {
      // yaw (param 4) 0 on a position item means "unset" here: QGC writes it as null (NaN, keep the
      // vehicle's heading mode) rather than pointing the vehicle north
      j["params"] = {it.param1, it.param2, it.param3, nullptr, it.lat, it.lon, it.alt};
      if (it.param4 != 0.0f) j["params"][3] = it.param4;
      j["Altitude"] = it.alt;
      j["AltitudeMode"] = 1;  // relative to home
      j["AMSLAltAboveTerrain"] = nullptr;
    } else {
      j["params"] = {it.param1, it.param2, it.param3, it.param4, 0, 0, 0};
    }
    jitems.push_back(j);
  }
  const LonLat home = uav.start_resolved;
  json polygons = json::array();
  auto fence = [&](const GeoPolygon& poly, bool inclusion) {
    if (poly.empty() || poly.front().size() < 4) return;
    json pts = json::array();
    for (std::size_t k = 0; k + 1 < poly.front().size(); ++k)
      pts.push_back({poly.front()[k].lat, poly.front()[k].lon});
    polygons.push_back({{"inclusion", inclusion}, {"polygon", pts}, {"version", 1}});
  };
  for (const auto& poly : plan.mission.area) fence(poly, true);
  for (const auto& poly : plan.mission.no_fly_zones) fence(poly, false);
  return {{"fileType", "Plan"},
          {"version", 1},
          {"groundStation", "QGroundControl"},
          {"mission",
           {{"version", 2},
            {"firmwareType", opt.qgc_firmware_type},
            {"vehicleType", opt.qgc_vehicle_type},
            {"globalPlanAltitudeMode", 1},
            {"cruiseSpeed", uav.speed_mps},
            {"hoverSpeed", uav.speed_mps},
            {"plannedHomePosition", {home.lat, home.lon, 0}},
            {"items", jitems}}},
          {"geoFence", {{"version", 2}, {"circles", json::array()}, {"polygons", polygons}}},
          {"rallyPoints", {{"version", 2}, {"points", json::array()}}}};
}

std::string wpl_text(const Plan& plan, std::size_t index, const ExportOptions& opt) {
  const auto items = mission_items(plan, index, opt.altitude);
  const LonLat home = plan.mission.uavs.at(index).start_resolved;
  std::string out = "QGC WPL 110\n";
  // row 0: home, absolute frame, ground level (0 m: the home's elevation is not known here)
  out += fmt::format("0\t1\t0\t16\t0\t0\t0\t0\t{:.8f}\t{:.8f}\t0\t1\n", home.lat, home.lon);
  int seq = 1;
  for (const auto& it : items) {
    out += fmt::format("{}\t0\t{}\t{}\t{}\t{}\t{}\t{}\t{:.8f}\t{:.8f}\t{}\t{}\n", seq++, it.frame, it.command,
                       num(it.param1), num(it.param2), num(it.param3), num(it.param4), it.lat, it.lon,
                       num(it.alt), it.autocontinue ? 1 : 0);
  }
  return out;
}

namespace {

std::string kml_ring(const GeoRing& ring) {
  std::string s;
  for (const auto& p : ring) s += coord(p.lon) + "," + coord(p.lat) + ",0 ";
  if (!s.empty()) s.pop_back();
  return s;
}

std::string kml_polygon_placemark(const GeoPolygon& poly, const std::string& name, const std::string& style) {
  std::string s = "    <Placemark>\n      <name>" + xml_escape(name) + "</name>\n      <styleUrl>#" + style +
                  "</styleUrl>\n      <Polygon>\n        <altitudeMode>clampToGround</altitudeMode>\n";
  for (std::size_t r = 0; r < poly.size(); ++r) {
    const char* tag = r == 0 ? "outerBoundaryIs" : "innerBoundaryIs";
    s += fmt::format("        <{}><LinearRing><coordinates>{}</coordinates></LinearRing></{}>\n", tag,
                     kml_ring(poly[r]), tag);
  }
  s += "      </Polygon>\n    </Placemark>\n";
  return s;
}

}  // namespace

std::string kml_text(const Plan& plan, std::size_t index, const ExportOptions& opt) {
  const auto items = mission_items(plan, index, opt.altitude);
  const UavPlan& up = plan.uavs.at(index);
  const LonLat home = plan.mission.uavs.at(index).start_resolved;
  std::string s =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<kml xmlns=\"http://www.opengis.net/kml/2.2\">\n";
  s += "  <Document>\n    <name>" +
       xml_escape(plan.mission.name.empty() ? up.id : plan.mission.name + " " + up.id) + "</name>\n";
  s += fmt::format(
      "    <description>uav {}: mission altitude {} m ({}), transition altitude {} m, heights relative to "
      "take-off</description>\n",
      xml_escape(up.id), num(plan.mission.altitude_m), xml_escape(plan.mission.altitude_source),
      num(transition_altitude(opt.altitude, index, plan.mission.altitude_m)));
  s += "    <Style id=\"area\"><LineStyle><color>ff00ff00</color><width>2</width></LineStyle>"
       "<PolyStyle><color>3300ff00</color></PolyStyle></Style>\n";
  s += "    <Style id=\"nfz\"><LineStyle><color>ff0000ff</color><width>2</width></LineStyle>"
       "<PolyStyle><color>550000ff</color></PolyStyle></Style>\n";
  s += "    <Style id=\"path\"><LineStyle><color>ffff7f00</color><width>3</width></LineStyle></Style>\n";
  for (std::size_t k = 0; k < plan.mission.area.size(); ++k)
    s += kml_polygon_placemark(plan.mission.area[k], fmt::format("area {}", k), "area");
  for (std::size_t k = 0; k < plan.mission.no_fly_zones.size(); ++k)
    s += kml_polygon_placemark(plan.mission.no_fly_zones[k], fmt::format("no-fly zone {}", k), "nfz");
  std::string coords = coord(home.lon) + "," + coord(home.lat) + ",0";
  for (const auto& it : items)
    if (has_position(it)) coords += fmt::format(" {},{},{}", coord(it.lon), coord(it.lat), num(it.alt));
  s += "    <Placemark>\n      <name>" + xml_escape(up.id) +
       " path</name>\n      <styleUrl>#path</styleUrl>\n";
  s += "      <LineString>\n        <tessellate>0</tessellate>\n        <altitudeMode>" +
       xml_escape(opt.kml_altitude_mode) + "</altitudeMode>\n        <coordinates>" + coords +
       "</coordinates>\n      </LineString>\n    </Placemark>\n";
  s += "  </Document>\n</kml>\n";
  return s;
}

std::map<std::string, std::string> dji_wpml(const Plan& plan, std::size_t index, const ExportOptions& opt) {
  const auto items = mission_items(plan, index, opt.altitude);
  const auto wps = flown_waypoints(items);
  const Uav& uav = plan.mission.uavs.at(index);
  const double speed = uav.speed_mps;
  const bool camera = plan.mission.camera.has_value() && plan.mission.spacing_m > 0;
  const double transit_alt = transition_altitude(opt.altitude, index, plan.mission.altitude_m);

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
      "      <wpml:droneInfo>\n"
      "        <wpml:droneEnumValue>{}</wpml:droneEnumValue>\n"
      "        <wpml:droneSubEnumValue>{}</wpml:droneSubEnumValue>\n"
      "      </wpml:droneInfo>\n"
      "    </wpml:missionConfig>\n",
      opt.altitude.land_instead_of_rtl ? "autoLand" : "goHome", num(std::min(transit_alt, 1500.0)),
      num(speed), opt.dji_drone_enum, opt.dji_drone_sub_enum);

  // camera: one action group per coverage run, photos every spacing_m metres
  auto action_group = [&](std::size_t start, std::size_t end, int id) {
    return fmt::format(
        "        <wpml:actionGroup>\n"
        "          <wpml:actionGroupId>{}</wpml:actionGroupId>\n"
        "          <wpml:actionGroupStartIndex>{}</wpml:actionGroupStartIndex>\n"
        "          <wpml:actionGroupEndIndex>{}</wpml:actionGroupEndIndex>\n"
        "          <wpml:actionGroupMode>sequence</wpml:actionGroupMode>\n"
        "          <wpml:actionTrigger>\n"
        "            <wpml:actionTriggerType>multipleDistance</wpml:actionTriggerType>\n"
        "            <wpml:actionTriggerParam>{}</wpml:actionTriggerParam>\n"
        "          </wpml:actionTrigger>\n"
        "          <wpml:action>\n"
        "            <wpml:actionId>0</wpml:actionId>\n"
        "            <wpml:actionActuatorFunc>takePhoto</wpml:actionActuatorFunc>\n"
        "            <wpml:actionActuatorFuncParam>\n"
        "              <wpml:payloadPositionIndex>0</wpml:payloadPositionIndex>\n"
        "            </wpml:actionActuatorFuncParam>\n"
        "          </wpml:action>\n"
        "        </wpml:actionGroup>\n",
        id, start, end, num(plan.mission.spacing_m));
  };
  // coverage runs: [start, end] waypoint indices of consecutive coverage waypoints of one part
  std::map<std::size_t, std::size_t> runs;
  for (std::size_t k = 0; k < wps.size(); ++k) {
    if (wps[k]->role != "coverage") continue;
    std::size_t e = k;
    while (e + 1 < wps.size() && wps[e + 1]->role == "coverage" && wps[e + 1]->part == wps[k]->part) ++e;
    runs[k] = e;
    k = e;
  }

  std::string tpl = header + "    <wpml:author>uavcover</wpml:author>\n" + mission_config;
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
      "      "
      "<wpml:globalWaypointTurnMode>toPointAndStopWithDiscontinuityCurvature</wpml:globalWaypointTurnMode>\n"
      "      <wpml:globalUseStraightLine>1</wpml:globalUseStraightLine>\n"
      "      <wpml:globalWaypointHeadingParam>\n"
      "        <wpml:waypointHeadingMode>followWayline</wpml:waypointHeadingMode>\n"
      "      </wpml:globalWaypointHeadingParam>\n",
      num(speed), num(plan.mission.altitude_m));
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
               "        <wpml:height>{}</wpml:height>\n"
               "        <wpml:useGlobalHeight>0</wpml:useGlobalHeight>\n"
               "        <wpml:useGlobalSpeed>1</wpml:useGlobalSpeed>\n"
               "        <wpml:useGlobalHeadingParam>1</wpml:useGlobalHeadingParam>\n"
               "        <wpml:useGlobalTurnParam>1</wpml:useGlobalTurnParam>\n"
               "        <wpml:useStraightLine>1</wpml:useStraightLine>\n",
               k, num(w.alt));
    wl += "      <Placemark>\n" + point +
          fmt::format(
              "        <wpml:index>{}</wpml:index>\n"
              "        <wpml:executeHeight>{}</wpml:executeHeight>\n"
              "        <wpml:waypointSpeed>{}</wpml:waypointSpeed>\n"
              "        <wpml:waypointHeadingParam>\n"
              "          <wpml:waypointHeadingMode>followWayline</wpml:waypointHeadingMode>\n"
              "        </wpml:waypointHeadingParam>\n"
              "        <wpml:waypointTurnParam>\n"
              "          "
              "<wpml:waypointTurnMode>toPointAndStopWithDiscontinuityCurvature</wpml:waypointTurnMode>\n"
              "          <wpml:waypointTurnDampingDist>0</wpml:waypointTurnDampingDist>\n"
              "        </wpml:waypointTurnParam>\n"
              "        <wpml:useStraightLine>1</wpml:useStraightLine>\n",
              k, num(w.alt), num(speed));
    if (camera) {
      auto r = runs.find(k);
      if (r != runs.end() && r->second > r->first) {
        const std::string g = action_group(r->first, r->second, group++);
        tpl += g;
        wl += g;
      }
    }
    tpl += "      </Placemark>\n";
    wl += "      </Placemark>\n";
  }
  tpl += "    </Folder>\n  </Document>\n</kml>\n";
  wl += "    </Folder>\n  </Document>\n</kml>\n";
  return {{"wpmz/template.kml", tpl}, {"wpmz/waylines.wpml", wl}};
}

std::string litchi_csv(const Plan& plan, std::size_t index, const ExportOptions& opt) {
  const auto items = mission_items(plan, index, opt.altitude);
  const auto wps = flown_waypoints(items);
  const Uav& uav = plan.mission.uavs.at(index);
  const bool camera = plan.mission.camera.has_value() && plan.mission.spacing_m > 0;
  std::string out =
      "latitude,longitude,altitude(m),heading(deg),curvesize(m),rotationdir,gimbalmode,gimbalpitchangle";
  for (int k = 1; k <= 15; ++k) out += fmt::format(",actiontype{},actionparam{}", k, k);
  out +=
      ",altitudemode,speed(m/"
      "s),poi_latitude,poi_longitude,poi_altitude(m),poi_altitudemode,photo_timeinterval,"
      "photo_distinterval\n";
  for (const MissionItem* w : wps) {
    // gimbal pitch -90 (nadir); no actions; altitude relative to take-off (altitudemode 0)
    out += fmt::format("{:.8f},{:.8f},{},0,0,0,2,-90", w->lat, w->lon, num(w->alt));
    for (int k = 1; k <= 15; ++k) out += ",-1,0";
    const bool shoot = camera && w->role == "coverage";
    out +=
        fmt::format(",0,{},0,0,0,0,-1,{}\n", num(uav.speed_mps), shoot ? num(plan.mission.spacing_m) : "-1");
  }
  return out;
}

std::string waypoints_csv(const Plan& plan, std::size_t index, const ExportOptions& opt) {
  const auto items = mission_items(plan, index, opt.altitude);
  std::string out = "seq,role,command,frame,lat,lon,alt_m,param1,param2,param3,param4\n";
  int seq = 1;
  for (const auto& it : items)
    out += fmt::format("{},{},{},{},{:.9f},{:.9f},{},{},{},{},{}\n", seq++, it.role, it.command, it.frame,
                       it.lat, it.lon, num(it.alt), num(it.param1), num(it.param2), num(it.param3),
                       num(it.param4));
  return out;
}

void write_zip(const fs::path& path, const std::map<std::string, std::string>& entries) {
  fs::create_directories(path.parent_path());
  const fs::path tmp = path.string() + ".tmp";
  fs::remove(tmp);
  int err = 0;
  zip_t* za = zip_open(tmp.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
  if (za == nullptr)
    throw std::runtime_error(fmt::format("cannot create '{}' (libzip error {})", tmp.string(), err));
  for (const auto& [name, data] : entries) {
    zip_source_t* src = zip_source_buffer(za, data.data(), data.size(), 0);
    if (src == nullptr || zip_file_add(za, name.c_str(), src, ZIP_FL_OVERWRITE | ZIP_FL_ENC_UTF_8) < 0) {
      if (src != nullptr) zip_source_free(src);
      const std::string msg = zip_strerror(za);
      zip_discard(za);
      throw std::runtime_error("cannot add '" + name + "' to '" + path.string() + "': " + msg);
    }
  }
  if (zip_close(za) < 0) {
    const std::string msg = zip_strerror(za);
    zip_discard(za);
    throw std::runtime_error("cannot write '" + path.string() + "': " + msg);
  }
  fs::rename(tmp, path);
}

std::vector<fs::path> export_plan(const Plan& plan, const std::vector<std::string>& formats,
                                  const fs::path& out_dir, const ExportOptions& opt) {
  // parse and check the format list first: nothing is written when one is unknown
  std::vector<std::string> wanted;
  for (const auto& entry : formats) {
    std::size_t pos = 0;
    while (pos <= entry.size()) {
      const std::size_t comma = std::min(entry.find(',', pos), entry.size());
      std::string f = entry.substr(pos, comma - pos);
      f.erase(0, f.find_first_not_of(" \t"));
      f.erase(f.find_last_not_of(" \t") + 1);
      for (auto& c : f) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      pos = comma + 1;
      if (f.empty()) continue;
      const auto& known = known_formats();
      if (std::find(known.begin(), known.end(), f) == known.end()) {
        std::string list;
        for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
        throw InputError("--format", "unknown format '" + f + "' (known: " + list + ")");
      }
      if (std::find(wanted.begin(), wanted.end(), f) == wanted.end()) wanted.push_back(f);
    }
  }
  if (wanted.empty()) throw InputError("--format", "no format given");
  if (plan.uavs.size() != plan.mission.uavs.size())
    throw std::runtime_error("export: plan has " + std::to_string(plan.uavs.size()) + " UAV plans for " +
                             std::to_string(plan.mission.uavs.size()) + " mission UAVs");
  if (opt.check_separation) {
    const auto problems = check_separation(plan, opt.altitude);
    if (!problems.empty()) throw InputError("separation", problems.front());
  }
  if (opt.warnings != nullptr) {
    const auto w = separation_warnings(plan);
    opt.warnings->insert(opt.warnings->end(), w.begin(), w.end());
  }
  // distinct file names per UAV
  std::vector<std::string> names;
  std::set<std::string> used;
  for (const auto& up : plan.uavs) {
    std::string base = safe_name(up.id), name = base;
    for (int k = 2; used.count(name) != 0; ++k) name = base + "-" + std::to_string(k);
    used.insert(name);
    names.push_back(name);
  }

  const fs::path dir = out_dir / "export";
  std::vector<fs::path> written;
  auto put = [&](const fs::path& p, const std::string& text) {
    io::write_file_atomic(p, text);
    written.push_back(p);
  };
  for (const auto& f : wanted) {
    for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
      const std::string& id = names[i];
      if (f == "geojson") {
        const json doc = uav_geojson(plan, i);
        const auto problems = validate_geojson(doc);
        if (!problems.empty())
          throw std::runtime_error("geojson export of '" + id + "' is invalid: " + problems.front());
        put(dir / (id + ".geojson"), doc.dump(1) + "\n");
      } else if (f == "qgc") {
        put(dir / (id + ".plan"), qgc_plan(plan, i, opt).dump(4) + "\n");
      } else if (f == "wpl") {
        put(dir / (id + ".waypoints"), wpl_text(plan, i, opt));
      } else if (f == "kml") {
        const std::string kml = kml_text(plan, i, opt);
        put(dir / (id + ".kml"), kml);
        if (opt.kmz) {
          write_zip(dir / (id + ".kmz"), {{"doc.kml", kml}});
          written.push_back(dir / (id + ".kmz"));
        }
      } else if (f == "dji") {
        write_zip(dir / (id + ".wpml.kmz"), dji_wpml(plan, i, opt));
        written.push_back(dir / (id + ".wpml.kmz"));
      } else if (f == "litchi") {
        const std::string text = litchi_csv(plan, i, opt);
        put(dir / (id + ".litchi.csv"), text);
        const auto rows = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) - 1;
        if (opt.warnings != nullptr && rows > kLitchiMaxWaypoints)
          opt.warnings->push_back(
              fmt::format("uav '{}': {} Litchi waypoints, more than the {} one Litchi mission holds",
                          plan.uavs[i].id, rows, kLitchiMaxWaypoints));
      } else if (f == "csv") {
        put(dir / (id + ".csv"), waypoints_csv(plan, i, opt));
      } else if (f == "trajectory") {
        const auto traj = trajectory::uav_trajectory(plan, i, opt.trajectory, opt.altitude);
        put(out_dir / "trajectory" / (id + ".csv"), trajectory::trajectory_csv(plan, traj.sample()));
      }
    }
  }
  return written;
}

}  // namespace uavcover::exporting
