// Round trips: every export is parsed back with an independent reader (nlohmann json, pugixml,
// libzip, plain text splitting) and compared with the plan's mission items.
#include <gtest/gtest.h>
#include <zip.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <pugixml.hpp>
#include <sstream>

#include "export/check.hpp"
#include "export/export.hpp"
#include "export/fixture.hpp"
#include "trajectory/trajectory.hpp"
#include "uavcover/error.hpp"

using namespace uavcover;
using namespace uavcover::exporting;
using namespace uavcover::waypoints;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

fs::path temp_dir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("uavcover_export_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

std::vector<std::string> lines(const std::string& s) {
  auto out = split(s, '\n');
  if (!out.empty() && out.back().empty()) out.pop_back();
  return out;
}

/// All entries of a ZIP archive, read with libzip.
std::map<std::string, std::string> unzip(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  EXPECT_TRUE(in) << p;
  std::ostringstream ss;
  ss << in.rdbuf();
  return check::unzip_bytes(ss.str());
}

std::vector<MissionItem> positioned(const std::vector<MissionItem>& items) {
  std::vector<MissionItem> out;
  for (const auto& it : items)
    if (it.command == kNavWaypoint || it.command == kNavTakeoff || it.command == kNavLand) out.push_back(it);
  return out;
}

std::vector<MissionItem> waypoints_only(const std::vector<MissionItem>& items) {
  std::vector<MissionItem> out;
  for (const auto& it : items)
    if (it.command == kNavWaypoint) out.push_back(it);
  return out;
}

/// "lon,lat[,alt] lon,lat[,alt] ..." -> triples
std::vector<std::array<double, 3>> kml_coords(const std::string& text) {
  std::vector<std::array<double, 3>> out;
  std::istringstream ss(text);
  std::string tok;
  while (ss >> tok) {
    const auto f = split(tok, ',');
    out.push_back({std::stod(f.at(0)), std::stod(f.at(1)), f.size() > 2 ? std::stod(f[2]) : 0.0});
  }
  return out;
}

constexpr double kDeg = 1e-9;  // coordinate tolerance in degrees (formats print 8-9 decimals)

}  // namespace

TEST(Formats, QgcPlanRoundTrip) {
  const Plan plan = fixture::two_uav_plan(true);
  ExportOptions opt;
  opt.qgc_firmware_type = 3;
  opt.qgc_vehicle_type = 2;
  const fs::path dir = temp_dir("qgc");
  const auto files = fixture::export_to(plan, {"qgc"}, dir, opt);
  ASSERT_EQ(files.size(), 2u);
  for (std::size_t u = 0; u < 2; ++u) {
    const json doc = json::parse(slurp(dir / "export" / (plan.uavs[u].id + ".plan")));
    EXPECT_EQ(doc["fileType"], "Plan");
    EXPECT_EQ(doc["version"], 1);
    EXPECT_EQ(doc["mission"]["firmwareType"], 3);
    EXPECT_EQ(doc["mission"]["vehicleType"], 2);
    const LonLat home = plan.mission.uavs[u].start_resolved;
    const json& hp = doc["mission"]["plannedHomePosition"];
    ASSERT_EQ(hp.size(), 3u);
    EXPECT_NEAR(hp[0].get<double>(), home.lat, kDeg);  // QGC order: lat, lon, alt
    EXPECT_NEAR(hp[1].get<double>(), home.lon, kDeg);
    const auto items = mission_items(plan, u, opt.altitude);
    const json& ji = doc["mission"]["items"];
    ASSERT_EQ(ji.size(), items.size());
    int takeoff = 0, wp = 0, speed = 0, cam = 0, rtl = 0;
    for (std::size_t k = 0; k < items.size(); ++k) {
      EXPECT_EQ(ji[k]["type"], "SimpleItem");
      EXPECT_EQ(ji[k]["command"].get<int>(), items[k].command);
      EXPECT_EQ(ji[k]["frame"].get<int>(), items[k].frame);
      EXPECT_EQ(ji[k]["doJumpId"].get<int>(), static_cast<int>(k) + 1);
      ASSERT_EQ(ji[k]["params"].size(), 7u);
      const int cmd = items[k].command;
      takeoff += cmd == 22;
      wp += cmd == 16;
      speed += cmd == 178;
      cam += cmd == 206;
      rtl += cmd == 20;
      if (cmd == 16 || cmd == 22) {
        EXPECT_EQ(ji[k]["frame"], 3);
        EXPECT_NEAR(ji[k]["params"][4].get<double>(), items[k].lat, 1e-12);
        EXPECT_NEAR(ji[k]["params"][5].get<double>(), items[k].lon, 1e-12);
        EXPECT_NEAR(ji[k]["params"][6].get<double>(), items[k].alt, 1e-6);
        EXPECT_TRUE(ji[k]["params"][3].is_null());  // yaw: keep the vehicle's heading mode
      } else {
        EXPECT_NEAR(ji[k]["params"][0].get<double>(), items[k].param1, 1e-6);
      }
    }
    EXPECT_EQ(takeoff, 1);
    EXPECT_EQ(speed, 1);
    EXPECT_EQ(cam, 12);  // each of the loop's 6 legs: start (d) and stop (0), docs/photogrammetry.md
    EXPECT_EQ(rtl, 1);
    EXPECT_EQ(wp, static_cast<int>(waypoints_only(items).size()));
    // geofence: one inclusion polygon around everything flown, the no-fly zone as exclusion,
    // [lat, lon] vertices, not closed (the PX4 check of every item is in geofence_test.cpp)
    const json& polys = doc["geoFence"]["polygons"];
    ASSERT_EQ(polys.size(), 2u);
    EXPECT_TRUE(polys[0]["inclusion"].get<bool>());
    EXPECT_FALSE(polys[1]["inclusion"].get<bool>());
    EXPECT_GE(polys[0]["polygon"].size(), 3u);
    EXPECT_LE(polys[0]["polygon"].size(), 16u);
    const GeoRing& nfz = plan.mission.no_fly_zones[0][0];
    ASSERT_EQ(polys[1]["polygon"].size(), nfz.size() - 1);
    for (std::size_t k = 0; k + 1 < nfz.size(); ++k) {
      EXPECT_NEAR(polys[1]["polygon"][k][0].get<double>(), nfz[k].lat, 1e-12);
      EXPECT_NEAR(polys[1]["polygon"][k][1].get<double>(), nfz[k].lon, 1e-12);
    }
  }
  fs::remove_all(dir);
}

