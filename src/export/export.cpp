#include "export/export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "autopilot/rules.hpp"
#include "export/geofence.hpp"
#include "export/separation.hpp"
#include "export/xml.hpp"
#include "export/zip.hpp"
#include "geodesy/local_frame.hpp"
#include "io/plan_io.hpp"
#include "sorties/sorties.hpp"
#include "terrain/terrain.hpp"
#include "uavcover/error.hpp"

namespace uavcover::exporting {

using nlohmann::json;

const std::vector<std::string>& known_formats() {
  static const std::vector<std::string> formats{"geojson", "qgc",    "wpl", "kml",
                                                "dji",     "litchi", "csv", "trajectory"};
  return formats;
}

std::vector<std::string> parse_formats(const std::vector<std::string>& formats) {
  std::vector<std::string> wanted;
  const auto& known = known_formats();
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
      if (std::find(known.begin(), known.end(), f) == known.end()) {
        std::string list;
        for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
        throw InputError("formats", "unknown format \"" + f + "\" (known: " + list + ")");
      }
      if (std::find(wanted.begin(), wanted.end(), f) == wanted.end()) wanted.push_back(f);
    }
  }
  if (wanted.empty()) throw InputError("formats", "no format given");
  return wanted;
}

bool idle(const UavPlan& uav) {
  return std::none_of(uav.parts.begin(), uav.parts.end(),
                      [](const PathPart& p) { return p.kind == PartKind::Coverage && !p.wgs84.empty(); });
}

namespace {

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

/// What the camera does at a flown waypoint, as the MAVLink items after it say (src/photo/photo.hpp):
/// DJI and Litchi translate the same trigger plan into their own actions.
struct CameraAt {
  double leg_trigger_m = 0.0;  ///< a leg starts here, shot every this many metres (distance capture)
  int photos = 0;              ///< single images taken here (leg ends; hover captures)
  double hold_s = 0.0;         ///< hover before shooting
  std::size_t leg_end = 0;     ///< where a leg starts: the waypoint where its shooting stops
  double inside_leg_m = 0.0;   ///< a waypoint inside a leg (terrain following): the leg's trigger distance
};
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

std::string export_autopilot(const Plan& /*plan*/, const ExportOptions& opt) {
  if (opt.autopilot.empty()) return "px4";
  for (const char* a : {"px4", "ardupilot", "dji", "litchi"})
    if (opt.autopilot == a) return opt.autopilot;
  std::string shown = opt.autopilot.substr(0, 64);
  for (char& c : shown)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  throw InputError("autopilot", "must be 'px4', 'ardupilot', 'dji' or 'litchi', got '" + shown + "'");
}

int qgc_firmware_type(const Plan& plan, const ExportOptions& opt) {
  const std::string autopilot = export_autopilot(plan, opt);  // validated even when overridden
  if (opt.qgc_firmware_type >= 0) return opt.qgc_firmware_type;
  return autopilot == "ardupilot" ? 3 : 12;
}

json qgc_plan(const Plan& plan, std::size_t index, const ExportOptions& opt) {
  const int firmware = qgc_firmware_type(plan, opt);
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
      j["params"] = {jnum(it.param1), jnum(it.param2), jnum(it.param3), jnum(it.param4),
                     it.lat,          it.lon,          it.alt};
      j["Altitude"] = it.alt;
      j["AltitudeMode"] = it.frame == kFrameGlobal ? 2 : 1;  // QGC AltMode: 2 absolute (AMSL), 1 relative
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
            {"globalPlanAltitudeMode", terrain::grid(plan.mission) != nullptr ? 2 : 1},
            {"cruiseSpeed", uav.speed_mps},
            {"hoverSpeed", uav.speed_mps},
            {"plannedHomePosition", {home.lat, home.lon, terrain::home_ground(plan.mission, index)}},
            {"items", jitems}}},
          {"geoFence", {{"version", 2}, {"circles", json::array()}, {"polygons", polygons}}},
          {"rallyPoints", {{"version", 2}, {"points", json::array()}}}};
}

