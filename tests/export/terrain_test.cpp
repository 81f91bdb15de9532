// Terrain following in the exports (docs/photogrammetry.md): over a GDAL-written hill every coverage
// leg keeps the camera's height above the ground within terrain.tolerance_m, transit clears the highest
// ground, and each format carries AMSL (or take-off-relative) heights from the same items.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <nlohmann/json.hpp>
#include <regex>

#include "export/export.hpp"
#include "io/dem.hpp"
#include "support/files.hpp"
#include "support/terrain_mission.hpp"
#include "uavcover/uavcover.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover {
namespace {

using testdem::Hill;
using testdem::kOrigin;
using testdem::TempDir;
using waypoints::MissionItem;

const Hill kHill{200, 60, 60, 0, 0};

Plan hill_plan(const TempDir& dir, const std::string& mode = "follow", double tolerance = 1.0,
               int epsg = 4326) {
  testdem::DemSpec spec;
  spec.epsg = epsg;
  testdem::write_hill(dir.path / "hill.tif", geodesy::LocalFrame(kOrigin), kHill, spec);
  Mission m = parse_mission(testdem::mission_text("hill.tif", mode, tolerance));
  io::load_terrain(m, dir.path);
  return plan(m);
}

bool positioned(const MissionItem& it) {
  return it.command == waypoints::kNavWaypoint || it.command == waypoints::kNavTakeoff ||
         it.command == waypoints::kNavLand;
}
bool in_leg(const MissionItem& it) {
  return it.role == "coverage" || it.role == "terrain" || it.role == "capture";
}

struct Segment {
  const MissionItem* a;
  const MissionItem* b;
};
// consecutive positioned items; coverage legs are those between two leg items of one part
std::vector<Segment> segments(const std::vector<MissionItem>& items, bool legs) {
  std::vector<Segment> out;
  const MissionItem* prev = nullptr;
  for (const auto& it : items) {
    if (!positioned(it)) continue;
    if (prev != nullptr) {
      const bool leg = in_leg(*prev) && in_leg(it) && prev->part == it.part && it.part >= 0;
      if (leg == legs) out.push_back({prev, &it});
    }
    prev = &it;
  }
  return out;
}

// height above the ground along every coverage leg, sampled every 0.5 m: grid ground and the true hill
void check_follow(const Plan& p, double tolerance) {
  const HeightGrid& g = *p.mission.terrain->grid;
  const geodesy::LocalFrame f(p.origin);
  const geodesy::LocalFrame hill_frame(kOrigin);
  int terrain_points = 0;
  for (std::size_t u = 0; u < p.uavs.size(); ++u) {
    const auto items = waypoints::mission_items(p, u);
    for (const auto& it : items) {
      if (positioned(it)) {
        EXPECT_EQ(it.frame, waypoints::kFrameGlobal);
      }
      terrain_points += it.role == "terrain" ? 1 : 0;
      if (it.role == "coverage" ||
          it.role == "terrain") {  // every waypoint at the camera's height above ground
        EXPECT_NEAR(it.alt - g.at({it.lon, it.lat}), 40.0, 1e-3);
      }
    }
    const auto legs = segments(items, true);
    ASSERT_FALSE(legs.empty());
    for (const auto& [a, b] : legs) {
      const Point pa = f.to_local({a->lon, a->lat}), pb = f.to_local({b->lon, b->lat});
      const int n = std::max(2, static_cast<int>(std::hypot(pb.x() - pa.x(), pb.y() - pa.y()) / 0.5));
      for (int k = 0; k <= n; ++k) {
        const double t = static_cast<double>(k) / n;
        const LonLat q = f.to_wgs84({pa.x() + t * (pb.x() - pa.x()), pa.y() + t * (pb.y() - pa.y())});
        const double flight = a->alt + t * (b->alt - a->alt);
        EXPECT_LE(std::fabs(flight - g.at(q) - 40.0), tolerance) << "leg point " << q.lon << ", " << q.lat;
        const Point h = hill_frame.to_local(q);  // against the true hill: plus the DEM's bilinear error
        EXPECT_LE(std::fabs(flight - kHill(h.x(), h.y()) - 40.0), tolerance + 0.5);
      }
    }
  }
  EXPECT_GT(terrain_points, 0) << "the hill needs waypoints inside the legs";
}

TEST(Terrain, FollowKeepsTheHeightAboveGroundWithinTheTolerance) {
  TempDir dir("terrain_follow");
  const Plan p = hill_plan(dir, "follow", 1.0);
  check_follow(p, 1.0);
}

TEST(Terrain, FollowOverAProjectedDemAndATighterTolerance) {
  TempDir dir("terrain_utm");
  const Plan tight = hill_plan(dir, "follow", 0.25, 32632);
  check_follow(tight, 0.25);
  const Plan loose = hill_plan(dir, "follow", 4.0, 32632);
  check_follow(loose, 4.0);
  auto count = [](const Plan& p) {
    std::size_t n = 0;
    for (std::size_t u = 0; u < p.uavs.size(); ++u)
      for (const auto& it : waypoints::mission_items(p, u)) n += it.role == "terrain" ? 1 : 0;
    return n;
  };
  EXPECT_GT(count(tight), count(loose));
}

TEST(Terrain, TransitClearsTheHighestGroundUnderItByTheTransitionAltitude) {
  TempDir dir("terrain_transit");
  const Plan p = hill_plan(dir, "follow");
  const HeightGrid& g = *p.mission.terrain->grid;
  const geodesy::LocalFrame f(p.origin);
  const waypoints::AltitudeOptions alt =
      waypoints::resolve_altitudes({}, p.uavs.size(), p.mission.altitude_m);
  std::vector<double> transit;
  for (std::size_t u = 0; u < p.uavs.size(); ++u) {
    const auto items = waypoints::mission_items(p, u);
    EXPECT_NEAR(items.front().alt, kHill.base + kHill.peak + waypoints::transition_altitude(alt, u, 40.0),
                0.6);
    transit.push_back(items.front().alt);
    int checked = 0;
    for (const auto& [a, b] : segments(items, false)) {
      if (a->role == "land" || b->role == "land") continue;
      // the leg's lower end, against the highest ground under the leg (sampled every 0.5 m)
      const Point pa = f.to_local({a->lon, a->lat}), pb = f.to_local({b->lon, b->lat});
      const int n = std::max(2, static_cast<int>(std::hypot(pb.x() - pa.x(), pb.y() - pa.y()) / 0.5));
      double top = -1e9;
      for (int k = 0; k <= n; ++k) {
        const double t = static_cast<double>(k) / n;
        top =
            std::max(top, g.at(f.to_wgs84({pa.x() + t * (pb.x() - pa.x()), pa.y() + t * (pb.y() - pa.y())})));
      }
      const bool descent = in_leg(*b) || in_leg(*a);  // the vertical descent to / climb from a leg
      if (descent) continue;
      EXPECT_GE(std::min(a->alt, b->alt) - top, waypoints::transition_altitude(alt, u, 40.0) - 1e-3);
      ++checked;
    }
    EXPECT_GT(checked, 0);
  }
  // the UAVs keep the step between their transit altitudes
  ASSERT_EQ(transit.size(), 2u);
  EXPECT_NEAR(transit[1] - transit[0], alt.transition_step_m, 1e-3);
}

TEST(Terrain, ExportsCarryAbsoluteOrTakeOffRelativeHeights) {
  TempDir dir("terrain_exports");
  const Plan p = hill_plan(dir, "follow");
  const double home = p.mission.terrain->grid->at(p.mission.uavs[0].start_resolved);
  const auto items = waypoints::mission_items(p, 0);
  std::vector<double> amsl;
  for (const auto& it : items)
    if (it.command == waypoints::kNavWaypoint) amsl.push_back(it.alt);

  const auto qgc = exporting::qgc_plan(p, 0);
  EXPECT_EQ(qgc["mission"]["globalPlanAltitudeMode"], 2);
  EXPECT_NEAR(qgc["mission"]["plannedHomePosition"][2].get<double>(), home, 1e-6);
  for (const auto& j : qgc["mission"]["items"])
    if (j.contains("AltitudeMode")) {
      EXPECT_EQ(j["AltitudeMode"], 2);  // QGroundControl AltitudeModeAbsolute
      EXPECT_EQ(j["frame"], 0);         // MAV_FRAME_GLOBAL
    }

  std::istringstream wpl(exporting::wpl_text(p, 0));
  std::string line;
  std::getline(wpl, line);  // QGC WPL 110
  std::getline(wpl, line);  // home
  std::vector<std::string> cols;
  {
    std::istringstream row(line);
    for (std::string c; std::getline(row, c, '\t');) cols.push_back(c);
  }
  ASSERT_EQ(cols.size(), 12u);
  EXPECT_NEAR(std::stod(cols[10]), home, 1e-3);
  while (std::getline(wpl, line)) {
    std::istringstream row(line);
    std::vector<std::string> c;
    for (std::string s; std::getline(row, s, '\t');) c.push_back(s);
    if (c.at(3) == "16") {  // waypoints in MAV_FRAME_GLOBAL
      EXPECT_EQ(c.at(2), "0");
    }
  }

  // DJI and Litchi: heights above take-off = AMSL - the DEM's ground at take-off, waypoint by waypoint
  const auto dji = exporting::dji_wpml(p, 0);
  const std::string& wl = dji.at("wpmz/waylines.wpml");
  std::vector<double> dji_h;
  const std::regex h_re("<wpml:executeHeight>([-0-9.e]+)</wpml:executeHeight>");
  for (auto it = std::sregex_iterator(wl.begin(), wl.end(), h_re); it != std::sregex_iterator(); ++it)
    dji_h.push_back(std::stod((*it)[1]));
  ASSERT_EQ(dji_h.size(), amsl.size());
  for (std::size_t k = 0; k < amsl.size(); ++k) EXPECT_NEAR(dji_h[k], amsl[k] - home, 1e-3);
  const auto litchi = exporting::litchi_csv(p, 0);
  std::istringstream csv(litchi.at(0));
  std::getline(csv, line);  // header
  std::size_t k = 0;
  while (std::getline(csv, line) && k < amsl.size()) {
    std::istringstream row(line);
    std::vector<std::string> c;
    for (std::string s; std::getline(row, s, ',');) c.push_back(s);
    EXPECT_NEAR(std::stod(c.at(2)), amsl[k++] - home, 1e-3);
  }
  EXPECT_EQ(k, std::min<std::size_t>(amsl.size(), 99));

  // everything is exported, separation holds with AMSL heights
  EXPECT_NO_THROW(exporting::export_artifacts(p, {"qgc,wpl,kml,dji,litchi,csv"}));
}

TEST(Terrain, OffModeFliesFlatAboveTakeOffWithSafeTransit) {
  TempDir dir("terrain_off");
  const Plan p = hill_plan(dir, "off");
  const double home = p.mission.terrain->grid->at(p.mission.uavs[0].start_resolved);
  for (const auto& it : waypoints::mission_items(p, 0)) {
    EXPECT_NE(it.role, "terrain");
    if (it.role == "coverage") {
      EXPECT_NEAR(it.alt, home + 40.0, 1e-3);
    }
  }
}

TEST(Terrain, WithoutADemHeightsStayRelativeToTakeOff) {
  Mission m = parse_mission(testdem::mission_text("unused.tif"));
  m.terrain.reset();
  const Plan p = plan(m);
  for (const auto& it : waypoints::mission_items(p, 0)) {
    if (positioned(it)) {
      EXPECT_EQ(it.frame, waypoints::kFrameGlobalRelativeAlt);
    }
    EXPECT_NE(it.role, "terrain");
    if (it.role == "coverage") {
      EXPECT_FLOAT_EQ(it.alt, 40.0f);
    }
  }
  // a terrain block whose DEM was never read is refused, not flown flat
  Mission unread = parse_mission(testdem::mission_text("unused.tif"));
  Plan q = p;
  q.mission.terrain = unread.terrain;
  try {
    (void)waypoints::mission_items(q, 0);
    ADD_FAILURE() << "not refused";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "terrain.dem");
  }
}