TEST(Formats, MissionPlannerWplRoundTrip) {
  const Plan plan = fixture::two_uav_plan(true);
  const fs::path dir = temp_dir("wpl");
  fixture::export_to(plan, {"wpl"}, dir);
  for (std::size_t u = 0; u < 2; ++u) {
    const auto rows = lines(slurp(dir / "export" / (plan.uavs[u].id + ".waypoints")));
    const auto items = mission_items(plan, u);
    ASSERT_EQ(rows.size(), items.size() + 2);
    EXPECT_EQ(rows[0], "QGC WPL 110");
    const auto home = split(rows[1], '\t');
    ASSERT_EQ(home.size(), 12u);
    EXPECT_EQ(home[0], "0");
    EXPECT_EQ(home[1], "1");  // current
    EXPECT_NEAR(std::stod(home[8]), plan.mission.uavs[u].start_resolved.lat, 1e-8);
    EXPECT_NEAR(std::stod(home[9]), plan.mission.uavs[u].start_resolved.lon, 1e-8);
    for (std::size_t k = 0; k < items.size(); ++k) {
      const auto f = split(rows[k + 2], '\t');
      ASSERT_EQ(f.size(), 12u) << rows[k + 2];
      EXPECT_EQ(std::stoi(f[0]), static_cast<int>(k) + 1);
      EXPECT_EQ(std::stoi(f[2]), items[k].frame);
      EXPECT_EQ(std::stoi(f[3]), items[k].command);
      EXPECT_NEAR(std::stod(f[4]), items[k].param1, 1e-6);
      EXPECT_NEAR(std::stod(f[8]), items[k].lat, 1e-8);
      EXPECT_NEAR(std::stod(f[9]), items[k].lon, 1e-8);
      EXPECT_NEAR(std::stod(f[10]), items[k].alt, 1e-6);
      EXPECT_EQ(f[11], "1");
    }
  }
  fs::remove_all(dir);
}