std::string wpl_text(const Plan& plan, std::size_t index, const ExportOptions& opt) {
  const auto items = mission_items(plan, index, opt.altitude);
  const Uav& uav = plan.mission.uavs.at(index);
  if (uav.speed_mps > limits::kArduPilotMaxSpeed)
    warn(opt, fmt::format("uav '{}': speed {} m/s is above ArduPilot's WPNAV_SPEED range (at most {} m/s)",
                          uav.id, uav.speed_mps, limits::kArduPilotMaxSpeed));
  const LonLat home = uav.start_resolved;
  std::string out = "QGC WPL 110\n";
  // row 0: home, absolute frame, ground level (0 m without a DEM: the home's elevation is not known then)
  out += fmt::format("0\t1\t0\t16\t0\t0\t0\t0\t{:.8f}\t{:.8f}\t{}\t1\n", home.lat, home.lon,
                     num(terrain::home_ground(plan.mission, index)));
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
  if (opt.kml_altitude_mode != "clampToGround" && opt.kml_altitude_mode != "relativeToGround" &&
      opt.kml_altitude_mode != "absolute")
    throw InputError("kml_altitude_mode", "must be clampToGround, relativeToGround or absolute");
  // with a DEM the heights are above mean sea level: the path is drawn "absolute" whatever the option
  const bool amsl = terrain::grid(plan.mission) != nullptr;
  const std::string mode = amsl ? "absolute" : opt.kml_altitude_mode;
  const AltitudeOptions altitudes =
      resolve_altitudes(opt.altitude, plan.uavs.size(), plan.mission.altitude_m);
  const auto items = mission_items(plan, index, altitudes);
  const UavPlan& up = plan.uavs.at(index);
  const LonLat home = plan.mission.uavs.at(index).start_resolved;
  std::string s =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<kml xmlns=\"http://www.opengis.net/kml/2.2\">\n";
  s += "  <Document>\n    <name>" +
       xml_escape(plan.mission.name.empty() ? up.id : plan.mission.name + " " + up.id) + "</name>\n";
  s += "    <description>" +
       xml_escape(fmt::format("uav {}: mission altitude {} m ({}), transition altitude {} m, heights {}",
                              up.id, num(plan.mission.altitude_m), plan.mission.altitude_source,
                              num(transition_altitude(altitudes, index, plan.mission.altitude_m)),
                              amsl ? "above mean sea level (terrain.dem), transit over its highest ground"
                                   : "relative to take-off")) +
       "</description>\n";
  s += "    <Style id=\"area\"><LineStyle><color>ff00ff00</color><width>2</width></LineStyle>"
       "<PolyStyle><color>3300ff00</color></PolyStyle></Style>\n";
  s += "    <Style id=\"nfz\"><LineStyle><color>ff0000ff</color><width>2</width></LineStyle>"
       "<PolyStyle><color>550000ff</color></PolyStyle></Style>\n";
  s += "    <Style id=\"path\"><LineStyle><color>ffff7f00</color><width>3</width></LineStyle></Style>\n";
  for (std::size_t k = 0; k < plan.mission.area.size(); ++k)
    s += kml_polygon_placemark(plan.mission.area[k], fmt::format("area {}", k), "area");
  for (std::size_t k = 0; k < plan.mission.no_fly_zones.size(); ++k)
    s += kml_polygon_placemark(plan.mission.no_fly_zones[k], fmt::format("no-fly zone {}", k), "nfz");
  std::string coords =
      coord(home.lon) + "," + coord(home.lat) + "," + num(terrain::home_ground(plan.mission, index));
  for (const auto& it : items)
    if (has_position(it)) coords += fmt::format(" {},{},{}", coord(it.lon), coord(it.lat), num(it.alt));
  s += "    <Placemark>\n      <name>" + xml_escape(up.id) +
       " path</name>\n      <styleUrl>#path</styleUrl>\n";
  s += "      <LineString>\n        <tessellate>0</tessellate>\n        <altitudeMode>" + xml_escape(mode) +
       "</altitudeMode>\n        <coordinates>" + coords +
       "</coordinates>\n      </LineString>\n    </Placemark>\n";
  s += "  </Document>\n</kml>\n";
  return s;
}

