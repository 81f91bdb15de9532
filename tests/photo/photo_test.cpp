// Photogrammetry (issue 18): trigger distance from the camera and overlaps, triggers on every coverage
// leg and never in transit in every format (read back from the files), image counts.
#include "photo/photo.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <numbers>
#include <pugixml.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "export/export.hpp"
#include "geodesy/local_frame.hpp"
#include "mission/mission_json.hpp"
#include "uavcover/error.hpp"
#include "uavcover/mission.hpp"
#include "uavcover/uavcover.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover {
namespace {

using nlohmann::json;

/// A 240 m x 160 m field with a no-fly zone and 2 UAVs starting south of it, flown with `camera`.
json field(const json& camera) {
  const double lon0 = 21.10, lat0 = 39.50;
  const double dx = 240.0 / 85000.0, dy = 160.0 / 111000.0;
  json area = {
      {"type", "Polygon"},
      {"coordinates",
       {{{lon0, lat0}, {lon0 + dx, lat0}, {lon0 + dx, lat0 + dy}, {lon0, lat0 + dy}, {lon0, lat0}}}}};
  json nfz = {{"type", "Polygon"},
              {"coordinates",
               {{{lon0 + dx * 0.4, lat0 + dy * 0.4},
                 {lon0 + dx * 0.55, lat0 + dy * 0.4},
                 {lon0 + dx * 0.55, lat0 + dy * 0.6},
                 {lon0 + dx * 0.4, lat0 + dy * 0.6},
                 {lon0 + dx * 0.4, lat0 + dy * 0.4}}}}};
  return {{"version", 1},
          {"name", "photo field"},
          {"area", area},
          {"no_fly_zones", {nfz}},
          {"camera", camera},
          {"uavs",
           {{{"id", "a"}, {"start", {lon0 - 0.0003, lat0 - 0.0003}}, {"speed_mps", 5}},
            {{"id", "b"}, {"start", {lon0 + dx + 0.0003, lat0 - 0.0003}}, {"speed_mps", 6}}}},
          {"seed", 3}};
}

json qgc_camera(double altitude = 30) {
  return {{"altitude_m", altitude}, {"sensor_width_mm", 13.2}, {"focal_length_mm", 8.8},
          {"image_width_px", 5472}, {"image_height_px", 3648}, {"side_overlap", 0.7}};
}

Plan plan_with(const json& camera) { return plan(parse_mission(field(camera).dump())); }

/// The count, sum over the UAV's coverage legs of ceil(L / d) + 1, less one at each corner where
/// a leg starts where the previous leg ended (issue 34: that image is taken once, the camera refuses a
/// second trigger there).
int formula_images(const Plan& p, std::size_t uav, double d) {
  int n = 0;
  for (const PathPart& part : p.uavs[uav].parts) {
    if (part.kind != PartKind::Coverage) continue;
    bool previous = false;  // the previous vertex ended a shot leg
    for (std::size_t k = 1; k < part.local.size(); ++k) {
      const double len =
          std::hypot(part.local[k].x() - part.local[k - 1].x(), part.local[k].y() - part.local[k - 1].y());
      if (len <= 1e-6) continue;
      n += static_cast<int>(std::ceil(len / d - 1e-9)) + (previous ? 0 : 1);
      previous = true;
    }
  }
  return n;
}

/// A generic MAVLink mission as read back from a file: command, params 1..4, lat, lon, alt.
struct Item {
  int command = 0;
  double p1 = 0, p2 = 0, p3 = 0, p4 = 0, lat = 0, lon = 0, alt = 0;
};

/// Flies `items` as an autopilot runs the camera commands: distance triggering starts at
/// DO_SET_CAM_TRIGG_DIST (d > 0), shoots every d metres flown, stops at d = 0; param3 = 1 shoots once;
/// IMAGE_START_CAPTURE shoots once. Fails the test when the camera would shoot on a move that is not a
/// coverage leg (a move at mission altitude between two different points), or a leg is flown without it in
/// distance capture.
int fly_camera(const std::vector<Item>& items, const LonLat& origin, double mission_alt, bool hover) {
  const geodesy::LocalFrame frame(origin);
  int photos = 0;
  double every = 0;
  bool have_pos = false;
  Point pos;
  double alt = 0;
  for (const Item& it : items) {
    if (it.command == 16 || it.command == 22 || it.command == 21) {
      const Point next = frame.to_local({it.lon, it.lat});
      if (have_pos) {
        const double len = std::hypot(next.x() - pos.x(), next.y() - pos.y());
        const bool leg =
            std::abs(alt - mission_alt) < 0.01 && std::abs(it.alt - mission_alt) < 0.01 && len > 1e-3;
        if (every > 0) {
          EXPECT_TRUE(leg) << "the camera shoots on a move that is not a coverage leg (alt " << alt << " -> "
                           << it.alt << ", " << len << " m)";
          photos += static_cast<int>(std::ceil(len / every - 1e-3)) - 1;  // strictly inside the leg
        } else if (leg && !hover) {
          // distance capture: a coverage leg flown without triggering is only allowed when it has no length
          ADD_FAILURE() << "a coverage leg of " << len << " m is flown without the camera";
        }
      }
      pos = next;
      alt = it.alt;
      have_pos = true;
    } else if (it.command == 206) {
      every = it.p1;
      if (it.p3 > 0) ++photos;
    } else if (it.command == 2000) {
      ++photos;
    } else if (it.command == 20) {
      EXPECT_EQ(every, 0) << "the camera still shoots on the way home";
    }
  }
  EXPECT_EQ(every, 0);
  return photos;
}

std::vector<Item> from_qgc(const json& doc) {
  std::vector<Item> out;
  for (const json& j : doc.at("mission").at("items")) {
    const json& p = j.at("params");
    auto num = [](const json& v) { return v.is_null() ? std::nan("") : v.get<double>(); };
    out.push_back({j.at("command").get<int>(), num(p[0]), num(p[1]), num(p[2]), num(p[3]), num(p[4]),
                   num(p[5]), num(p[6])});
  }
  return out;
}

std::vector<Item> from_wpl(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "QGC WPL 110");
  std::vector<Item> out;
  bool first = true;
  while (std::getline(in, line)) {
    // tab-separated; strtod reads Mission Planner's "NaN"
    std::vector<double> f;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, '\t')) f.push_back(std::strtod(cell.c_str(), nullptr));
    EXPECT_EQ(f.size(), 12u) << line;
    if (f.size() != 12) continue;
    Item it{0, f[4], f[5], f[6], f[7], f[8], f[9], f[10]};
    const int command = static_cast<int>(f[3]);
    it.command = command;
    if (first) {  // item 0: home (Mission Planner's convention), not flown
      first = false;
      continue;
    }
    out.push_back(it);
  }
  return out;
}