TEST(Formats, KmlAndKmzRoundTrip) {
  const Plan plan = fixture::two_uav_plan();
  ExportOptions opt;
  opt.kmz = true;
  const fs::path dir = temp_dir("kml");
  fixture::export_to(plan, {"kml"}, dir, opt);
  for (std::size_t u = 0; u < 2; ++u) {
    const std::string id = plan.uavs[u].id;
    const std::string text = slurp(dir / "export" / (id + ".kml"));
    const auto kmz = unzip(dir / "export" / (id + ".kmz"));
    ASSERT_EQ(kmz.count("doc.kml"), 1u);
    EXPECT_EQ(kmz.at("doc.kml"), text);
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_string(text.c_str()));
    const std::string desc = doc.select_node("/kml/Document/description").node().text().get();
    EXPECT_NE(desc.find("mission altitude 40 m (default)"), std::string::npos) << desc;
    const auto placemarks = doc.select_nodes("/kml/Document/Placemark");
    ASSERT_EQ(placemarks.size(), 3u);  // area, no-fly zone, path
    // area polygon: lon,lat order, matches the mission ring
    const auto area = kml_coords(
        doc.select_node("/kml/Document/Placemark[1]/Polygon/outerBoundaryIs/LinearRing/coordinates")
            .node()
            .text()
            .get());
    const GeoRing& ring = plan.mission.area[0][0];
    ASSERT_EQ(area.size(), ring.size());
    for (std::size_t k = 0; k < ring.size(); ++k) {
      EXPECT_NEAR(area[k][0], ring[k].lon, kDeg);
      EXPECT_NEAR(area[k][1], ring[k].lat, kDeg);
    }
    EXPECT_TRUE(doc.select_node("/kml/Document/Placemark[2]/Polygon").node());
    const auto line = doc.select_node("/kml/Document/Placemark[3]/LineString").node();
    ASSERT_TRUE(line);
    EXPECT_STREQ(line.child("altitudeMode").text().get(), "relativeToGround");
    const auto pts = kml_coords(line.child("coordinates").text().get());
    const auto pos = positioned(mission_items(plan, u));
    ASSERT_EQ(pts.size(), pos.size() + 1);  // home on the ground first
    EXPECT_NEAR(pts[0][1], plan.mission.uavs[u].start_resolved.lat, kDeg);
    EXPECT_DOUBLE_EQ(pts[0][2], 0.0);
    for (std::size_t k = 0; k < pos.size(); ++k) {
      EXPECT_NEAR(pts[k + 1][0], pos[k].lon, kDeg);
      EXPECT_NEAR(pts[k + 1][1], pos[k].lat, kDeg);
      EXPECT_NEAR(pts[k + 1][2], pos[k].alt, 1e-6);
    }
  }
  fs::remove_all(dir);
}

TEST(Formats, DjiWpmlRoundTrip) {
  const Plan plan = fixture::two_uav_plan(true);
  const fs::path dir = temp_dir("dji");
  fixture::export_to(plan, {"dji"}, dir);
  for (std::size_t u = 0; u < 2; ++u) {
    const auto entries = unzip(dir / "export" / (plan.uavs[u].id + ".wpml.kmz"));
    ASSERT_EQ(entries.size(), 2u);
    ASSERT_EQ(entries.count("wpmz/template.kml"), 1u);
    ASSERT_EQ(entries.count("wpmz/waylines.wpml"), 1u);
    const auto wps = waypoints_only(mission_items(plan, u));
    for (const char* name : {"wpmz/template.kml", "wpmz/waylines.wpml"}) {
      pugi::xml_document doc;
      ASSERT_TRUE(doc.load_string(entries.at(name).c_str())) << name;
      EXPECT_STREQ(doc.child("kml").attribute("xmlns:wpml").value(), "http://www.dji.com/wpmz/1.0.2");
      const auto config = doc.select_node("/kml/Document/wpml:missionConfig").node();
      ASSERT_TRUE(config) << name;
      EXPECT_STREQ(config.child("wpml:finishAction").text().get(), "goHome");
      const auto marks = doc.select_nodes("/kml/Document/Folder/Placemark");
      ASSERT_EQ(marks.size(), wps.size()) << name;
      const bool wayline = std::string(name).ends_with(".wpml");
      if (wayline) {
        EXPECT_STREQ(doc.select_node("/kml/Document/Folder/wpml:executeHeightMode").node().text().get(),
                     "relativeToStartPoint");
      }
      std::size_t k = 0, groups = 0, distance_groups = 0;
      for (const auto& m : marks) {
        const auto c = kml_coords(m.node().select_node("Point/coordinates").node().text().get());
        ASSERT_EQ(c.size(), 1u);
        EXPECT_NEAR(c[0][0], wps[k].lon, kDeg);
        EXPECT_NEAR(c[0][1], wps[k].lat, kDeg);
        EXPECT_EQ(m.node().child("wpml:index").text().as_int(), static_cast<int>(k));
        const char* h = wayline ? "wpml:executeHeight" : "wpml:height";
        EXPECT_NEAR(m.node().child(h).text().as_double(), wps[k].alt, 1e-6);
        for (const auto& g : m.node().children("wpml:actionGroup")) {
          ++groups;
          EXPECT_EQ(g.child("wpml:actionGroupStartIndex").text().as_int(), static_cast<int>(k));
          EXPECT_STREQ(wps[k].role.c_str(), "coverage");
          const int end = g.child("wpml:actionGroupEndIndex").text().as_int();
          EXPECT_STREQ(wps[static_cast<std::size_t>(end)].role.c_str(), "coverage");
          const std::string type =
              g.select_node("wpml:actionTrigger/wpml:actionTriggerType").node().text().get();
          if (type == "multipleDistance") {
            ++distance_groups;
            EXPECT_EQ(end, static_cast<int>(k) + 1);  // one coverage leg
            EXPECT_NEAR(g.select_node("wpml:actionTrigger/wpml:actionTriggerParam").node().text().as_double(),
                        *plan.mission.trigger_distance_m, 1e-5);  // a MAVLink float param
          } else {
            EXPECT_EQ(type, "reachPoint");  // the photo at a leg's end
            EXPECT_EQ(end, static_cast<int>(k));
          }
        }
        ++k;
      }
      EXPECT_EQ(distance_groups, 6u);  // the loop's 6 legs, each shot on its own
      // and a photo at the last leg's end: the other legs end where the next one starts, whose distance
      // group shoots that corner (issue 34: one image per shared corner)
      EXPECT_EQ(groups, 7u);
    }
  }
  fs::remove_all(dir);
}

