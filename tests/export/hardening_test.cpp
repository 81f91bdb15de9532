// The export hardening items, one test (or a few) each: outputs as bytes, the .plan geofence PX4
// accepts and the yaw convention, the DJI WPML required elements, the consumers' limits, XML
// escaping, idle UAVs and file names from the UAV ids.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <pugixml.hpp>
#include <set>

#include "autopilot/fence.hpp"
#include "export/check.hpp"
#include "export/export.hpp"
#include "export/fixture.hpp"
#include "export/xml.hpp"
#include "io/plan_io.hpp"
#include "mavlink/mission_protocol.hpp"
#include "uavcover/error.hpp"

using namespace uavcover;
using namespace uavcover::exporting;
using namespace uavcover::autopilot;
using namespace uavcover::waypoints;
namespace fs = std::filesystem;
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

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

}  // namespace

// ---- Part A: outputs as bytes ----

TEST(Artifacts, NamesMediaTypesAndInMemoryArchives) {
  const Plan plan = fixture::two_uav_plan(true);
  ExportOptions opt;
  opt.kmz = true;
  opt.trajectory.dt = 1.0;
  const Artifacts a = export_artifacts(plan, known_formats(), opt);
  const std::map<std::string, std::string> expected{{".geojson", "application/geo+json"},
                                                    {".plan", "application/json"},
                                                    {".waypoints", "text/plain"},
                                                    {".kml", "application/vnd.google-earth.kml+xml"},
                                                    {".kmz", "application/vnd.google-earth.kmz"},
                                                    {".wpml.kmz", "application/vnd.google-earth.kmz"},
                                                    {".litchi.csv", "text/csv"},
                                                    {".csv", "text/csv"},
                                                    {".trajectory.png", "image/png"}};
  for (const std::string id : {"alpha", "bravo"}) {
    for (const auto& [ext, type] : expected) {
      const Artifact* f = check::find(a, "export/" + id + ext);
      ASSERT_NE(f, nullptr) << id << ext;
      EXPECT_EQ(f->media_type, type) << id << ext;
      EXPECT_FALSE(f->bytes.empty());
    }
    ASSERT_NE(check::find(a, "trajectory/" + id + ".csv"), nullptr);
    // the KMZ and DJI KMZ are real ZIP archives built in memory
    EXPECT_EQ(check::unzip_bytes(check::find(a, "export/" + id + ".kmz")->bytes).at("doc.kml"),
              check::find(a, "export/" + id + ".kml")->bytes);
    EXPECT_EQ(check::unzip_bytes(check::find(a, "export/" + id + ".wpml.kmz")->bytes).size(), 2u);
  }
  EXPECT_EQ(a.size(), 2u * 10u);
  // the same plan gives the same bytes (fixed ZIP entry times)
  const Artifacts again = export_artifacts(plan, known_formats(), opt);
  ASSERT_EQ(again.size(), a.size());
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(again[k].bytes, a[k].bytes) << a[k].name;
}