int run(const std::string& cmd) {
  const int st = std::system(cmd.c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

TEST(Terrain, CommandLinePlansExportsAndRefusesBadDems) {
  TempDir dir("terrain_cli");
  testdem::write_hill(dir.path / "hill.tif", geodesy::LocalFrame(kOrigin), kHill);
  std::ofstream(dir.path / "mission.json") << testdem::mission_text("hill.tif");  // relative to the mission
  const std::string cli = UAVCOVER_CLI;
  const auto plan_dir = dir.path / "plan";
  ASSERT_EQ(run("cd / && " + cli + " -q plan " + (dir.path / "mission.json").string() + " --out " +
                plan_dir.string() + " --export qgc"),
            0);
  const auto pj = nlohmann::json::parse(testing::slurp(plan_dir / "plan.json"));
  EXPECT_EQ(pj["mission"]["terrain"]["dem"], (dir.path / "hill.tif").string());
  EXPECT_TRUE(pj.contains("terrain"));
  EXPECT_TRUE(std::filesystem::exists(plan_dir / "terrain-profile.png"));
  const auto qgc = nlohmann::json::parse(testing::slurp(plan_dir / "export" / "a.plan"));
  EXPECT_EQ(qgc["mission"]["globalPlanAltitudeMode"], 2);
  // `export` reads the DEM again from plan.json's absolute name
  ASSERT_EQ(
      run(cli + " -q export " + plan_dir.string() + " --format wpl --out " + (dir.path / "out").string()), 0);
  // bad DEM: exit 2 naming terrain.dem
  std::ofstream(dir.path / "bad.tif") << "not a tiff";
  std::ofstream(dir.path / "bad.json") << testdem::mission_text("bad.tif");
  const auto err = dir.path / "err.txt";
  EXPECT_EQ(run(cli + " -q plan " + (dir.path / "bad.json").string() + " --out " +
                (dir.path / "p2").string() + " 2>" + err.string()),
            2);
  EXPECT_NE(testing::slurp(err).find("terrain.dem"), std::string::npos) << testing::slurp(err);
}

}  // namespace
}  // namespace uavcover