TEST(Formats, LitchiAndCsvRoundTrip) {
  const Plan plan = fixture::two_uav_plan(true);
  const fs::path dir = temp_dir("litchi");
  fixture::export_to(plan, {"litchi,csv"}, dir);
  for (std::size_t u = 0; u < 2; ++u) {
    const auto items = mission_items(plan, u);
    const auto wps = waypoints_only(items);
    const auto rows = lines(slurp(dir / "export" / (plan.uavs[u].id + ".litchi.csv")));
    ASSERT_EQ(rows.size(), wps.size() + 1);
    const auto header = split(rows[0], ',');
    ASSERT_EQ(header.size(), 46u);
    EXPECT_EQ(header[0], "latitude");
    EXPECT_EQ(header[1], "longitude");
    EXPECT_EQ(header[2], "altitude(m)");
    EXPECT_EQ(header[39], "speed(m/s)");
    EXPECT_EQ(header[45], "photo_distinterval");
    for (std::size_t k = 0; k < wps.size(); ++k) {
      const auto f = split(rows[k + 1], ',');
      ASSERT_EQ(f.size(), header.size());
      EXPECT_NEAR(std::stod(f[0]), wps[k].lat, 1e-8);
      EXPECT_NEAR(std::stod(f[1]), wps[k].lon, 1e-8);
      EXPECT_NEAR(std::stod(f[2]), wps[k].alt, 1e-6);
      EXPECT_NEAR(std::stod(f[39]), plan.mission.uavs[u].speed_mps, 1e-9);
      // distance shooting starts at every coverage waypoint that starts a leg (the loop's last ends one)
      const bool starts_leg =
          wps[k].role == "coverage" && k + 1 < wps.size() && wps[k + 1].role == "coverage";
      EXPECT_EQ(std::stod(f[45]) > 0, starts_leg) << k;
    }
    const auto csv = lines(slurp(dir / "export" / (plan.uavs[u].id + ".csv")));
    ASSERT_EQ(csv.size(), items.size() + 1);
    EXPECT_EQ(csv[0], "seq,role,command,frame,lat,lon,alt_m,param1,param2,param3,param4");
    for (std::size_t k = 0; k < items.size(); ++k) {
      const auto f = split(csv[k + 1], ',');
      ASSERT_EQ(f.size(), 11u);
      EXPECT_EQ(f[1], items[k].role);
      EXPECT_EQ(std::stoi(f[2]), items[k].command);
      EXPECT_NEAR(std::stod(f[4]), items[k].lat, kDeg);
      EXPECT_NEAR(std::stod(f[5]), items[k].lon, kDeg);
    }
  }
  fs::remove_all(dir);
}