TEST(Photo, TriggerDistanceFromCameraAndOverlaps) {
  // QGroundControl convention: 13.2 mm / 8.8 mm at 100 m -> 150 m across; 3648/5472 of it = 100 m along
  json cam = qgc_camera(100);
  Mission m = parse_mission(field(cam).dump());
  EXPECT_NEAR(*m.footprint_m, 150.0, 1e-9);
  EXPECT_NEAR(*m.along_track_footprint_m, 100.0, 1e-9);
  EXPECT_NEAR(*m.trigger_distance_m, 25.0, 1e-9);  // front overlap 0.75 by default
  cam["front_overlap"] = 0.8;
  m = parse_mission(field(cam).dump());
  EXPECT_NEAR(*m.trigger_distance_m, 20.0, 1e-9);
  // without an image height: 4:3 of the width
  cam.erase("image_height_px");
  m = parse_mission(field(cam).dump());
  EXPECT_NEAR(*m.along_track_footprint_m, 112.5, 1e-9);
  cam["sensor_height_mm"] = 8.8;  // 100 m * 8.8 / 8.8
  m = parse_mission(field(cam).dump());
  EXPECT_NEAR(*m.along_track_footprint_m, 100.0, 1e-9);
  // the paper's convention: HFOV 90 deg at 50 m -> 100 m across; VFOV 60 deg -> 2 * 50 * tan 30 deg along
  const json fov = {
      {"altitude_m", 50}, {"hfov_deg", 90}, {"vfov_deg", 60}, {"overlap", 0.5}, {"front_overlap", 0.8}};
  m = parse_mission(field(fov).dump());
  EXPECT_NEAR(*m.footprint_m, 100.0, 1e-9);
  EXPECT_NEAR(*m.along_track_footprint_m, 100.0 * std::tan(std::numbers::pi / 6), 1e-9);
  EXPECT_NEAR(*m.trigger_distance_m, 0.2 * 100.0 * std::tan(std::numbers::pi / 6), 1e-9);
}

