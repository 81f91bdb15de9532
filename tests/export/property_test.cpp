// Property test of the exporters: a few hundred random valid plans (seeded: random areas, 1-5 UAVs
// in strips, random lawnmower loops, idle UAVs, altitudes, speeds, ids and hostile mission names),
// every format, each output read back by its own parser and checked against its consumer's limits.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <pugixml.hpp>
#include <random>

#include "export/check.hpp"
#include "export/export.hpp"
#include "export/fixture.hpp"
#include "uavcover/error.hpp"

using namespace uavcover;
using namespace uavcover::exporting;
using namespace uavcover::waypoints;
using nlohmann::json;

namespace {

struct Gen {
  std::mt19937_64 rng;
  double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
  int integer(int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng); }
  bool chance(double p) { return uni(0, 1) < p; }
};

std::string hostile_name(Gen& g) {
  static const std::vector<std::string> pieces{
      "field ",       "<b>",          "&amp;", "\"", "'",  "]]>", "\xC3\xA9", "\xFF",
      "\xED\xA0\x80", "\xEF\xBF\xBE", "\t",    "\n", "\r", " ",   "\x7F"};
  std::string s;
  const int n = g.integer(0, 12);
  for (int k = 0; k < n; ++k) {
    if (g.chance(0.3))
      s += static_cast<char>(g.integer(0, 0x1F));
    else
      s += pieces[static_cast<std::size_t>(g.integer(0, static_cast<int>(pieces.size()) - 1))];
  }
  return s;
}

std::string random_id(Gen& g, std::size_t u) {
  static const std::string first = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-";
  static const std::string rest = first + ".";
  std::string id(1, first[static_cast<std::size_t>(g.integer(0, static_cast<int>(first.size()) - 1))]);
  const int n = g.integer(0, 12);
  for (int k = 0; k < n; ++k)
    id += rest[static_cast<std::size_t>(g.integer(0, static_cast<int>(rest.size()) - 1))];
  return id + "_" + std::to_string(u);  // unique
}

/// A lawnmower loop over [x0, x1] x [y0, y1] with `cols` sweeps, closed (last == first).
std::vector<Point> lawnmower(double x0, double x1, double y0, double y1, int cols) {
  std::vector<Point> pts;
  for (int c = 0; c < cols; ++c) {
    const double x = x0 + (x1 - x0) * c / std::max(1, cols - 1);
    if (c % 2 == 0) {
      pts.emplace_back(x, y0);
      pts.emplace_back(x, y1);
    } else {
      pts.emplace_back(x, y1);
      pts.emplace_back(x, y0);
    }
  }
  pts.emplace_back(x1, y1 + 1.0);  // back along the top, outside the sweeps
  pts.emplace_back(x0, y1 + 1.0);
  pts.push_back(pts.front());
  return pts;
}