namespace uavcover {
namespace {

// Issue 31, climb and descent limits: over the 60 m hill a 0.5 m/s limit at 5 m/s slows the steep legs
// (a DO_CHANGE_SPEED before each run of them, the cruise speed back after), their vertical speed at the
// flown speed stays within the limit, and plan() says where; max_grade is said, not changed.
TEST(Terrain, ClimbLimitsSlowTheSteepLegsAndSayWhere) {
  const TempDir dir("climb");
  testdem::write_hill(dir.path / "hill.tif", geodesy::LocalFrame(kOrigin), kHill);
  auto j = nlohmann::json::parse(testdem::mission_text("hill.tif"));
  j["terrain"]["max_climb_mps"] = 0.5;
  j["terrain"]["max_descent_mps"] = 0.5;
  j["terrain"]["max_grade"] = 0.2;
  Mission m = parse_mission(j.dump());
  io::load_terrain(m, dir.path);
  const Plan p = plan(m);
  int said = 0;
  for (const auto& w : p.warnings) said += w.find("terrain: the leg from (") != std::string::npos;
  EXPECT_GT(said, 0);
  const geodesy::LocalFrame f(p.origin);
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    SCOPED_TRACE(p.uavs[i].id);
    const auto items = waypoints::mission_items(p, i);
    const double cruise = p.mission.uavs[i].speed_mps;
    double speed = cruise;
    int slowed = 0;
    const MissionItem* prev = nullptr;
    for (const auto& it : items) {
      if (it.command == waypoints::kDoChangeSpeed) {
        speed = it.param2;
        if (speed < cruise) ++slowed;
        continue;
      }
      if (!positioned(it)) continue;
      if (prev != nullptr && in_leg(*prev) && in_leg(it) && prev->part == it.part) {
        const Point a = f.to_local({prev->lon, prev->lat}), b = f.to_local({it.lon, it.lat});
        const double d = std::hypot(b.x() - a.x(), b.y() - a.y());
        if (d > 0.01) {
          EXPECT_LE(std::fabs(it.alt - prev->alt) * speed / d, 0.5 + 1e-3) << it.lon << " " << it.lat;
        }
      }
      prev = &it;
    }
    EXPECT_GT(slowed, 0);
    EXPECT_EQ(speed, cruise);  // back to cruise before the end
  }
  // without limits: no speed item but the first
  const Plan free = hill_plan(dir);
  for (std::size_t i = 0; i < free.uavs.size(); ++i) {
    const auto items = waypoints::mission_items(free, i);
    EXPECT_EQ(std::count_if(items.begin(), items.end(),
                            [](const MissionItem& it) { return it.command == waypoints::kDoChangeSpeed; }),
              1);
  }
}

// Issue 31, the terrain frame: for ArduPilot the coverage waypoints carry their height above the ground in
// MAV_FRAME_GLOBAL_TERRAIN_ALT without terrain waypoints between them; take-off and transit stay AMSL;
// the .plan marks them AltitudeMode 4 in a mixed plan; PX4 and a plan without a DEM refuse it.
TEST(Terrain, TerrainFrameForArduPilot) {
  const TempDir dir("frame");
  const Plan p = hill_plan(dir);
  exporting::ExportOptions opt;
  opt.autopilot = "ardupilot";
  opt.altitude.terrain_frame = true;
  const auto items = waypoints::mission_items(p, 0, opt.altitude);
  int terrain = 0, amsl = 0;
  for (const auto& it : items) {
    if (!positioned(it)) continue;
    EXPECT_NE(it.role, "terrain");
    if (it.frame == waypoints::kFrameGlobalTerrainAlt) {
      ++terrain;
      EXPECT_FLOAT_EQ(it.alt, static_cast<float>(p.mission.altitude_m));
    } else {
      ++amsl;
      EXPECT_EQ(it.frame, waypoints::kFrameGlobal);
    }
  }
  EXPECT_GT(terrain, 4);
  EXPECT_GT(amsl, 1);
  const auto arts = exporting::export_artifacts(p, {"qgc,wpl"}, opt);
  const auto qgc =
      std::find_if(arts.begin(), arts.end(), [](const auto& a) { return a.name == "export/a.plan"; });
  ASSERT_NE(qgc, arts.end());
  const auto doc = nlohmann::json::parse(qgc->bytes);
  EXPECT_EQ(doc["mission"]["globalPlanAltitudeMode"], 0);
  int mode4 = 0;
  for (const auto& it : doc["mission"]["items"])
    mode4 += it.value("AltitudeMode", -1) == 4 && it["frame"] == 10;
  EXPECT_EQ(mode4, terrain);
  EXPECT_THROW(exporting::export_artifacts(p, {"dji"}, opt), InputError);  // WPML has its own heights
  opt.autopilot = "px4";
  EXPECT_THROW(exporting::export_artifacts(p, {"qgc"}, opt), InputError);
  Plan flat = p;
  flat.mission.terrain.reset();
  opt.autopilot = "ardupilot";
  try {
    (void)exporting::export_artifacts(flat, {"qgc"}, opt);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "terrain_frame");
  }
}

}  // namespace
}  // namespace uavcover