TEST(Photo, CameraFieldsRoundTripAndRefusals) {
  json cam = qgc_camera();
  cam["front_overlap"] = 0.7;
  cam["min_trigger_interval_s"] = 0.5;
  cam["gimbal_pitch_deg"] = -80;
  cam["capture"] = "hover";
  cam["image_size_mb"] = 12;
  const Mission m = parse_mission(field(cam).dump());
  const Mission back = parse_mission(mission_to_json(m));
  EXPECT_EQ(back.camera->front_overlap, 0.7);
  EXPECT_EQ(back.camera->min_trigger_interval_s, 0.5);
  EXPECT_EQ(back.camera->gimbal_pitch_deg, -80);
  EXPECT_EQ(back.camera->capture, "hover");
  EXPECT_EQ(back.camera->image_size_mb, 12);
  EXPECT_EQ(back.camera->image_height_px, 3648);

  auto refused = [&](json c, const std::string& field_name) {
    try {
      parse_mission(field(c).dump());
      ADD_FAILURE() << "accepted " << c.dump();
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field_name) << e.what();
    }
  };
  json c = qgc_camera();
  c["front_overlap"] = 0.99;
  refused(c, "camera.front_overlap");
  c = qgc_camera();
  c["capture"] = "burst";
  refused(c, "camera.capture");
  c = qgc_camera();
  c["gimbal_pitch_deg"] = 30;
  refused(c, "camera.gimbal_pitch_deg");
  c = qgc_camera();
  c["image_height_px"] = -1;
  refused(c, "camera.image_height_px");

  // too fast for the camera: 30 m altitude -> 30 m along, 7.5 m apart; 2 s minimum -> 3.75 m/s at most
  c = qgc_camera();
  c["min_trigger_interval_s"] = 2.0;
  try {
    parse_mission(field(c).dump());
    ADD_FAILURE() << "a UAV at 5 m/s was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "uavs[0].speed_mps");
    EXPECT_NE(std::string(e.what()).find("at most 3.75 m/s"), std::string::npos) << e.what();
  }
  c["min_trigger_interval_s"] = 1.0;  // 7.5 m/s fits both UAVs
  EXPECT_NO_THROW(parse_mission(field(c).dump()));
}