Plan random_plan(Gen& g) {
  Plan plan;
  plan.origin = {g.uni(-170, 170), g.uni(-60, 60)};
  const geodesy::LocalFrame frame(plan.origin);
  Mission& m = plan.mission;
  m.name = hostile_name(g);
  m.altitude_source = g.chance(0.5) ? "altitude_m" : hostile_name(g);
  m.mode = g.chance(0.5) ? Mode::Coverage : Mode::Strict;
  const double W = g.uni(100, 400), H = g.uni(80, 300);
  // the area: a rectangle with outward bumps on its edges (simple, CCW, holds [-W, W] x [-H, H])
  std::vector<Point> ring;
  const std::array<Point, 4> corners{Point(-W, -H), Point(W, -H), Point(W, H), Point(-W, H)};
  for (std::size_t c = 0; c < 4; ++c) {
    const Point a = corners[c], b = corners[(c + 1) % 4];
    ring.push_back(a);
    const int bumps = g.integer(0, 2);
    for (int k = 1; k <= bumps; ++k) {
      const double t = static_cast<double>(k) / (bumps + 1);
      const double dx = b.x() - a.x(), dy = b.y() - a.y(), len = std::hypot(dx, dy), out = g.uni(0, 50);
      ring.emplace_back(a.x() + t * dx + dy / len * out, a.y() + t * dy - dx / len * out);
    }
  }
  m.area.push_back({fixture::geo_ring(frame, ring)});
  if (g.chance(0.5))  // north of everything flown
    m.no_fly_zones.push_back({fixture::geo_ring(
        frame, {{-W / 2, H + 60}, {-W / 2 + 40, H + 60}, {-W / 2 + 40, H + 100}, {-W / 2, H + 100}})});
  m.altitude_m = g.uni(10, 100);
  m.spacing_m = g.uni(5, 30);
  if (g.chance(0.5)) {
    m.camera = Camera{};
    m.camera->altitude_m = m.altitude_m;
    m.camera->hfov_deg = 60;
    m.camera->overlap = 0.2;
    m.footprint_m = 2 * m.altitude_m * std::tan(std::numbers::pi / 6);
    m.along_track_footprint_m = *m.footprint_m * 0.75;
    m.trigger_distance_m = *m.along_track_footprint_m * (1 - m.camera->front_overlap);
  }
  const int n = g.integer(1, 5);
  const double sw = 2 * W / n;
  bool any = false;
  for (int u = 0; u < n; ++u) {
    const double x0 = -W + u * sw + 2, x1 = -W + (u + 1) * sw - 2;
    Uav uav;
    uav.id = random_id(g, static_cast<std::size_t>(u));
    const Point home(g.uni(x0, x1), -H - g.uni(20, 200));
    uav.start_resolved = frame.to_wgs84(home);
    uav.start = uav.start_resolved;
    uav.share = 1.0 / n;
    uav.speed_mps = g.uni(1, 25);
    uav.max_accel_mps2 = g.uni(1, 5);
    UavPlan up;
    up.id = uav.id;
    const bool idle_uav = (u < n - 1 || any) && g.chance(0.15);
    Point here = home;
    if (!idle_uav) {
      const int loops = g.integer(1, 3);
      const double top = m.mode == Mode::Coverage ? H + 20 : H - 2;  // coverage mode may leave the area
      for (int l = 0; l < loops; ++l) {
        const double ya = g.uni(-H + 2, top - 10), yb = g.uni(ya + 5, top);
        const double xa = g.uni(x0, x1 - 4), xb = g.uni(xa + 3, x1);
        const auto loop = lawnmower(xa, xb, ya, yb, g.integer(2, g.chance(0.2) ? 70 : 8));
        up.parts.push_back(fixture::make_part(frame, PartKind::Transit, {here, loop.front()}));
        up.parts.push_back(fixture::make_part(frame, PartKind::Coverage, loop));
        here = loop.back();
      }
      any = true;
    }
    up.parts.push_back(fixture::make_part(frame, PartKind::Transit, {here, home}));
    m.uavs.push_back(uav);
    plan.uavs.push_back(up);
  }
  return plan;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out(1);
  for (char c : s) {
    if (c == sep)
      out.emplace_back();
    else
      out.back() += c;
  }
  if (out.back().empty()) out.pop_back();
  return out;
}

void check_csv(const std::string& text, std::size_t columns, const std::string& what) {
  for (const auto& row : split(text, '\n')) ASSERT_EQ(split(row, ',').size(), columns) << what << ": " << row;
}

}  // namespace

