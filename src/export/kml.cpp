#include "export/export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "export/support.hpp"
#include "export/xml.hpp"
#include "terrain/terrain.hpp"
#include "uavcover/error.hpp"

namespace uavcover::exporting {

using namespace waypoints;  // the waypoint model the formats write
using nlohmann::json;

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
      resolve_altitudes(opt.altitude, altitude_slots(plan), plan.mission.altitude_m);
  const auto items = items_of(plan, index, opt, altitudes);
  const UavPlan& up = plan.uavs.at(index);
  const LonLat home = plan.mission.uavs.at(index).start_resolved;
  std::string s =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<kml xmlns=\"http://www.opengis.net/kml/2.2\">\n";
  s += "  <Document>\n    <name>" +
       xml_escape(plan.mission.name.empty() ? up.id : plan.mission.name + " " + up.id) + "</name>\n";
  s += "    <description>" +
       xml_escape(fmt::format(
           "uav {}: mission altitude {} m ({}), transition altitude {} m, heights {}", up.id,
           num(plan.mission.altitude_m), plan.mission.altitude_source,
           num(transition_altitude(altitudes, altitude_slot(plan, index), plan.mission.altitude_m)),
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
  // the parts' attitude (PathPart::attitude through the items, docs/exports.md): a point per waypoint with a
  // heading or under an ROI, its icon turned to the heading, the values as ExtendedData; only when a part
  // has one, so other plans' KML is unchanged
  const std::vector<AttitudeAt> att = attitude_actions(items);
  std::string points;
  std::size_t k = 0;
  for (const auto& it : items) {
    if (it.command != kNavWaypoint) continue;
    const AttitudeAt a = k < att.size() ? att[k] : AttitudeAt{};
    ++k;
    if (std::isnan(a.heading_deg) && !a.roi) continue;
    std::string data;
    auto datum = [&](const char* name, const std::string& value) {
      data += fmt::format("          <Data name=\"{}\"><value>{}</value></Data>\n", name, value);
    };
    if (!std::isnan(a.heading_deg)) datum("heading_deg", num(degrees(a.heading_deg)));
    if (!std::isnan(a.gimbal_pitch_deg)) datum("gimbal_pitch_deg", num(degrees(a.gimbal_pitch_deg)));
    if (a.roi)
      datum("roi", fmt::format("{},{},{}", coord(a.roi_lon), coord(a.roi_lat), num(degrees(a.roi_alt))));
    points += fmt::format(
        "      <Placemark>\n        <name>waypoint {}</name>\n{}        <ExtendedData>\n{}        "
        "</ExtendedData>\n        <Point>\n          <altitudeMode>{}</altitudeMode>\n          "
        "<coordinates>{},{},{}</coordinates>\n        </Point>\n      </Placemark>\n",
        k - 1,
        std::isnan(a.heading_deg)
            ? std::string()
            : fmt::format("        <Style><IconStyle><heading>{}</heading></IconStyle></Style>\n",
                          num(degrees(a.heading_deg))),
        data, xml_escape(mode), coord(it.lon), coord(it.lat), num(it.alt));
  }
  if (!points.empty())
    s += "    <Folder>\n      <name>" + xml_escape(up.id) + " attitude</name>\n" + points + "    </Folder>\n";
  s += "  </Document>\n</kml>\n";
  return s;
}

}  // namespace uavcover::exporting