TEST(Photo, TriggersOnEveryLegNeverInTransitInEveryFormat) {
  const Plan p = plan_with(qgc_camera());
  const double d = *p.mission.trigger_distance_m;
  const auto est = photo::estimate(p);
  ASSERT_TRUE(est.has_value());
  EXPECT_NEAR(est->trigger_distance_m, d, 1e-12);
  const double alt = p.mission.altitude_m;
  int total = 0;
  for (std::size_t u = 0; u < p.uavs.size(); ++u) {
    const int expected = formula_images(p, u, d);
    ASSERT_GT(expected, 10);
    EXPECT_EQ(est->uavs[u].images, expected) << "uav " << u;
    total += expected;
    // MAVLink items, the QGroundControl .plan and the Mission Planner .waypoints, read back
    std::vector<Item> items;
    for (const auto& it : waypoints::mission_items(p, u))
      items.push_back({it.command, it.param1, it.param2, it.param3, it.param4, it.lat, it.lon, it.alt});
    EXPECT_EQ(fly_camera(items, p.origin, alt, false), expected) << "mission items, uav " << u;
    EXPECT_EQ(fly_camera(from_qgc(exporting::qgc_plan(p, u)), p.origin, alt, false), expected)
        << "qgc, uav " << u;
    EXPECT_EQ(fly_camera(from_wpl(exporting::wpl_text(p, u)), p.origin, alt, false), expected)
        << "wpl, uav " << u;

    // the gimbal is pitched before the first coverage waypoint
    bool gimbal = false;
    for (const auto& it : waypoints::mission_items(p, u)) {
      if (it.command == waypoints::kDoGimbalManagerPitchyaw) {
        gimbal = true;
        EXPECT_FLOAT_EQ(it.param1, -90.0f);
      }
      if (it.role == "coverage") {
        EXPECT_TRUE(gimbal);
        break;
      }
    }

    // DJI WPML: multipleDistance groups only over coverage legs; photos = per leg ceil(L/d) + end photos
    const auto files = exporting::dji_wpml(p, u);
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_string(files.at("wpmz/template.kml").c_str()));
    std::vector<std::pair<LonLat, double>> points;
    int dji_photos = 0;
    const geodesy::LocalFrame frame(p.origin);
    std::vector<std::pair<std::size_t, std::size_t>> distance_groups;
    for (const auto& pm : doc.select_nodes("//Placemark")) {
      const pugi::xml_node n = pm.node();
      std::istringstream c(n.child("Point").child_value("coordinates"));
      LonLat ll{};
      char comma = 0;
      c >> ll.lon >> comma >> ll.lat;
      points.push_back({ll, n.child("wpml:height").text().as_double()});
      EXPECT_EQ(n.child("wpml:gimbalPitchAngle").text().as_double(), -90.0);
      for (const auto& g : n.children("wpml:actionGroup")) {
        const std::string type = g.child("wpml:actionTrigger").child_value("wpml:actionTriggerType");
        const auto s = g.child("wpml:actionGroupStartIndex").text().as_ullong();
        const auto e = g.child("wpml:actionGroupEndIndex").text().as_ullong();
        if (type == "multipleDistance") {
          EXPECT_NEAR(g.child("wpml:actionTrigger").child("wpml:actionTriggerParam").text().as_double(), d,
                      1e-3);
          distance_groups.push_back({s, e});
        } else {
          EXPECT_EQ(type, "reachPoint");
          EXPECT_EQ(s, e);
          for (const auto& a : g.children("wpml:action"))
            dji_photos += std::string(a.child_value("wpml:actionActuatorFunc")) == "takePhoto";
        }
      }
    }
    for (const auto& [s, e] : distance_groups) {
      ASSERT_EQ(e, s + 1);
      ASSERT_LT(e, points.size());
      EXPECT_NEAR(points[s].second, alt, 1e-6);  // both ends at mission altitude: a coverage leg
      EXPECT_NEAR(points[e].second, alt, 1e-6);
      const Point a = frame.to_local(points[s].first), b = frame.to_local(points[e].first);
      dji_photos += static_cast<int>(std::ceil(std::hypot(b.x() - a.x(), b.y() - a.y()) / d - 1e-3));
    }
    EXPECT_EQ(dji_photos, expected) << "dji, uav " << u;

    // Litchi: photo_distinterval only on rows that start a coverage leg, photo actions at leg ends
    const auto csvs = exporting::litchi_csv(p, u);
    ASSERT_EQ(csvs.size(), 1u);
    std::istringstream csv(csvs.front());
    std::string line;
    std::getline(csv, line);
    std::vector<std::vector<std::string>> rows;
    while (std::getline(csv, line)) {
      std::vector<std::string> cells;
      std::stringstream ss(line);
      std::string cell;
      while (std::getline(ss, cell, ',')) cells.push_back(cell);
      ASSERT_EQ(cells.size(), 8u + 30u + 8u);
      rows.push_back(cells);
    }
    int litchi_photos = 0;
    for (std::size_t k = 0; k < rows.size(); ++k) {
      EXPECT_EQ(std::stod(rows[k][7]), -90.0);
      for (int a = 0; a < 15; ++a) litchi_photos += rows[k][8 + 2 * a] == "1";
      const double every = std::stod(rows[k].back());
      if (every > 0) {
        ASSERT_LT(k + 1, rows.size());
        EXPECT_NEAR(std::stod(rows[k][2]), alt, 1e-6);
        EXPECT_NEAR(std::stod(rows[k + 1][2]), alt, 1e-6);
        EXPECT_NEAR(every, d, 1e-3);
        const Point a = frame.to_local({std::stod(rows[k][1]), std::stod(rows[k][0])});
        const Point b = frame.to_local({std::stod(rows[k + 1][1]), std::stod(rows[k + 1][0])});
        litchi_photos += static_cast<int>(std::ceil(std::hypot(b.x() - a.x(), b.y() - a.y()) / d - 1e-3));
      }
    }
    EXPECT_EQ(litchi_photos, expected) << "litchi, uav " << u;
  }
  EXPECT_EQ(est->images, total);
  EXPECT_NEAR(est->storage_mb, total * 8.0, 1e-9);
  EXPECT_NEAR(est->side_overlap, 0.7, 1e-9);
  EXPECT_GE(est->front_overlap, 0.75 - 1e-9);  // legs are shot at most d apart
  EXPECT_LT(est->front_overlap, 1.0);
}

