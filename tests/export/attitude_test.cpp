// Every export carries PathPart::attitude (issue 30, docs/exports.md "Attitude"), read back with an
// independent reader (nlohmann json, plain text splitting, pugixml, libzip): the orbit's headings toward
// its centre and its own height, the oblique pass's gimbal pitch and fixed heading, the ROI, the part with
// its own height and trigger distance; and the autopilots' upload rules accept the missions.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <pugixml.hpp>
#include <string>
#include <vector>

#include "autopilot/rules.hpp"
#include "export/attitude_fixture.hpp"
#include "export/check.hpp"
#include "export/export.hpp"
#include "geodesy/local_frame.hpp"
#include "mavlink/mission_protocol.hpp"
#include "waypoints/ardupilot.hpp"
#include "waypoints/waypoints.hpp"

using namespace uavcover;
using namespace uavcover::exporting;
using namespace uavcover::waypoints;
using nlohmann::json;

namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out(1);
  for (char c : s) {
    if (c == sep)
      out.emplace_back();
    else
      out.back() += c;
  }
  return out;
}

std::vector<std::string> lines(const std::string& s) {
  auto out = split(s, '\n');
  if (!out.empty() && out.back().empty()) out.pop_back();
  return out;
}

const std::string& bytes_of(const Artifacts& a, const std::string& name) {
  const Artifact* f = check::find(a, name);
  if (f == nullptr) throw std::runtime_error("no artifact " + name);
  return f->bytes;
}

double heading_error(double a, double b) { return std::abs(std::remainder(a - b, 360.0)); }

/// What the orbit's waypoints must carry: at `p` (local), the bearing to the centre.
double toward_centre(const geodesy::LocalFrame& frame, double lat, double lon) {
  return fixture::bearing_deg(frame.to_local({lon, lat}), fixture::kOrbitCentre);
}

bool near_roi(const geodesy::LocalFrame& frame, double lat, double lon) {
  const Point r = frame.to_local({lon, lat});
  return std::hypot(r.x() - fixture::kRoi.x(), r.y() - fixture::kRoi.y()) < 0.01;
}

}  // namespace

TEST(AttitudeExports, QgcPlanAndWplCarryHeadingsGimbalRoiAndHeights) {
  const Plan plan = fixture::attitude_plan();
  const geodesy::LocalFrame frame(plan.origin);
  const Artifacts out = export_artifacts(plan, {"qgc", "wpl"});
  // .plan: SimpleItems, params [p1..p4, lat, lon, alt]
  const json doc = json::parse(bytes_of(out, "export/alpha.plan"));
  int orbit = 0, oblique_gimbal = 0, roi_on = 0, roi_off = 0, high = 0;
  for (const json& it : doc["mission"]["items"]) {
    const int cmd = it["command"].get<int>();
    const json& p = it["params"];
    if (cmd == 16 && it["Altitude"].get<double>() == fixture::kOrbitAltitude) {
      ++orbit;
      ASSERT_TRUE(p[3].is_number());
      EXPECT_LT(heading_error(p[3].get<double>(), toward_centre(frame, p[4], p[5])), 0.01);
    }
    if (cmd == 16 && it["Altitude"].get<double>() == fixture::kHighAltitude) ++high;
    if (cmd == 1000 && p[0].get<double>() == fixture::kObliquePitch) ++oblique_gimbal;
    if (cmd == 201 && p[0].get<double>() == 3) {
      ++roi_on;
      EXPECT_TRUE(near_roi(frame, p[4], p[5]));
      EXPECT_DOUBLE_EQ(p[6].get<double>(), plan.mission.altitude_m);
    }
    if (cmd == 201 && p[0].get<double>() == 0) ++roi_off;
  }
  EXPECT_GE(orbit, 13);
  EXPECT_EQ(oblique_gimbal, 1);
  EXPECT_EQ(roi_on, 1);
  EXPECT_EQ(roi_off, 1);
  EXPECT_EQ(high, 2);
  // .waypoints: seq current frame command p1 p2 p3 p4 lat lon alt autocontinue; row 0 home
  const auto rows = lines(bytes_of(out, "export/alpha.waypoints"));
  int wpl_orbit = 0, wpl_roi = 0, wpl_gimbal = 0;
  for (std::size_t k = 2; k < rows.size(); ++k) {
    const auto f = split(rows[k], '\t');
    ASSERT_EQ(f.size(), 12u);
    const int cmd = std::stoi(f[3]);
    if (cmd == 16 && std::stod(f[10]) == fixture::kOrbitAltitude) {
      ++wpl_orbit;
      EXPECT_LT(heading_error(std::stod(f[7]), toward_centre(frame, std::stod(f[8]), std::stod(f[9]))), 0.01);
    }
    if (cmd == 201 && std::stod(f[4]) == 3) {
      ++wpl_roi;
      EXPECT_TRUE(near_roi(frame, std::stod(f[8]), std::stod(f[9])));
    }
    if (cmd == 1000 && std::stod(f[4]) == fixture::kObliquePitch) ++wpl_gimbal;
  }
  EXPECT_EQ(wpl_orbit, orbit);
  EXPECT_EQ(wpl_roi, 1);
  EXPECT_EQ(wpl_gimbal, 1);
}