namespace {

/// The gimbal pitch of the camera UAV `index` carries: its own (uavs[i].camera), else the mission's.
double gimbal_pitch_of(const Plan& plan, std::size_t index) {
  const Uav* u = index < plan.mission.uavs.size() ? &plan.mission.uavs[index] : nullptr;
  return u != nullptr && u->camera ? u->camera->gimbal_pitch_deg : plan.mission.camera->gimbal_pitch_deg;
}

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
      resolve_altitudes(opt.altitude, plan.uavs.size(), plan.mission.altitude_m);
  const auto items = above_takeoff(plan, index, mission_items(plan, index, altitudes));
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
               "        <wpml:useGlobalHeadingParam>1</wpml:useGlobalHeadingParam>\n"
               "        <wpml:useGlobalTurnParam>1</wpml:useGlobalTurnParam>\n"
               "        <wpml:useStraightLine>1</wpml:useStraightLine>\n"
               "        <wpml:gimbalPitchAngle>{}</wpml:gimbalPitchAngle>\n",
               k, num(w.alt), num(w.alt), num(pitch));
    wl += "      <Placemark>\n" + point +
          fmt::format(
              "        <wpml:index>{}</wpml:index>\n"
              "        <wpml:executeHeight>{}</wpml:executeHeight>\n"
              "        <wpml:waypointSpeed>{}</wpml:waypointSpeed>\n"
              "        <wpml:waypointHeadingParam>\n"
              "          <wpml:waypointHeadingMode>followWayline</wpml:waypointHeadingMode>\n"
              "          <wpml:waypointHeadingPathMode>followBadArc</wpml:waypointHeadingPathMode>\n"
              "        </wpml:waypointHeadingParam>\n"
              "        <wpml:waypointTurnParam>\n"
              "          "
              "<wpml:waypointTurnMode>toPointAndStopWithDiscontinuityCurvature</wpml:waypointTurnMode>\n"
              "          <wpml:waypointTurnDampingDist>0</wpml:waypointTurnDampingDist>\n"
              "        </wpml:waypointTurnParam>\n"
              "        <wpml:useStraightLine>1</wpml:useStraightLine>\n",
              k, num(w.alt), num(speed));
    const std::string g = groups_at(k, group);
    tpl += g;
    wl += g;
    tpl += "      </Placemark>\n";
    wl += "      </Placemark>\n";
  }
  tpl += "    </Folder>\n  </Document>\n</kml>\n";
  wl += "    </Folder>\n  </Document>\n</kml>\n";
  return {{"wpmz/template.kml", tpl}, {"wpmz/waylines.wpml", wl}};
}