TEST(Photo, HoverAndCaptureStopsAtEveryShot) {
  json cam = qgc_camera();
  cam["capture"] = "hover";
  cam["gimbal_pitch_deg"] = -75;
  const Plan p = plan_with(cam);
  const double d = *p.mission.trigger_distance_m;
  const auto est = photo::estimate(p);
  ASSERT_TRUE(est.has_value());
  for (std::size_t u = 0; u < p.uavs.size(); ++u) {
    const auto items = waypoints::mission_items(p, u);
    int captures = 0, holds = 0;
    for (std::size_t k = 0; k < items.size(); ++k) {
      if (items[k].command == waypoints::kImageStartCapture) {
        ++captures;
        // issue 34: the hold belongs to the waypoint; the capture's param1 is the camera instance (0 = all)
        // and param3 one image
        EXPECT_EQ(items[k].param1, 0.0f) << "item " << k;
        EXPECT_EQ(items[k].param3, 1.0f) << "item " << k;
        // right after its stop (a waypoint with the hold time), never a second capture at the same stop
        ASSERT_GT(k, 0u);
        EXPECT_EQ(items[k - 1].command, waypoints::kNavWaypoint) << "item " << k;
        EXPECT_FLOAT_EQ(items[k - 1].param1, static_cast<float>(photo::kHoverHoldS));
        EXPECT_FLOAT_EQ(items[k - 1].alt, static_cast<float>(p.mission.altitude_m));
      }
      if (items[k].command == waypoints::kDoSetCamTriggDist) {
        ADD_FAILURE() << "distance trigger in hover capture";
      }
      if (items[k].command == waypoints::kDoGimbalManagerPitchyaw) {
        EXPECT_FLOAT_EQ(items[k].param1, -75.0f);
      }
      holds += items[k].command == waypoints::kNavWaypoint && items[k].param1 > 0;
    }
    EXPECT_EQ(captures, formula_images(p, u, d));
    EXPECT_EQ(captures, est->uavs[u].images);
    EXPECT_GT(holds, 0);
    EXPECT_NEAR(est->uavs[u].hover_time_s, captures * photo::kHoverHoldS, 1e-9);
  }
}

TEST(Photo, LegShotsAreEvenAndIncludeBothEnds) {
  const Point a(0, 0), b(30, 40);  // 50 m
  const auto shots = photo::leg_shots(a, b, 12.0);
  ASSERT_EQ(static_cast<int>(shots.size()), photo::leg_images(50.0, 12.0));
  EXPECT_EQ(shots.size(), 6u);  // ceil(50 / 12) + 1
  EXPECT_DOUBLE_EQ(shots.front().x(), 0.0);
  EXPECT_DOUBLE_EQ(shots.back().x(), 30.0);
  for (std::size_t k = 1; k < shots.size(); ++k)
    EXPECT_LE(std::hypot(shots[k].x() - shots[k - 1].x(), shots[k].y() - shots[k - 1].y()), 12.0 + 1e-9);
  EXPECT_EQ(photo::leg_images(24.0, 12.0), 3);
  EXPECT_EQ(photo::leg_images(0.0, 12.0), 1);
}

TEST(Photo, NoCameraNoEstimate) {
  json doc = field(qgc_camera());
  doc.erase("camera");
  doc["spacing_m"] = 10;
  const Plan p = plan(parse_mission(doc.dump()));
  EXPECT_FALSE(photo::estimate(p).has_value());
  for (const auto& it : waypoints::mission_items(p, 0)) {
    EXPECT_NE(it.command, waypoints::kDoSetCamTriggDist);
    EXPECT_NE(it.command, waypoints::kDoGimbalManagerPitchyaw);
  }
}

}  // namespace
}  // namespace uavcover