TEST(AttitudeExports, DjiWpmlHeadingsPoiAndGimbalRotate) {
  const Plan plan = fixture::attitude_plan();
  const geodesy::LocalFrame frame(plan.origin);
  const Artifacts out = export_artifacts(plan, {"dji"});
  const auto entries = check::unzip_bytes(bytes_of(out, "export/alpha.wpml.kmz"));
  for (const char* name : {"wpmz/waylines.wpml", "wpmz/template.kml"}) {
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_string(entries.at(name).c_str())) << name;
    const bool wayline = std::string(name).ends_with(".wpml");
    int orbit = 0, poi = 0, rotates = 0, followed = 0;
    double last_rotate = 0;
    for (const auto& m : doc.select_nodes("/kml/Document/Folder/Placemark")) {
      const pugi::xml_node n = m.node();
      const auto c = split(n.select_node("Point/coordinates").node().text().get(), ',');
      const double lon = std::stod(c.at(0)), lat = std::stod(c.at(1));
      const double h = n.child(wayline ? "wpml:executeHeight" : "wpml:height").text().as_double();
      const pugi::xml_node hp = n.child("wpml:waypointHeadingParam");
      const std::string mode = hp ? hp.child("wpml:waypointHeadingMode").text().get() : "";
      if (!wayline) {
        EXPECT_EQ(n.child("wpml:useGlobalHeadingParam").text().as_int(), hp ? 0 : 1);
      }
      if (h == fixture::kOrbitAltitude) {
        ++orbit;
        EXPECT_EQ(mode, "smoothTransition");
        const double angle = hp.child("wpml:waypointHeadingAngle").text().as_double();
        EXPECT_GE(angle, -180.0);  // WPML's range
        EXPECT_LE(angle, 180.0);
        EXPECT_LT(heading_error(angle, toward_centre(frame, lat, lon)), 0.01);
      }
      if (mode == "towardPOI") {
        ++poi;
        const auto pt = split(hp.child("wpml:waypointPoiPoint").text().get(), ',');
        ASSERT_EQ(pt.size(), 3u);
        EXPECT_TRUE(near_roi(frame, std::stod(pt[0]), std::stod(pt[1])));  // "lat,lon,height"
      }
      if (mode == "followWayline" || !hp) ++followed;
      for (const auto& a : n.select_nodes("wpml:actionGroup/wpml:action")) {
        if (std::string(a.node().child("wpml:actionActuatorFunc").text().get()) != "gimbalRotate") continue;
        ++rotates;
        const pugi::xml_node p = a.node().child("wpml:actionActuatorFuncParam");
        EXPECT_EQ(p.child("wpml:gimbalPitchRotateEnable").text().as_int(), 1);
        EXPECT_STREQ(p.child("wpml:gimbalRotateMode").text().get(), "absoluteAngle");
        last_rotate = p.child("wpml:gimbalPitchRotateAngle").text().as_double();
        if (rotates == 1) {
          EXPECT_DOUBLE_EQ(last_rotate, fixture::kObliquePitch);
        }
      }
    }
    EXPECT_GE(orbit, 13) << name;
    // the ROI holds while leaving the point before the part and its waypoints but the last
    EXPECT_GE(poi, 2) << name;
    EXPECT_GT(followed, 0) << name;  // transit waypoints keep following the wayline
    EXPECT_EQ(rotates, 2) << name;   // -45 for the oblique pass, back to the camera's -90 after it
    EXPECT_DOUBLE_EQ(last_rotate, plan.mission.camera->gimbal_pitch_deg) << name;
  }
}