std::vector<std::string> litchi_csv(const Plan& plan, std::size_t index, const ExportOptions& opt) {
  const auto items = above_takeoff(plan, index, mission_items(plan, index, opt.altitude));
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
  auto row = [&](std::size_t k) {
    const MissionItem& w = *wps[k];
    std::string out = fmt::format("{:.8f},{:.8f},{},0,0,0,2,{}", w.lat, w.lon, num(w.alt), num(pitch));
    const CameraAt c = camera && k < shots.size() ? shots[k] : CameraAt{};
    int actions = 0;
    if (c.photos > 0 && c.hold_s > 0) {
      out += fmt::format(",0,{}", static_cast<int>(std::lround(c.hold_s * 1000)));
      ++actions;
    }
    for (int p = 0; p < c.photos && actions < 15; ++p, ++actions) out += ",1,0";
    for (; actions < 15; ++actions) out += ",-1,0";
    out += fmt::format(",0,{},0,0,0,0,-1,{}\n", num(speed),
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

namespace {

/// UAV ids are used unchanged in file names: the parser's id rule, checked again here for plan
/// folders that did not come through it.
bool usable_id(const std::string& id) {
  if (id.empty() || id.size() > 64 || id.front() == '.') return false;
  return std::all_of(id.begin(), id.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  });
}

/// The autopilots' upload rules (src/autopilot/rules.hpp) on the MAVLink items of UAV `i` of `p` (what the
/// .plan, .waypoints, CSV and `uavcover upload` carry): a rule the autopilots refuse the mission for
/// refuses the export; the limits that depend on the vehicle's configuration (item capacity, PX4's
/// distance parameters) warn, for the autopilot the export is for.
void check_consumers(const Plan& p, std::size_t i, const std::vector<MissionItem>& items,
                     const std::string& autopilot, std::vector<std::string>& warnings) {
  const std::string& id = p.uavs[i].id;
  const LonLat home = p.mission.uavs[i].start_resolved;
  struct Consumer {
    const char* name;
    std::vector<autopilot::Problem> problems;
    bool warn;
  };
  const Consumer consumers[] = {
      {"ArduPilot", autopilot::ardupilot_problems(items), autopilot == "ardupilot"},
      {"PX4", autopilot::px4_problems(items, home, terrain::home_ground(p.mission, i)), autopilot == "px4"}};
  for (const Consumer& c : consumers)
    for (const autopilot::Problem& pr : c.problems) {
      if (pr.fatal)
        throw InputError("autopilot", fmt::format("uav '{}': {} would refuse the mission: {}", id, c.name,
                                                  autopilot::describe(pr, items)));
      if (c.warn)
        warnings.push_back(fmt::format("uav '{}': {}: {}", id, c.name, autopilot::describe(pr, items)));
    }
}

}  // namespace

Artifacts export_artifacts(const Plan& plan, const std::vector<std::string>& formats,
                           const ExportOptions& options) {
  const std::vector<std::string> wanted = parse_formats(formats);
  if (plan.uavs.size() != plan.mission.uavs.size())
    throw InputError("uavs", fmt::format("the plan has {} UAV plans for {} mission UAVs", plan.uavs.size(),
                                         plan.mission.uavs.size()));
  if (!std::isfinite(options.geofence_margin_m) || options.geofence_margin_m < 0)
    throw InputError("geofence_margin_m", "must be >= 0");
  if (!std::isfinite(options.trajectory_step_s) || options.trajectory_step_s < 0 ||
      (options.trajectory_step_s > 0 && options.trajectory_step_s < 0.001))
    throw InputError("trajectory_step_s", "must be 0 (the segment form) or a step of at least 0.001 s");
  const std::string autopilot = export_autopilot(plan, options);  // an unknown one refuses before anything
  for (std::size_t i = 0; i < plan.uavs.size(); ++i)
    if (!usable_id(plan.uavs[i].id) || plan.uavs[i].id != plan.mission.uavs[i].id)
      throw InputError(fmt::format("uavs[{}].id", i),
                       "not usable as a file name (1 to 64 of A-Z a-z 0-9 _ - ., not starting with '.')");
  // warnings go to the caller only when the whole export succeeds
  std::vector<std::string> warnings;
  ExportOptions opt = options;
  opt.warnings = &warnings;
  opt.altitude = resolve_altitudes(options.altitude, plan.uavs.size(), plan.mission.altitude_m, &warnings);
  if (opt.check_separation) {
    const auto problems = check_separation(plan, opt.altitude);
    if (!problems.empty()) throw InputError("separation", problems.front());
  }
  for (const auto& w : separation_warnings(plan)) warnings.push_back(w);
  // idle UAVs (no coverage part) are skipped: a take-off-and-return mission is not worth flying
  std::vector<std::size_t> flown;
  for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
    if (idle(plan.uavs[i])) {
      warnings.push_back(
          fmt::format("uav '{}': no coverage parts, nothing exported for it", plan.uavs[i].id));
      continue;
    }
    flown.push_back(i);
    const auto items = mission_items(plan, i, opt.altitude);
    const auto violations = no_fly_violations(plan, i, items);
    if (!violations.empty()) throw InputError("no_fly_zones", violations.front() + " (re-plan the mission)");
    if (!opt.per_sortie) check_consumers(plan, i, items, autopilot, warnings);
  }
  if (flown.empty()) throw InputError("uavs", "no UAV has coverage parts: nothing to export");

  Artifacts out;
  auto put = [&](std::string name, const char* media_type, std::string bytes) {
    out.push_back({std::move(name), media_type, std::move(bytes)});
  };
  // format f of UAV i of `plan` (the whole plan, or one sortie's) under the name `base`.<ext>
  auto put_uav = [&](const Plan& p, std::size_t i, const std::string& f, const std::string& base) {
    const std::string& id = p.uavs[i].id;
    if (f == "geojson") {
      const json doc = uav_geojson(p, i);
      const auto problems = validate_geojson(doc);
      if (!problems.empty())
        throw InputError(fmt::format("uavs[{}]", i), "its GeoJSON export is invalid: " + problems.front());
      put(base + ".geojson", "application/geo+json", dump(doc, 1));
    } else if (f == "qgc") {
      put(base + ".plan", "application/json", dump(qgc_plan(p, i, opt), 4));
    } else if (f == "wpl") {
      put(base + ".waypoints", "text/plain", wpl_text(p, i, opt));
    } else if (f == "kml") {
      std::string kml = kml_text(p, i, opt);
      if (opt.kmz) put(base + ".kmz", "application/vnd.google-earth.kmz", zip_bytes({{"doc.kml", kml}}));
      put(base + ".kml", "application/vnd.google-earth.kml+xml", std::move(kml));
    } else if (f == "dji") {
      put(base + ".wpml.kmz", "application/vnd.google-earth.kmz", zip_bytes(dji_wpml(p, i, opt)));
    } else if (f == "litchi") {
      auto missions = litchi_csv(p, i, opt);
      if (missions.size() == 1) {
        put(base + ".litchi.csv", "text/csv", std::move(missions.front()));
      } else {
        for (std::size_t k = 0; k < missions.size(); ++k)
          put(fmt::format("{}.{}.litchi.csv", base, k + 1), "text/csv", std::move(missions[k]));
      }
    } else if (f == "csv") {
      put(base + ".csv", "text/csv", waypoints_csv(p, i, opt));
    } else if (f == "trajectory") {
      const auto traj = trajectory::uav_trajectory(p, i, opt.trajectory, opt.altitude);
      put("trajectory/" + id + ".csv", "text/csv",
          opt.trajectory_step_s > 0 ? trajectory::trajectory_csv(p, traj.sample(opt.trajectory_step_s))
                                    : trajectory::segments_csv(p, traj));
    }
  };
  // per sortie: the sorties of each flown UAV (cut now when the plan has none, e.g. built by hand)
  std::map<std::size_t, std::vector<Sortie>> sortie_lists;
  if (opt.per_sortie)
    for (const std::size_t i : flown) {
      auto list = plan.uavs[i].sorties.empty() ? sorties::cut_sorties(plan, i) : plan.uavs[i].sorties;
      for (const auto& s : list) {
        const Plan sp = sorties::sortie_plan(plan, i, s);
        const auto items = mission_items(sp, i, opt.altitude);
        const auto violations = no_fly_violations(sp, i, items);
        if (!violations.empty())
          throw InputError("no_fly_zones", violations.front() + " (re-plan the mission)");
        check_consumers(sp, i, items, autopilot, warnings);
      }
      sortie_lists[i] = std::move(list);
    }
  for (const auto& f : wanted) {
    const bool split = opt.per_sortie && f != "geojson" && f != "trajectory";
    for (const std::size_t i : flown) {
      const std::string& id = plan.uavs[i].id;
      if (!split) {
        put_uav(plan, i, f, "export/" + id);
        continue;
      }
      for (const auto& s : sortie_lists[i])
        put_uav(sorties::sortie_plan(plan, i, s), i, f, fmt::format("export/{}.s{}", id, s.index + 1));
    }
  }
  // ids are kept unchanged, so two ids can still name one file ("a.wpml" kml/kmz vs "a" dji)
  std::map<std::string, std::size_t> seen;
  for (std::size_t k = 0; k < out.size(); ++k) {
    const auto [it, fresh] = seen.emplace(out[k].name, k);
    if (!fresh)
      throw InputError("uavs", fmt::format("two exports would both be written to {}: rename one of the UAVs",
                                           out[k].name));
  }
  if (options.warnings != nullptr)
    options.warnings->insert(options.warnings->end(), warnings.begin(), warnings.end());
  return out;
}

}  // namespace uavcover::exporting