TEST(Artifacts, ARefusedExportWritesNothing) {
  // a tampered plan folder: the second UAV's transit crosses the no-fly zone. Every format of the
  // first UAV would be fine, yet nothing at all may be written (no partial folder, no .tmp file).
  Plan plan = fixture::two_uav_plan();
  const geodesy::LocalFrame frame(plan.origin);
  plan.uavs[1].parts.front() =
      fixture::make_part(frame, PartKind::Transit, {{120, -60}, {70, -20}, {90, -40}});
  const fs::path dir = fs::temp_directory_path() / ("uavcover_refused_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string msg = message_of([&] { fixture::export_to(plan, known_formats(), dir); });
  EXPECT_NE(msg.find("no_fly_zones: uav 'bravo'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("no-fly zone 0"), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(dir / "export"));
  EXPECT_FALSE(fs::exists(dir / "trajectory"));
  fs::remove_all(dir);
}

TEST(Artifacts, LibraryErrorsNameFieldsNotFlags) {
  const Plan plan = fixture::two_uav_plan();
  try {
    export_artifacts(plan, {"qgc,x"});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "formats");
    EXPECT_EQ(std::string(e.what()).find("--"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("unknown format \"x\" (known: geojson"), std::string::npos);
  }
}

// ---- 5. QGroundControl .plan geofence and yaw ----

TEST(QgcGeofence, EveryItemHomeAndLegPassPx4sFenceCheck) {
  for (const bool camera : {false, true}) {
    Plan plan = fixture::two_uav_plan(camera);
    // coverage mode: alpha's loop reaches 15 m beyond the area's west edge (x = -100)
    const geodesy::LocalFrame frame(plan.origin);
    plan.mission.mode = Mode::Coverage;
    plan.uavs[0].parts[1] =
        fixture::make_part(frame, PartKind::Coverage,
                           {{-90, -40}, {-10, -40}, {-10, 0}, {-115, 0}, {-115, 40}, {-90, 40}, {-90, -40}});
    const Artifacts a = export_artifacts(plan, {"qgc"});
    for (const std::string id : {"alpha", "bravo"}) {
      const json doc = json::parse(check::find(a, "export/" + id + ".plan")->bytes);
      EXPECT_EQ(check::px4_fence_failure(doc), "") << id;
      // home and the take-off lie outside the area, and the area alone would have failed
      json area_only = doc;
      area_only["geoFence"]["polygons"] = json::array();
      json ring = json::array();
      for (std::size_t k = 0; k + 1 < plan.mission.area[0][0].size(); ++k)
        ring.push_back({plan.mission.area[0][0][k].lat, plan.mission.area[0][0][k].lon});
      area_only["geoFence"]["polygons"].push_back({{"inclusion", true}, {"polygon", ring}, {"version", 1}});
      EXPECT_NE(check::px4_fence_failure(area_only), "") << id;
      // the fence keeps at least ~the margin around home
      const auto& poly = doc["geoFence"]["polygons"][0]["polygon"];
      const LonLat home = plan.mission.uavs[id == "alpha" ? 0 : 1].start_resolved;
      const LonLat near = frame.to_wgs84([&] {
        Point h = frame.to_local(home);
        return Point(h.x() + (id == "alpha" ? -12.0 : 12.0), h.y() - 12.0);  // 17 m out
      }());
      EXPECT_TRUE(check::px4_inside_polygon(poly, near.lat, near.lon)) << id;
      EXPECT_LE(poly.size() + plan.mission.no_fly_zones[0][0].size() - 1, kPx4MaxFenceVertices);
    }
  }
}

TEST(QgcGeofence, AFlightIntoANoFlyZoneIsRefused) {
  Plan plan = fixture::two_uav_plan();
  const geodesy::LocalFrame frame(plan.origin);
  // a waypoint inside the zone, and (separately) a leg through it
  Plan inside = plan;
  inside.uavs[1].parts.front() =
      fixture::make_part(frame, PartKind::Transit, {{120, -60}, {70, -20}, {90, -40}});
  EXPECT_NE(message_of([&] { export_artifacts(inside, {"qgc"}); }).find("lies inside no-fly zone 0"),
            std::string::npos);
  Plan through = plan;
  through.uavs[1].parts.front() =
      fixture::make_part(frame, PartKind::Transit, {{120, -60}, {50, -20}, {90, -40}});
  through.uavs[1].parts.front().wgs84[1] = frame.to_wgs84({50, -20});
  EXPECT_NE(message_of([&] { export_artifacts(through, {"csv"}); }).find("crosses no-fly zone 0"),
            std::string::npos);
  EXPECT_FALSE(no_fly_violations(through, 1, mission_items(through, 1)).empty());
  EXPECT_TRUE(no_fly_violations(plan, 1, mission_items(plan, 1)).empty());
}

// The no-fly check projects back to lon/lat only the points of a leg inside a zone's padded box in the
// plan's frame: its answers are those of testing every point of every leg (1 m apart), on legs that
// pass a zone's corners and edges by less than a metre, cross it, or stay far from it.
TEST(QgcGeofence, TheIndexedNoFlyCheckAnswersAsTestingEveryPoint) {
  const Plan plan = fixture::two_uav_plan();
  const geodesy::LocalFrame frame(plan.origin);
  const auto& zones = plan.mission.no_fly_zones;
  auto reference = [&](const Plan& p, std::size_t i, const std::vector<MissionItem>& items) {
    auto zone_of = [&](LonLat q) {
      for (std::size_t z = 0; z < zones.size(); ++z)
        if (inside_ring(q, zones[z].front())) return static_cast<int>(z);
      return -1;
    };
    std::vector<LonLat> places{p.mission.uavs[i].start_resolved};
    for (const auto& it : items)
      if (it.command == kNavWaypoint || it.command == kNavTakeoff || it.command == kNavLand)
        places.push_back({it.lon, it.lat});
    places.push_back(p.mission.uavs[i].start_resolved);
    std::size_t found = 0;
    for (std::size_t k = 0; k < places.size(); ++k) {
      if (zone_of(places[k]) >= 0) {
        ++found;
        continue;
      }
      if (k == 0) continue;
      const Point a = frame.to_local(places[k - 1]), b = frame.to_local(places[k]);
      const int steps = static_cast<int>(std::ceil(std::hypot(b.x() - a.x(), b.y() - a.y())));
      for (int s = 1; s < steps; ++s) {
        const double t = static_cast<double>(s) / steps;
        if (zone_of(frame.to_wgs84(Point(a.x() + t * (b.x() - a.x()), a.y() + t * (b.y() - a.y())))) >= 0) {
          ++found;
          break;
        }
      }
    }
    return found;
  };
  std::size_t crossing = 0, clear = 0;
  // zone 0 is x 60..80, y -30..-10 in the plan's frame; the leg (120, -60) -> v -> (90, -40)
  for (double x = 20; x <= 130; x += 3.7)
    for (double y = -70; y <= 30; y += 3.7)
      for (const double off : {0.0, 0.4}) {
        Plan p = plan;
        const Point v(x + off, y - off);
        p.uavs[1].parts.front() = fixture::make_part(frame, PartKind::Transit, {{120, -60}, v, {90, -40}});
        p.uavs[1].parts.front().wgs84[1] = frame.to_wgs84(v);
        const auto items = mission_items(p, 1);
        const std::size_t expected = reference(p, 1, items);
        EXPECT_EQ(no_fly_violations(p, 1, items).size(), expected) << x << " " << y << " " << off;
        (expected > 0 ? crossing : clear) += 1;
      }
  EXPECT_GT(crossing, 50u);
  EXPECT_GT(clear, 50u);
}

TEST(QgcGeofence, YawKeepsTheHeadingInEveryFormat) {
  const Plan plan = fixture::two_uav_plan();
  const auto items = mission_items(plan, 0);
  const Artifacts a = export_artifacts(plan, {"qgc,wpl,csv"});
  const json doc = json::parse(check::find(a, "export/alpha.plan")->bytes);
  const auto wpl = split(check::find(a, "export/alpha.waypoints")->bytes, '\n');
  const auto csv = split(check::find(a, "export/alpha.csv")->bytes, '\n');
  const auto mav = mavlink::to_mission_items(items, plan.mission.uavs[0].start_resolved);
  std::size_t positioned = 0;
  for (std::size_t k = 0; k < items.size(); ++k) {
    const int cmd = items[k].command;
    const std::string p4_wpl = split(wpl.at(k + 2), '\t').at(7);
    const std::string p4_csv = split(csv.at(k + 1), ',').at(10);
    if (cmd == kNavWaypoint || cmd == kNavTakeoff || cmd == kNavLand) {
      ++positioned;
      EXPECT_TRUE(std::isnan(items[k].param4));
      EXPECT_TRUE(doc["mission"]["items"][k]["params"][3].is_null());
      EXPECT_EQ(p4_wpl, "NaN");
      EXPECT_EQ(p4_csv, "NaN");
      EXPECT_TRUE(std::isnan(mav[k + 1].param4));
    } else {
      EXPECT_FALSE(std::isnan(items[k].param4));  // ArduPilot refuses NaN in other commands
      EXPECT_FALSE(doc["mission"]["items"][k]["params"][3].is_null());
      EXPECT_EQ(std::stod(p4_wpl), items[k].param4);
    }
  }
  EXPECT_GT(positioned, 5u);
}

// ---- 6. DJI WPML required elements ----

TEST(DjiWpml, RequiredElementsArePresentAndInRange) {
  const Plan plan = fixture::two_uav_plan(true);
  const auto files = dji_wpml(plan, 0);
  for (const char* name : {"wpmz/template.kml", "wpmz/waylines.wpml"}) {
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_string(files.at(name).c_str())) << name;
    const bool tpl = std::string(name).ends_with(".kml");
    auto node = [&](const char* path) { return doc.select_node(path).node(); };
    auto value = [&](const char* path) {
      const auto n = node(path);
      EXPECT_TRUE(n) << name << " " << path;
      return n.text().as_double();
    };
    const char* mc = "/kml/Document/wpml:missionConfig/";
    EXPECT_GE(value((std::string(mc) + "wpml:takeOffSecurityHeight").c_str()), 1.2);
    EXPECT_LE(value((std::string(mc) + "wpml:takeOffSecurityHeight").c_str()), 1500);
    const double rth = value((std::string(mc) + "wpml:globalRTHHeight").c_str());
    EXPECT_GT(rth, plan.mission.altitude_m);
    EXPECT_LE(rth, 1500);
    const double transit = value((std::string(mc) + "wpml:globalTransitionalSpeed").c_str());
    EXPECT_GT(transit, 0);
    EXPECT_LE(transit, 15);
    EXPECT_EQ(value((std::string(mc) + "wpml:droneInfo/wpml:droneEnumValue").c_str()), 77);
    EXPECT_EQ(value((std::string(mc) + "wpml:payloadInfo/wpml:payloadEnumValue").c_str()), 66);  // M3E camera
    EXPECT_EQ(value((std::string(mc) + "wpml:payloadInfo/wpml:payloadPositionIndex").c_str()), 0);
    const double speed = value("/kml/Document/Folder/wpml:autoFlightSpeed");
    EXPECT_GT(speed, 0);
    EXPECT_LE(speed, 15);
    if (tpl) {
      const std::string pitch_mode = node("/kml/Document/Folder/wpml:gimbalPitchMode").text().get();
      EXPECT_TRUE(pitch_mode == "manual" || pitch_mode == "usePointSetting") << pitch_mode;
      const std::string path_mode =
          node("/kml/Document/Folder/wpml:globalWaypointHeadingParam/wpml:waypointHeadingPathMode")
              .text()
              .get();
      EXPECT_TRUE(path_mode == "clockwise" || path_mode == "counterClockwise" || path_mode == "followBadArc");
    }
    std::size_t marks = 0, photos = 0;
    for (const auto& m : doc.select_nodes("/kml/Document/Folder/Placemark")) {
      const auto p = m.node();
      ++marks;
      if (tpl) {
        ASSERT_STREQ(p.child("wpml:useGlobalHeight").text().get(), "0");
        ASSERT_TRUE(p.child("wpml:ellipsoidHeight")) << "Placemark " << marks;
        ASSERT_TRUE(p.child("wpml:height"));
        const auto pitch = p.child("wpml:gimbalPitchAngle");
        ASSERT_TRUE(pitch);  // required by gimbalPitchMode usePointSetting
        EXPECT_GE(pitch.text().as_double(), -90);
        EXPECT_LE(pitch.text().as_double(), 35);
      } else {
        const std::string mode =
            p.select_node("wpml:waypointHeadingParam/wpml:waypointHeadingPathMode").node().text().get();
        EXPECT_EQ(mode, "followBadArc");
      }
      for (const auto& act : p.select_nodes("wpml:actionGroup/wpml:action")) {
        const auto a = act.node();
        if (std::string(a.child("wpml:actionActuatorFunc").text().get()) != "takePhoto") continue;
        ++photos;
        const auto param = a.child("wpml:actionActuatorFuncParam");
        EXPECT_TRUE(param.child("wpml:payloadPositionIndex"));
        EXPECT_STREQ(param.child("wpml:fileSuffix").text().get(), "alpha");
        const std::string global = param.child("wpml:useGlobalPayloadLensIndex").text().get();
        EXPECT_TRUE(global == "0" || global == "1");
        EXPECT_TRUE(param.child("wpml:payloadLensIndex"));
      }
    }
    EXPECT_GT(marks, 3u);
    // 6 legs: a distance group each, and a photo at the last leg's end (the other ends are the next
    // leg's shared corner, shot by its distance group; issue 34)
    EXPECT_EQ(photos, 7u);
  }
  // a drone without a known camera needs the payload given
  ExportOptions other;
  other.dji_drone_enum = 60;  // M300 RTK: payloads are exchangeable
  EXPECT_NE(message_of([&] { dji_wpml(plan, 0, other); }).find("dji_payload_enum"), std::string::npos);
  other.dji_payload_enum = 42;
  EXPECT_NE(dji_wpml(plan, 0, other).at("wpmz/template.kml").find("<wpml:payloadEnumValue>42<"),
            std::string::npos);
}

// ---- 7. consumer limits ----

TEST(Limits, SpeedsAreClampedWithAWarning) {
  Plan plan = fixture::two_uav_plan(true);
  plan.mission.uavs[0].speed_mps = 30;
  std::vector<std::string> warnings;
  ExportOptions opt;
  opt.warnings = &warnings;
  const Artifacts a = export_artifacts(plan, {"dji,litchi,qgc"}, opt);
  const auto dji = check::unzip_bytes(check::find(a, "export/alpha.wpml.kmz")->bytes);
  EXPECT_NE(dji.at("wpmz/waylines.wpml").find("<wpml:waypointSpeed>15</wpml:waypointSpeed>"),
            std::string::npos);
  EXPECT_EQ(dji.at("wpmz/waylines.wpml").find("<wpml:waypointSpeed>30<"), std::string::npos);
  const auto rows = split(check::find(a, "export/alpha.litchi.csv")->bytes, '\n');
  EXPECT_EQ(split(rows.at(1), ',').at(39), "15");
  std::size_t clamped = 0, px4 = 0;
  for (const auto& w : warnings) {
    clamped += w.find("uav 'alpha': speed 30 m/s clamped to 15 m/s") != std::string::npos;
    px4 += w.find("MPC_XY_VEL_MAX") != std::string::npos;
  }
  EXPECT_EQ(clamped, 2u);  // DJI and Litchi
  EXPECT_EQ(px4, 1u);      // PX4 caps it itself: a warning only
}

TEST(Limits, TransitionAltitudesStayUnderTheCeiling) {
  // mission altitude 40 m, step 10 m, 10 UAVs: 60..150 m; compressed to fit 120 m with >= 5 m steps
  std::vector<std::string> warnings;
  AltitudeOptions o;
  const AltitudeOptions r = resolve_altitudes(o, 10, 40, &warnings);
  EXPECT_DOUBLE_EQ(r.transition_base_m, 60);
  EXPECT_LE(transition_altitude(r, 9, 40), 120.0);
  EXPECT_GE(r.transition_step_m, 5.0);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("step compressed from 10 m"), std::string::npos) << warnings[0];
  // resolving again changes nothing
  EXPECT_DOUBLE_EQ(resolve_altitudes(r, 10, 40).transition_step_m, r.transition_step_m);
  // 200 UAVs cannot be separated under 120 m: the message says what to change
  const std::string msg = message_of([&] { resolve_altitudes(o, 200, 40); });
  EXPECT_NE(msg.find("altitude.transition_ceiling_m"), std::string::npos) << msg;
  for (const char* hint :
       {"fewer UAVs", "smaller transition step", "lower mission altitude", "higher ceiling"})
    EXPECT_NE(msg.find(hint), std::string::npos) << hint << ": " << msg;
  // a stricter minimum separation refuses the 10 UAVs too; no ceiling keeps the old altitudes
  o.min_vertical_separation_m = 10;
  EXPECT_THROW(resolve_altitudes(o, 10, 40), InputError);
  o.transition_ceiling_m = 0;
  EXPECT_DOUBLE_EQ(transition_altitude(resolve_altitudes(o, 200, 40), 199, 40), 60 + 199 * 10);
  // a mission altitude that leaves no room under the ceiling
  EXPECT_NE(
      message_of([&] { resolve_altitudes(AltitudeOptions{}, 2, 110); }).find("lower the mission altitude"),
      std::string::npos);
  // the exports fly the resolved altitudes: mission items, and through them every format
  Plan plan = fixture::two_uav_plan();
  AltitudeOptions tight;
  tight.transition_ceiling_m = 65;  // base 60, step 10 -> 5
  const auto items = mission_items(plan, 1, tight);
  EXPECT_FLOAT_EQ(items.front().alt, 65.0F);
}

TEST(Limits, HeightsBeyondDjiAndLitchiAreRefused) {
  const Plan plan = fixture::two_uav_plan();
  ExportOptions opt;
  opt.altitude.transition_ceiling_m = 0;
  opt.altitude.transition_base_m = 600;
  for (const char* f : {"dji", "litchi"}) {
    const std::string msg = message_of([&] { export_artifacts(plan, {f}, opt); });
    EXPECT_NE(msg.find("accepts at most 500 m"), std::string::npos) << f << ": " << msg;
  }
  EXPECT_NO_THROW(export_artifacts(plan, {"qgc,wpl,kml,csv"}, opt));  // MAVLink has no such limit
}

// ---- 8. XML injection ----

TEST(XmlEscape, ControlCharactersAndBadUtf8NeverBreakTheXml) {
  EXPECT_EQ(xml_escape("a&b<c>\"'"), "a&amp;b&lt;c&gt;&quot;&apos;");
  EXPECT_EQ(xml_escape(std::string("x\x01y\0z", 5)), "x\xEF\xBF\xBDy\xEF\xBF\xBDz");
  EXPECT_EQ(xml_escape("t\tn\nr\r"), "t&#9;n&#10;r&#13;");
  EXPECT_FALSE(check::xml_chars_valid("a\x01"));  // the checker itself catches what pugixml lets through
  EXPECT_FALSE(check::xml_chars_valid("\xFF"));
  EXPECT_EQ(xml_escape("\xC3\xA9\xE2\x82\xAC\xF0\x9F\x9A\x81"),
            "\xC3\xA9\xE2\x82\xAC\xF0\x9F\x9A\x81");                              // é € 🚁
  EXPECT_EQ(xml_escape("\xFF\xC3"), "\xEF\xBF\xBD\xEF\xBF\xBD");                  // not UTF-8
  EXPECT_EQ(xml_escape("\xED\xA0\x80"), "\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD");  // a surrogate
  EXPECT_EQ(xml_escape("\xEF\xBF\xBE"), "\xEF\xBF\xBD");                          // U+FFFE
  Plan plan = fixture::two_uav_plan(true);
  std::string hostile = "</name><x>&amp;";
  for (char c = 0; c < 0x20; ++c) hostile += c;
  hostile += "\xFF]]>";
  plan.mission.name = hostile;
  plan.mission.altitude_source = hostile;
  ExportOptions opt;
  opt.kmz = true;
  const Artifacts a = export_artifacts(plan, {"kml,dji,qgc,geojson"}, opt);
  for (const auto& f : a) {
    if (f.name.ends_with(".kml")) {
      pugi::xml_document doc;
      ASSERT_TRUE(doc.load_string(f.bytes.c_str())) << f.name;
      EXPECT_TRUE(check::xml_chars_valid(f.bytes)) << f.name;
      const std::string name = doc.select_node("/kml/Document/name").node().text().get();
      EXPECT_EQ(name.rfind("</name><x>&amp;\xEF\xBF\xBD", 0), 0u) << name;  // the text round-trips, escaped
      EXPECT_NE(name.find("\t\n"), std::string::npos);
      EXPECT_EQ(doc.select_nodes("//x").size(), 0u);
    } else if (f.name.ends_with(".kmz")) {
      for (const auto& [entry, text] : check::unzip_bytes(f.bytes)) {
        pugi::xml_document doc;
        EXPECT_TRUE(doc.load_string(text.c_str())) << entry;
        EXPECT_TRUE(check::xml_chars_valid(text)) << entry;
      }
    } else {
      EXPECT_TRUE(json::accept(f.bytes)) << f.name;
    }
  }
}

// ---- 9. idle UAVs ----

TEST(IdleUavs, AreSkippedWithAWarning) {
  Plan plan = fixture::two_uav_plan(true);
  plan.uavs[1].parts = {plan.uavs[1].parts.front()};  // bravo: transit only, no coverage
  std::vector<std::string> warnings;
  ExportOptions opt;
  opt.warnings = &warnings;
  opt.trajectory.dt = 1.0;
  const Artifacts a = export_artifacts(plan, known_formats(), opt);
  for (const auto& f : a) EXPECT_EQ(f.name.find("bravo"), std::string::npos) << f.name;
  EXPECT_NE(check::find(a, "export/alpha.litchi.csv"), nullptr);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "uav 'bravo': no coverage parts, nothing exported for it");
  plan.uavs[0].parts.clear();
  EXPECT_NE(message_of([&] { export_artifacts(plan, {"qgc"}); }).find("no UAV has coverage parts"),
            std::string::npos);
}