TEST(ExportProperty, RandomPlansGiveOutputsTheirConsumersAccept) {
  Gen g{std::mt19937_64(20240611)};
  std::map<std::string, int> refused;
  int exported = 0, files = 0;
  for (int trial = 0; trial < 300; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const Plan plan = random_plan(g);
    ExportOptions opt;
    opt.kmz = true;
    opt.trajectory.dt = 2.0;
    opt.qgc_firmware_type = g.chance(0.5) ? 12 : 3;
    opt.altitude.transition_base_m = g.chance(0.5) ? 0.0 : plan.mission.altitude_m + g.uni(5, 40);
    opt.altitude.transition_step_m = g.uni(3, 15);
    opt.altitude.transition_ceiling_m = g.chance(0.8) ? 120.0 : g.uni(60, 200);
    std::vector<std::string> warnings;
    opt.warnings = &warnings;
    Artifacts a;
    try {
      a = export_artifacts(plan, known_formats(), opt);
    } catch (const InputError& e) {
      // only the documented refusals: altitudes that cannot be kept, separation
      const std::string f = e.field();
      ASSERT_TRUE(f == "altitude.transition_ceiling_m" || f == "separation") << e.what();
      ++refused[f];
      continue;
    }
    ++exported;
    const double ceiling = opt.altitude.transition_ceiling_m;
    std::size_t flying = 0;
    for (std::size_t u = 0; u < plan.uavs.size(); ++u) {
      const std::string& id = plan.uavs[u].id;
      const std::string base = "export/" + id;
      if (idle(plan.uavs[u])) {
        for (const auto& f : a) ASSERT_NE(f.name.rfind(base + ".", 0), 0u) << f.name;
        continue;
      }
      ++flying;
      const double speed = plan.mission.uavs[u].speed_mps;
      // GeoJSON
      const json gj = json::parse(check::find(a, base + ".geojson")->bytes);
      ASSERT_TRUE(validate_geojson(gj).empty());
      // QGroundControl .plan: the schema fields, params of 7, PX4's fence check, altitudes under the ceiling
      const json qgc = json::parse(check::find(a, base + ".plan")->bytes);
      ASSERT_EQ(qgc["fileType"], "Plan");
      ASSERT_EQ(qgc["version"], 1);
      ASSERT_TRUE(qgc["mission"]["items"].is_array());
      ASSERT_TRUE(qgc["rallyPoints"]["points"].is_array());
      ASSERT_TRUE(qgc["geoFence"]["polygons"].is_array());
      for (const auto& it : qgc["mission"]["items"]) {
        ASSERT_TRUE(it["command"].is_number_integer());
        ASSERT_TRUE(it["frame"].is_number_integer());
        ASSERT_EQ(it["params"].size(), 7u);
        if (ceiling > 0 && (it["command"] == 16 || it["command"] == 22)) {
          ASSERT_LE(it["params"][6].get<double>(), std::max(ceiling, plan.mission.altitude_m) + 1e-3);
        }
      }
      ASSERT_EQ(check::px4_fence_failure(qgc), "");
      // Mission Planner WPL: 12 tab-separated columns
      const auto wpl = split(check::find(a, base + ".waypoints")->bytes, '\n');
      ASSERT_EQ(wpl.at(0), "QGC WPL 110");
      for (std::size_t k = 1; k < wpl.size(); ++k) ASSERT_EQ(split(wpl[k], '\t').size(), 12u) << wpl[k];
      // KML and KMZ: well-formed XML, the same document in the archive
      const std::string& kml = check::find(a, base + ".kml")->bytes;
      pugi::xml_document kdoc;
      ASSERT_TRUE(kdoc.load_string(kml.c_str())) << kml.substr(0, 400);
      ASSERT_TRUE(check::xml_chars_valid(kml));
      ASSERT_EQ(check::unzip_bytes(check::find(a, base + ".kmz")->bytes).at("doc.kml"), kml);
      // DJI WPML: well-formed, within DJI's ranges
      const auto wpmz = check::unzip_bytes(check::find(a, base + ".wpml.kmz")->bytes);
      ASSERT_EQ(wpmz.size(), 2u);
      for (const auto& [name, text] : wpmz) {
        pugi::xml_document d;
        ASSERT_TRUE(d.load_string(text.c_str())) << name;
        ASSERT_TRUE(check::xml_chars_valid(text)) << name;
        const double s = d.select_node("/kml/Document/Folder/wpml:autoFlightSpeed").node().text().as_double();
        ASSERT_GT(s, 0);
        ASSERT_LE(s, limits::kDjiMaxSpeed);
        const double tsh = d.select_node("/kml/Document/wpml:missionConfig/wpml:takeOffSecurityHeight")
                               .node()
                               .text()
                               .as_double();
        ASSERT_GE(tsh, 1.2);
        ASSERT_LE(tsh, 1500);
        ASSERT_TRUE(d.select_node("/kml/Document/wpml:missionConfig/wpml:globalRTHHeight"));
        for (const auto& pm : d.select_nodes("/kml/Document/Folder/Placemark")) {
          const auto h = pm.node().child(name.ends_with(".kml") ? "wpml:height" : "wpml:executeHeight");
          ASSERT_LE(h.text().as_double(), limits::kDjiMaxHeight);
        }
      }
      // Litchi: missions of at most 99 waypoints, 46 columns, speed and altitude in range
      std::vector<const Artifact*> litchi;
      if (const Artifact* one = check::find(a, base + ".litchi.csv")) litchi.push_back(one);
      for (int k = 1; const Artifact* part = check::find(a, base + "." + std::to_string(k) + ".litchi.csv");
           ++k)
        litchi.push_back(part);
      ASSERT_FALSE(litchi.empty());
      for (const Artifact* f : litchi) {
        const auto rows = split(f->bytes, '\n');
        ASSERT_GE(rows.size(), 2u);
        ASSERT_LE(rows.size() - 1, limits::kLitchiMaxWaypoints);
        for (std::size_t r = 1; r < rows.size(); ++r) {
          const auto c = split(rows[r], ',');
          ASSERT_EQ(c.size(), 46u);
          ASSERT_LE(std::stod(c[39]), limits::kLitchiMaxSpeed);
          ASSERT_NEAR(std::stod(c[39]), std::min(speed, limits::kLitchiMaxSpeed), 1e-9);
          ASSERT_GE(std::stod(c[2]), -200);
          ASSERT_LE(std::stod(c[2]), limits::kLitchiMaxAltitude);
        }
      }
      // CSVs
      check_csv(check::find(a, base + ".csv")->bytes, 11, base + ".csv");
      check_csv(check::find(a, "trajectory/" + id + ".csv")->bytes, 15, "trajectory/" + id + ".csv");
      files += 9 + static_cast<int>(litchi.size());
    }
    ASSERT_GT(flying, 0u);
  }
  RecordProperty("exported", exported);
  RecordProperty("files", files);
  EXPECT_GT(exported, 200);  // the refusals are the exception
  for (const auto& [field, count] : refused) RecordProperty("refused_" + field, count);
}