TEST(Formats, GeojsonIsValidRfc7946AndMatchesThePlan) {
  const Plan plan = fixture::two_uav_plan();
  const fs::path dir = temp_dir("geojson");
  fixture::export_to(plan, {"geojson"}, dir);
  for (std::size_t u = 0; u < 2; ++u) {
    const json doc = json::parse(slurp(dir / "export" / (plan.uavs[u].id + ".geojson")));
    EXPECT_TRUE(validate_geojson(doc).empty());
    std::size_t lines_seen = 0;
    for (const auto& f : doc["features"]) {
      if (f["geometry"]["type"] != "LineString") continue;
      const auto& part = plan.uavs[u].parts.at(f["properties"]["part"].get<std::size_t>());
      const auto& c = f["geometry"]["coordinates"];
      ASSERT_EQ(c.size(), part.wgs84.size());
      for (std::size_t k = 0; k < c.size(); ++k) {
        EXPECT_DOUBLE_EQ(c[k][0].get<double>(), part.wgs84[k].lon);  // [lon, lat]
        EXPECT_DOUBLE_EQ(c[k][1].get<double>(), part.wgs84[k].lat);
      }
      ++lines_seen;
    }
    EXPECT_EQ(lines_seen, plan.uavs[u].parts.size());
  }
  fs::remove_all(dir);
}

TEST(Formats, GeojsonValidatorCatchesBrokenDocuments) {
  const Plan plan = fixture::two_uav_plan();
  const json good = uav_geojson(plan, 0);
  ASSERT_TRUE(validate_geojson(good).empty());
  // clockwise exterior
  json cw = good;
  auto& ring = cw["features"][0]["geometry"]["coordinates"][0];
  std::reverse(ring.begin(), ring.end());
  ASSERT_FALSE(validate_geojson(cw).empty());
  EXPECT_NE(validate_geojson(cw)[0].find("counter-clockwise"), std::string::npos);
  // open ring
  json open = good;
  open["features"][0]["geometry"]["coordinates"][0].erase(
      open["features"][0]["geometry"]["coordinates"][0].size() - 1);
  auto p = validate_geojson(open);
  ASSERT_FALSE(p.empty());
  EXPECT_NE(p[0].find("not closed"), std::string::npos);
  // [lat, lon] swapped with latitude beyond 90 (here: use a far-north fake position)
  json swapped = good;
  swapped["features"][2]["geometry"]["coordinates"][0] = {47.0, 120.0};
  p = validate_geojson(swapped);
  ASSERT_FALSE(p.empty());
  EXPECT_NE(p[0].find("latitude out of range"), std::string::npos);
  // single-point LineString
  json shorty = good;
  shorty["features"][2]["geometry"]["coordinates"] = json::array({json::array({8.5, 47.4})});
  EXPECT_FALSE(validate_geojson(shorty).empty());
  EXPECT_FALSE(validate_geojson(json::object()).empty());
}

TEST(Formats, ExportPlanWritesEveryFormatAndRejectsUnknownOnes) {
  const Plan plan = fixture::two_uav_plan(true);
  const fs::path dir = temp_dir("all");
  std::vector<std::string> all = known_formats();
  const auto files = fixture::export_to(plan, all, dir);
  for (const auto& id : {"alpha", "bravo"}) {
    for (const auto& ext :
         {".geojson", ".plan", ".waypoints", ".kml", ".wpml.kmz", ".litchi.csv", ".csv", ".trajectory.png"})
      EXPECT_TRUE(fs::exists(dir / "export" / (std::string(id) + ext))) << id << ext;
    const auto traj = lines(slurp(dir / "trajectory" / (std::string(id) + ".csv")));
    ASSERT_GT(traj.size(), 10u);
    EXPECT_EQ(traj[0], "t,kind,x,y,z,lat,lon,vx,vy,vz,ax,ay,az,v_max,a_max");  // the segment form
  }
  EXPECT_EQ(files.size(), 18u);
  try {
    fixture::export_to(plan, {"qgc,bogus"}, dir);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "formats");  // the library names its field, not a CLI flag
    EXPECT_NE(std::string(e.what()).find("bogus"), std::string::npos);
  }
  EXPECT_THROW(fixture::export_to(plan, {}, dir), InputError);
  // a shared transition altitude is refused
  ExportOptions same;
  same.altitude.transition_step_m = 0;
  EXPECT_THROW(fixture::export_to(plan, {"qgc"}, dir, same), InputError);
  fs::remove_all(dir);
}