// ---- ids unchanged in file names ----

TEST(FileNames, UseTheIdUnchanged) {
  Plan plan = fixture::two_uav_plan();
  plan.uavs[0].id = plan.mission.uavs[0].id = "Alpha.1_x-Y";
  plan.uavs[1].id = plan.mission.uavs[1].id = "_b";
  ExportOptions opt;
  opt.trajectory.dt = 1.0;
  const Artifacts a = export_artifacts(plan, known_formats(), opt);
  for (const char* name : {"export/Alpha.1_x-Y.plan", "export/Alpha.1_x-Y.wpml.kmz", "export/_b.litchi.csv",
                           "trajectory/Alpha.1_x-Y.csv", "export/_b.geojson"})
    EXPECT_NE(check::find(a, name), nullptr) << name;
  // two ids naming one file are refused rather than one export overwriting the other
  Plan clash = fixture::two_uav_plan();
  clash.uavs[1].id = clash.mission.uavs[1].id = "alpha.wpml";
  opt.kmz = true;
  EXPECT_NE(message_of([&] { export_artifacts(clash, {"kml,dji"}, opt); }).find("export/alpha.wpml.kmz"),
            std::string::npos);
  // ids that are not file names (a tampered plan folder)
  for (const std::string& bad :
       std::vector<std::string>{"../x", "a/b", ".hidden", "", "sp ace", std::string(65, 'a')}) {
    Plan p = fixture::two_uav_plan();
    p.uavs[0].id = p.mission.uavs[0].id = bad;
    EXPECT_NE(message_of([&] { export_artifacts(p, {"csv"}); }).find("uavs[0].id"), std::string::npos) << bad;
  }
}