TEST(AttitudeExports, LitchiHeadingGimbalAndPoiColumns) {
  const Plan plan = fixture::attitude_plan();
  const geodesy::LocalFrame frame(plan.origin);
  const Artifacts out = export_artifacts(plan, {"litchi"});
  const auto rows = lines(bytes_of(out, "export/alpha.litchi.csv"));
  const auto header = split(rows.at(0), ',');
  auto col = [&](const std::string& name) {
    for (std::size_t k = 0; k < header.size(); ++k)
      if (header[k] == name) return k;
    throw std::runtime_error("no column " + name);
  };
  const std::size_t lat = col("latitude"), lon = col("longitude"), alt = col("altitude(m)"),
                    heading = col("heading(deg)"), gmode = col("gimbalmode"), pitch = col("gimbalpitchangle"),
                    plat = col("poi_latitude"), plon = col("poi_longitude");
  int orbit = 0, tilted = 0, poi = 0;
  for (std::size_t k = 1; k < rows.size(); ++k) {
    const auto f = split(rows[k], ',');
    ASSERT_EQ(f.size(), header.size());
    const double la = std::stod(f[lat]), lo = std::stod(f[lon]);
    if (std::stod(f[alt]) == fixture::kOrbitAltitude) {
      ++orbit;
      EXPECT_GE(std::stod(f[heading]), 0.0);
      EXPECT_LT(std::stod(f[heading]), 360.0);
      EXPECT_LT(heading_error(std::stod(f[heading]), toward_centre(frame, la, lo)), 0.01);
    }
    if (std::stod(f[pitch]) == fixture::kObliquePitch) {
      ++tilted;
      EXPECT_DOUBLE_EQ(std::stod(f[heading]), fixture::kObliqueHeading);
    }
    if (std::stoi(f[gmode]) == 1) {  // focus POI
      ++poi;
      EXPECT_TRUE(near_roi(frame, std::stod(f[plat]), std::stod(f[plon])));
    } else {
      EXPECT_EQ(std::stoi(f[gmode]), 2);
      EXPECT_EQ(std::stod(f[plat]), 0.0);
    }
  }
  EXPECT_GE(orbit, 13);
  EXPECT_EQ(tilted, 2);  // the pass's two waypoints reach it at -45
  EXPECT_GE(poi, 2);
}

TEST(AttitudeExports, GeojsonCarriesEachPartsAttitude) {
  const Plan plan = fixture::attitude_plan();
  const Artifacts out = export_artifacts(plan, {"geojson"});
  const json doc = json::parse(bytes_of(out, "export/alpha.geojson"));
  EXPECT_TRUE(validate_geojson(doc).empty());
  int with = 0;
  for (const json& f : doc["features"]) {
    if (!f["properties"].contains("part")) continue;
    const int part = f["properties"]["part"].get<int>();
    const bool has = f["properties"].contains("attitude");
    EXPECT_EQ(has, !plan.uavs[0].parts[static_cast<std::size_t>(part)].attitude.empty()) << part;
    if (!has) continue;
    ++with;
    const json& a = f["properties"]["attitude"];
    if (part == 1) {
      EXPECT_EQ(a["altitude_m"].get<double>(), fixture::kOrbitAltitude);
      EXPECT_EQ(a["heading_deg"].size(), f["geometry"]["coordinates"].size());
    }
    if (part == 3) {
      EXPECT_EQ(a["gimbal_pitch_deg"].get<double>(), fixture::kObliquePitch);
    }
    if (part == 5) {
      EXPECT_EQ(a["roi"].size(), 2u);
    }
    if (part == 7) {
      EXPECT_EQ(a["trigger_distance_m"].get<double>(), fixture::kHighTrigger);
    }
  }
  EXPECT_EQ(with, 4);
}

TEST(AttitudeExports, AutopilotsAcceptTheMissions) {
  const Plan plan = fixture::attitude_plan();
  // PX4 (the default) and ArduPilot: the exports' own checks (check_consumers) would refuse
  for (const char* ap : {"px4", "ardupilot"}) {
    ExportOptions opt;
    opt.autopilot = ap;
    EXPECT_NO_THROW((void)export_artifacts(plan, {"qgc", "wpl"}, opt)) << ap;
  }
  const LonLat home = plan.mission.uavs[0].start_resolved;
  // the PX4 mission: heading in NAV_WAYPOINT param4, no CONDITION_YAW; both autopilots store every item
  const auto px4 = mission_items(plan, 0);
  for (const auto& p : autopilot::px4_problems(px4, home, 0.0)) EXPECT_FALSE(p.fatal) << p.message;
  for (const auto& p : autopilot::ardupilot_problems(px4)) EXPECT_FALSE(p.fatal) << p.message;
  // the ArduPilot mission with CONDITION_YAW: every MISSION_ITEM_INT accepted (AP_Mission's conversion)
  const auto ap = ardupilot_mission_items(plan, 0);
  for (const auto& p : autopilot::ardupilot_problems(ap)) EXPECT_FALSE(p.fatal) << p.message;
  const auto wire = mavlink::to_mission_items(ap, home);
  int yaw = 0;
  for (const auto& m : wire) {
    EXPECT_EQ(autopilot::ardupilot_item_result(m), mavlink::kMissionAccepted) << m.command;
    yaw += m.command == kConditionYaw ? 1 : 0;
  }
  EXPECT_GT(yaw, 0);
  // PX4 does refuse CONDITION_YAW, which is why the PX4 export has none
  bool refused = false;
  for (const auto& p : autopilot::px4_problems(ap, home, 0.0)) refused = refused || p.fatal;
  EXPECT_TRUE(refused);
}