TEST(Formats, LitchiWarnsBeyond99Waypoints) {
  Plan plan = fixture::two_uav_plan();
  const geodesy::LocalFrame frame(plan.origin);
  std::vector<Point> loop;
  for (int k = 0; k <= 60; ++k) loop.emplace_back(-90 + k, -40);
  for (int k = 1; k <= 60; ++k) loop.emplace_back(-30, -40 + k);
  loop.emplace_back(-90, 20);
  loop.push_back(loop.front());
  plan.uavs[0].parts[1] = fixture::make_part(frame, PartKind::Coverage, loop);
  plan.uavs[0].parts[2] = fixture::make_part(frame, PartKind::Transit, {{-90, -40}, {-120, -60}});
  std::vector<std::string> warnings;
  ExportOptions opt;
  opt.warnings = &warnings;
  const fs::path dir = temp_dir("litchi99");
  fixture::export_to(plan, {"litchi"}, dir, opt);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("uav 'alpha'"), std::string::npos);
  EXPECT_NE(warnings[0].find("99"), std::string::npos);
  // split into missions of at most 99 waypoints, each starting where the previous one ended
  const auto wps = waypoints_only(mission_items(plan, 0));
  ASSERT_GT(wps.size(), 99u);
  EXPECT_FALSE(fs::exists(dir / "export" / "alpha.litchi.csv"));
  std::vector<std::vector<std::string>> missions;
  for (int k = 1; fs::exists(dir / "export" / ("alpha." + std::to_string(k) + ".litchi.csv")); ++k)
    missions.push_back(lines(slurp(dir / "export" / ("alpha." + std::to_string(k) + ".litchi.csv"))));
  ASSERT_EQ(missions.size(), 2u);
  std::size_t rows = 0;
  for (const auto& m : missions) {
    EXPECT_LE(m.size() - 1, 99u);
    rows += m.size() - 1;
  }
  EXPECT_EQ(rows, wps.size() + 1);                   // the joining waypoint is in both
  EXPECT_EQ(missions[0].back(), missions[1].at(1));  // mission 2 starts where mission 1 ended
  EXPECT_TRUE(fs::exists(dir / "export" / "bravo.litchi.csv"));
  fs::remove_all(dir);
}

TEST(Formats, TrajectoryIsTheSegmentFormOrSampledAtTheChosenStep) {
  const Plan plan = fixture::two_uav_plan(true);
  for (std::size_t u = 0; u < 2; ++u) {
    const std::string id = plan.uavs[u].id;
    const auto traj =
        trajectory::uav_trajectory(plan, u, {}, resolve_altitudes({}, 2, plan.mission.altitude_m));
    // default: the segment form of the same trajectory
    const auto seg = export_artifacts(plan, {"trajectory"});
    const auto* f = check::find(seg, "trajectory/" + id + ".csv");
    ASSERT_NE(f, nullptr);
    EXPECT_EQ(f->bytes, trajectory::segments_csv(plan, traj));
    // a step: the sampled CSV at that step
    ExportOptions opt;
    opt.trajectory_step_s = 0.1;
    const auto sampled = export_artifacts(plan, {"trajectory"}, opt);
    const auto* s = check::find(sampled, "trajectory/" + id + ".csv");
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(s->bytes, trajectory::trajectory_csv(plan, traj.sample(0.1)));
  }
  // a caller that keeps the trajectories gets each UAV's once, the one the files were made from
  std::map<std::string, trajectory::Trajectory> kept;
  ExportOptions keep;
  keep.trajectories = &kept;
  const auto both = export_artifacts(plan, {"trajectory,trajectory_plot"}, keep);
  ASSERT_EQ(kept.size(), 2u);
  const auto plain = export_artifacts(plan, {"trajectory,trajectory_plot"});
  ASSERT_EQ(both.size(), plain.size());
  for (std::size_t k = 0; k < both.size(); ++k) EXPECT_EQ(both[k].bytes, plain[k].bytes) << both[k].name;
  for (std::size_t u = 0; u < 2; ++u) {
    const auto& id = plan.uavs[u].id;
    ASSERT_TRUE(kept.contains(id));
    EXPECT_EQ(trajectory::segments_csv(plan, kept.at(id)),
              check::find(both, "trajectory/" + id + ".csv")->bytes);
  }
  for (const double bad : {-1.0, 0.0005, std::nan("")}) {
    ExportOptions opt;
    opt.trajectory_step_s = bad;
    try {
      (void)export_artifacts(plan, {"trajectory"}, opt);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "trajectory_step_s");
    }
  }
}