TEST(AttitudeRules, Px4RefusesRoiOutsideAGlobalFrameOrWithAnotherMode) {
  const Plan plan = fixture::attitude_plan();
  const LonLat home = plan.mission.uavs[0].start_resolved;
  auto items = mission_items(plan, 0);
  std::size_t roi = items.size();
  for (std::size_t k = 0; k < items.size(); ++k)
    if (items[k].command == kDoSetRoi && items[k].param1 == 3.0f) roi = k;
  ASSERT_LT(roi, items.size());
  auto fatal = [&](const std::vector<MissionItem>& its) {
    for (const auto& p : autopilot::px4_problems(its, home, 0.0))
      if (p.fatal && p.item == static_cast<long>(roi)) return true;
    return false;
  };
  EXPECT_FALSE(fatal(items));
  auto bad = items;
  bad[roi].param1 = 2.0f;  // MAV_ROI_WPINDEX: PX4's parser answers MAV_MISSION_INVALID_PARAM1
  EXPECT_TRUE(fatal(bad));
  bad = items;
  bad[roi].frame = kFrameMission;
  EXPECT_TRUE(fatal(bad));
}

TEST(AttitudeExports, KmlPointsCarryHeadingGimbalAndRoi) {
  const Plan plan = fixture::attitude_plan();
  const geodesy::LocalFrame frame(plan.origin);
  const Artifacts out = export_artifacts(plan, {"kml"});
  pugi::xml_document doc;
  ASSERT_TRUE(doc.load_string(bytes_of(out, "export/alpha.kml").c_str()));
  int orbit = 0, headed = 0, roi = 0;
  for (const auto& m : doc.select_nodes("/kml/Document/Folder/Placemark")) {
    const pugi::xml_node n = m.node();
    const auto c = split(n.select_node("Point/coordinates").node().text().get(), ',');
    ASSERT_EQ(c.size(), 3u);
    std::map<std::string, std::string> data;
    for (const auto& d : n.select_nodes("ExtendedData/Data"))
      data[d.node().attribute("name").value()] = d.node().child("value").text().get();
    if (data.count("heading_deg") != 0) {
      ++headed;
      EXPECT_DOUBLE_EQ(n.select_node("Style/IconStyle/heading").node().text().as_double(),
                       std::stod(data["heading_deg"]));
    }
    if (std::stod(c[2]) == fixture::kOrbitAltitude) {
      ++orbit;
      EXPECT_LT(heading_error(std::stod(data.at("heading_deg")),
                              toward_centre(frame, std::stod(c[1]), std::stod(c[0]))),
                0.01);
    }
    if (data.count("roi") != 0) {
      ++roi;
      const auto r = split(data["roi"], ',');
      EXPECT_TRUE(near_roi(frame, std::stod(r.at(1)), std::stod(r.at(0))));  // "lon,lat,alt" as in KML
    }
    if (data.count("gimbal_pitch_deg") != 0 &&
        std::stod(data["gimbal_pitch_deg"]) == fixture::kObliquePitch) {
      EXPECT_DOUBLE_EQ(std::stod(data.at("heading_deg")), fixture::kObliqueHeading);
    }
  }
  EXPECT_GE(orbit, 13);
  EXPECT_GE(headed, 13 + 2);
  EXPECT_GE(roi, 2);
  // bravo has no attitude: its KML has no attitude folder
  pugi::xml_document b;
  ASSERT_TRUE(b.load_string(bytes_of(out, "export/bravo.kml").c_str()));
  EXPECT_TRUE(b.select_nodes("/kml/Document/Folder").empty());
}
