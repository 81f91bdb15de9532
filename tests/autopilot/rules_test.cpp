// What the autopilots accept (issue 34): ArduPilot's and PX4's upload rules (src/autopilot/rules.hpp)
// on hand-made items, then on every item every MAVLink exporter writes (mission items, the .plan and the
// .waypoints read back) for every planner over the examples, both capture modes, several gimbal settings,
// with and without terrain following and per battery sortie; and the image estimate of plan.json against
// the shots the items make an autopilot take.
#include "autopilot/rules.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "export/export.hpp"
#include "geodesy/local_frame.hpp"
#include "io/dem.hpp"
#include "mavlink/mission_protocol.hpp"
#include "photo/photo.hpp"
#include "planners/planner.hpp"
#include "sorties/sorties.hpp"
#include "support/files.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover {
namespace {

using nlohmann::json;
namespace ex = exporting;
namespace wp = uavcover::waypoints;
namespace rules = autopilot;
namespace mav = mavlink;
namespace fs = std::filesystem;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

mav::MissionItemInt item(std::uint16_t command, std::uint8_t frame, float p1, float p2, float p3, float p4,
                         double lat = 47.39, double lon = 8.54, float z = 50) {
  mav::MissionItemInt m;
  m.command = command;
  m.frame = frame;
  m.param1 = p1;
  m.param2 = p2;
  m.param3 = p3;
  m.param4 = p4;
  m.x = static_cast<std::int32_t>(std::llround(lat * 1e7));
  m.y = static_cast<std::int32_t>(std::llround(lon * 1e7));
  m.z = z;
  return m;
}

TEST(ConsumerRules, ArduPilotSanityCheckParams) {
  // the item: the gimbal with NaN rates is refused at param 3
  EXPECT_EQ(rules::ardupilot_item_result(item(1000, 2, -90, 0, kNaN, kNaN, 0, 0, 0)),
            rules::kMissionInvalidParam1 + 2);
  EXPECT_EQ(rules::ardupilot_item_result(item(1000, 2, -90, 0, 0, kNaN, 0, 0, 0)),
            rules::kMissionInvalidParam1 + 3);
  EXPECT_EQ(rules::ardupilot_item_result(item(1000, 2, -90, 0, 0, 0, 0, 0, 0)), mav::kMissionAccepted);
  // NaN yaw (param 4) is allowed on waypoints, take-off and land only
  for (std::uint16_t c : {16, 21, 22})
    EXPECT_EQ(rules::ardupilot_item_result(item(c, 3, 0, 0, 0, kNaN)), mav::kMissionAccepted) << c;
  EXPECT_EQ(rules::ardupilot_item_result(item(16, 3, kNaN, 0, 0, kNaN)), rules::kMissionInvalidParam1);
  EXPECT_EQ(rules::ardupilot_item_result(item(16, 3, 0, 0, kNaN, kNaN)), rules::kMissionInvalidParam1 + 2);
  // VTOL_LAND may have NaN in 3 and 4; infinity is never allowed
  EXPECT_EQ(rules::ardupilot_item_result(item(85, 3, 0, 0, kNaN, kNaN)), mav::kMissionAccepted);
  EXPECT_EQ(rules::ardupilot_item_result(item(16, 3, 0, 0, 0, kInf)), rules::kMissionInvalidParam1 + 3);
  EXPECT_EQ(rules::ardupilot_item_result(item(206, 2, 0, kInf, 0, 0, 0, 0, 0)),
            rules::kMissionInvalidParam1 + 1);
  EXPECT_EQ(rules::ardupilot_item_result(item(178, 2, 1, 5, -1, kNaN, 0, 0, 0)),
            rules::kMissionInvalidParam1 + 3);
  EXPECT_EQ(rules::ardupilot_item_result(item(2000, 2, 0, 0, 1, 0, 0, 0, 0)), mav::kMissionAccepted);
}

TEST(ConsumerRules, ArduPilotCommandsAndLocations) {
  EXPECT_EQ(rules::ardupilot_item_result(item(0, 3, 0, 0, 0, 0)), mav::kMissionInvalid);
  EXPECT_EQ(rules::ardupilot_item_result(item(31999, 2, 0, 0, 0, 0)), mav::kMissionUnsupported);
  EXPECT_EQ(rules::ardupilot_item_result(item(16, 3, 0, 0, 0, 0, 91.0)), rules::kMissionInvalidParam5X);
  EXPECT_EQ(rules::ardupilot_item_result(item(16, 3, 0, 0, 0, 0, 47, 181.0)), rules::kMissionInvalidParam6Y);
  EXPECT_EQ(rules::ardupilot_item_result(item(16, 3, 0, 0, 0, 0, 47, 8, kNaN)), rules::kMissionInvalidParam7);
  EXPECT_EQ(rules::ardupilot_item_result(item(16, 3, 0, 0, 0, 0, 47, 8, 83000)),
            rules::kMissionInvalidParam7);
  EXPECT_EQ(rules::ardupilot_item_result(item(16, 1 /* LOCAL_NED */, 0, 0, 0, 0)),
            mav::kMissionUnsupportedFrame);
  // commands without a location: x, y, z and the frame are not checked
  EXPECT_EQ(rules::ardupilot_item_result(item(20, 1, 0, 0, 0, 0, 95.0, 200.0, kNaN)), mav::kMissionAccepted);
}

wp::MissionItem mi(std::uint16_t command, float p1, float p2, float p3, float p4, std::string role,
                   double lat = 0, double lon = 0, float alt = 0) {
  wp::MissionItem it;
  it.command = command;
  it.frame =
      (command == 16 || command == 21 || command == 22) ? wp::kFrameGlobalRelativeAlt : wp::kFrameMission;
  it.param1 = p1;
  it.param2 = p2;
  it.param3 = p3;
  it.param4 = p4;
  it.lat = lat;
  it.lon = lon;
  it.alt = alt;
  it.role = std::move(role);
  return it;
}

int fatal(const std::vector<rules::Problem>& ps) {
  int n = 0;
  for (const auto& p : ps) n += p.fatal ? 1 : 0;
  return n;
}

TEST(ConsumerRules, WholeMissionRules) {
  const LonLat home{8.54, 47.39};
  std::vector<wp::MissionItem> ok = {mi(22, 0, 0, 0, kNaN, "takeoff", 47.39, 8.54, 60),
                                     mi(178, 1, 5, -1, 0, "speed"),
                                     mi(16, 0, 0, 0, kNaN, "transit", 47.391, 8.54, 60),
                                     mi(2000, 0, 0, 1, 0, "camera"), mi(20, 0, 0, 0, 0, "rtl")};
  EXPECT_EQ(fatal(rules::ardupilot_problems(ok)), 0);
  EXPECT_EQ(fatal(rules::px4_problems(ok, home, 0)), 0);
  // hover-and-capture's old bug: the hold in IMAGE_START_CAPTURE param1 selects camera 4
  auto bad = ok;
  bad[3].param1 = 4;
  EXPECT_EQ(fatal(rules::ardupilot_problems(bad)), 1);
  // no take-off first: ArduCopter refuses AUTO, PX4 refuses a take-off after a waypoint
  bad = ok;
  std::swap(bad[0], bad[2]);
  EXPECT_GE(fatal(rules::ardupilot_problems(bad)), 1);
  EXPECT_GE(fatal(rules::px4_problems(bad, home, 0)), 1);
  // PX4: take-off below NAV_ACC_RAD + 1 m
  bad = ok;
  bad[0].alt = 10.5f;
  EXPECT_EQ(fatal(rules::px4_problems(bad, home, 0)), 1);
  rules::Px4Params small;
  small.nav_acc_rad_m = 2;
  EXPECT_EQ(fatal(rules::px4_problems(bad, home, 0, small)), 0);
  // PX4 runs only its list of mission commands
  bad = ok;
  bad[1].command = 115;  // CONDITION_YAW
  EXPECT_EQ(fatal(rules::px4_problems(bad, home, 0)), 1);
  EXPECT_EQ(fatal(rules::ardupilot_problems(bad)), 0);
  // capacity: a configurable limit, not fatal
  rules::ArduPilotLimits tiny;
  tiny.max_items = 5;
  const auto cap = rules::ardupilot_problems(ok, tiny);
  ASSERT_EQ(cap.size(), 1u);
  EXPECT_FALSE(cap.front().fatal);
  EXPECT_NE(rules::describe(cap.front(), ok).find("6 items"), std::string::npos);
}

// ---- every export of the examples --------------------------------------------------------------------

/// What the camera of an autopilot takes flying `items` (ArduPilot's AP_Camera): a shot at each
/// DO_SET_CAM_TRIGG_DIST with param3 1 and at each IMAGE_START_CAPTURE (camera 0), and every d metres
/// (horizontal distance from the last shot) while distance triggering is on; a shot at the place of the
/// previous one with nothing flown between is refused (the shutter is still held, CAMx_DURATION).
struct Shots {
  int taken = 0;
  /// a trigger command refused right after another trigger command at the same place (the double
  /// trigger of issue 34)
  int refused = 0;
  /// a leg's stop trigger at the place a distance shot was just taken (a leg whose length is a multiple
  /// of d, as on grid missions): one image either way, the estimate counts one
  int coincident = 0;
  int wrong_camera = 0;  ///< IMAGE_START_CAPTURE for another camera instance than all (0)
  int holds = 0;         ///< captures made while stopped at a waypoint with a hold time
};
Shots fly_camera(const std::vector<wp::MissionItem>& items, const LonLat& origin) {
  const geodesy::LocalFrame frame(origin);
  Shots out;
  double every = 0, travelled = 0;
  bool have = false;
  Point pos;
  float alt = 0, hold = 0;
  std::optional<std::pair<Point, float>> last_shot;
  bool moved = true, by_distance = false;
  auto shoot = [&](const Point& at, float z, bool distance = false) {
    if (last_shot && !moved &&
        std::hypot(at.x() - last_shot->first.x(), at.y() - last_shot->first.y()) < 1e-3 &&
        std::abs(z - last_shot->second) < 1e-3f) {
      ++(by_distance && !distance ? out.coincident : out.refused);
      return;
    }
    by_distance = distance;
    ++out.taken;
    last_shot = {at, z};
    moved = false;
    travelled = 0;
  };
  for (const auto& it : items) {
    if (it.command == wp::kNavWaypoint || it.command == wp::kNavTakeoff || it.command == wp::kNavLand) {
      const Point next = frame.to_local({it.lon, it.lat});
      if (have) {
        const double len = std::hypot(next.x() - pos.x(), next.y() - pos.y());
        if (len > 1e-6 || std::abs(it.alt - alt) > 1e-3f) moved = true;
        if (every > 0) {
          double s = 0;  // along this segment
          while (travelled + (len - s) >= every - 1e-6) {
            s += every - travelled;
            const double t = len > 0 ? std::min(1.0, s / len) : 1.0;
            moved = true;
            shoot(Point(pos.x() + t * (next.x() - pos.x()), pos.y() + t * (next.y() - pos.y())),
                  alt + static_cast<float>(t) * (it.alt - alt), true);
          }
          travelled += len - s;
        }
      }
      pos = next;
      alt = it.alt;
      hold = it.param1;
      have = true;
    } else if (it.command == wp::kDoSetCamTriggDist) {
      every = it.param1;
      travelled = 0;
      if (it.param3 == 1.0f) shoot(pos, alt);
    } else if (it.command == wp::kImageStartCapture) {
      if (it.param1 != 0.0f) {
        ++out.wrong_camera;
        continue;
      }
      out.holds += hold > 0 ? 1 : 0;
      shoot(pos, alt);
    }
  }
  return out;
}

/// The MAVLink items of a .plan (null = NaN) as the uploader would send them.
std::vector<mav::MissionItemInt> from_qgc(const json& doc) {
  std::vector<mav::MissionItemInt> out;
  for (const json& j : doc.at("mission").at("items")) {
    const json& p = j.at("params");
    auto num = [](const json& v) { return v.is_null() ? std::nan("") : v.get<double>(); };
    out.push_back(item(j.at("command").get<std::uint16_t>(), j.at("frame").get<std::uint8_t>(),
                       static_cast<float>(num(p[0])), static_cast<float>(num(p[1])),
                       static_cast<float>(num(p[2])), static_cast<float>(num(p[3])), num(p[4]), num(p[5]),
                       static_cast<float>(num(p[6]))));
  }
  return out;
}

/// The rows of a .waypoints file after home, as Mission Planner reads them (strtod reads "NaN").
std::vector<mav::MissionItemInt> from_wpl(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "QGC WPL 110");
  std::vector<mav::MissionItemInt> out;
  bool home = true;
  while (std::getline(in, line)) {
    std::vector<double> f;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, '\t')) f.push_back(std::strtod(cell.c_str(), nullptr));
    EXPECT_EQ(f.size(), 12u) << line;
    if (f.size() != 12) continue;
    if (home) {
      home = false;
      continue;
    }
    out.push_back(item(static_cast<std::uint16_t>(f[3]), static_cast<std::uint8_t>(f[2]),
                       static_cast<float>(f[4]), static_cast<float>(f[5]), static_cast<float>(f[6]),
                       static_cast<float>(f[7]), f[8], f[9], static_cast<float>(f[10])));
  }
  return out;
}

struct Sweep {
  int missions = 0;  ///< mission item lists checked
  int items = 0;
  int files = 0;       ///< .plan and .waypoints read back
  int images = 0;      ///< estimated (= taken) images compared
  int shared = 0;      ///< corners shot once for two legs
  int coincident = 0;  ///< stop triggers where a distance shot was just taken (see Shots)
};

/// Checks every MAVLink export of `p`: every item by both autopilots' rules, the files read back, and
/// the shots against the estimate.
void check_plan(const Plan& p, const std::string& what, Sweep& sweep) {
  SCOPED_TRACE(what);
  const auto est = photo::estimate(p);
  for (std::size_t u = 0; u < p.uavs.size(); ++u) {
    if (ex::idle(p.uavs[u])) continue;
    const auto items = wp::mission_items(p, u);
    ++sweep.missions;
    sweep.items += static_cast<int>(items.size());
    for (const auto& pr : rules::ardupilot_problems(items))
      EXPECT_FALSE(pr.fatal) << p.uavs[u].id << ": ArduPilot: " << rules::describe(pr, items);
    const LonLat home = p.mission.uavs[u].start_resolved;
    const double home_amsl =
        p.mission.terrain && p.mission.terrain->grid ? p.mission.terrain->grid->at(home) : 0.0;
    for (const auto& pr : rules::px4_problems(items, home, home_amsl))
      EXPECT_FALSE(pr.fatal) << p.uavs[u].id << ": PX4: " << rules::describe(pr, items);
    // the shots the autopilot takes are what plan.json estimates, and none is refused
    if (est) {
      const Shots s = fly_camera(items, p.origin);
      EXPECT_EQ(s.taken, est->uavs[u].images) << p.uavs[u].id;
      EXPECT_EQ(s.refused, 0) << p.uavs[u].id << ": a trigger the camera refuses";
      EXPECT_EQ(s.wrong_camera, 0) << p.uavs[u].id;
      const bool hover = (p.mission.uavs[u].camera ? p.mission.uavs[u].camera->capture
                                                   : p.mission.camera->capture) == "hover";
      if (hover) {
        EXPECT_EQ(s.holds, s.taken) << p.uavs[u].id << ": a capture without a hold";
      }
      sweep.images += s.taken;
      sweep.coincident += s.coincident;
      sweep.shared += est->uavs[u].shared_corners;
    }
  }
  // the files, read back: every item as the upload would send it
  std::vector<std::string> warnings;
  ex::ExportOptions opt;
  opt.warnings = &warnings;
  opt.check_separation = false;  // separation is tested elsewhere; this is about the items
  const auto artifacts = ex::export_artifacts(p, {"qgc", "wpl"}, opt);
  for (const auto& a : artifacts) {
    std::vector<mav::MissionItemInt> read;
    if (a.name.ends_with(".plan")) {
      read = from_qgc(json::parse(a.bytes));
    } else if (a.name.ends_with(".waypoints")) {
      read = from_wpl(a.bytes);
    } else {
      continue;
    }
    ++sweep.files;
    ASSERT_FALSE(read.empty()) << a.name;
    for (std::size_t k = 0; k < read.size(); ++k)
      EXPECT_EQ(rules::ardupilot_item_result(read[k]), mav::kMissionAccepted)
          << a.name << " item " << k + 1 << " (MAV_CMD " << read[k].command << ")";
  }
}

/// The camera variants of `base`: both capture modes, several gimbal pitches.
void check_variants(const Plan& base, const std::string& what, Sweep& sweep) {
  for (const std::string capture : {"distance", "hover"})
    for (const double pitch : {-90.0, -45.0, 0.0}) {
      Plan p = base;
      if (p.mission.camera) {
        p.mission.camera->capture = capture;
        p.mission.camera->gimbal_pitch_deg = pitch;
      }
      for (auto& u : p.mission.uavs)
        if (u.camera) {
          u.camera->capture = capture;
          u.camera->gimbal_pitch_deg = pitch;
        }
      check_plan(p, what + ", " + capture + ", gimbal " + std::to_string(pitch), sweep);
      if (pitch != -90.0) continue;
      // one mission per battery sortie
      for (std::size_t u = 0; u < p.uavs.size(); ++u) {
        if (ex::idle(p.uavs[u])) continue;
        const auto list = p.uavs[u].sorties.empty() ? sorties::cut_sorties(p, u) : p.uavs[u].sorties;
        for (const auto& s : list) {
          const Plan sp = sorties::sortie_plan(p, u, s);
          const auto items = wp::mission_items(sp, u);
          ++sweep.missions;
          sweep.items += static_cast<int>(items.size());
          for (const auto& pr : rules::ardupilot_problems(items))
            EXPECT_FALSE(pr.fatal) << what << " sortie " << s.index << ": " << rules::describe(pr, items);
          const LonLat home = sp.mission.uavs[u].start_resolved;
          const double home_amsl =
              sp.mission.terrain && sp.mission.terrain->grid ? sp.mission.terrain->grid->at(home) : 0.0;
          for (const auto& pr : rules::px4_problems(items, home, home_amsl))
            EXPECT_FALSE(pr.fatal) << what << " sortie " << s.index << ": " << rules::describe(pr, items);
        }
      }
    }
}

/// A mission of examples/ as v1 JSON with a camera (the mCPP example has none).
json example_v1(const std::string& name) {
  const fs::path path = fs::path(UAVCOVER_SOURCE_DIR) / "examples" / name;
  json j = json::parse(testing::slurp(path));
  if (!j.contains("camera")) {
    j = json::parse(mission_to_json(parse_mission(j.dump())));
    j.erase("spacing_m");
    j.erase("altitude_m");
    j["camera"] = {{"altitude_m", 40}, {"hfov_deg", 73.4}, {"overlap", 0.5}};
  }
  return j;
}

TEST(ConsumerRules, EveryExportOfTheExamplesForEveryPlanner) {
  Sweep sweep;
  int plans = 0;
  std::vector<std::string> skipped;
  for (const std::string name : {"olive-grove.json", "hill-terrain.json", "mcpp-darp-input.json"}) {
    const json base = example_v1(name);
    for (const auto& planner : planners::registry()) {
      json j = base;
      j["planner"] = planner.name;
      j.erase("planner_params");  // the example's are for its own planner
      // budgets that keep the sweep short; the rules do not depend on the plan's quality
      // (deterministic budgets only: node and resource counts, never wall time)
      if (planner.name == "darp")
        j["planner_params"] = {{"placement_evaluations", 50}, {"max_iterations", 2000}};
      if (planner.name == "milp") j["planner_params"] = {{"node_limit", 20}};
      if (planner.name == "smt")
        j["planner_params"] = {{"resource_limit", 200000}, {"resource_budget", 2000000}};
      Mission m;
      try {
        m = parse_mission(j.dump());
        if (m.terrain) io::load_terrain(m, fs::path(UAVCOVER_SOURCE_DIR) / "examples");
      } catch (const InputError& e) {
        skipped.push_back(name + "/" + planner.name + ": " + e.what());
        continue;
      }
      Plan p;
      try {
        p = plan(m);
      } catch (const InputError& e) {  // a planner that does not take this mission (e.g. no-fly zones)
        skipped.push_back(name + "/" + planner.name + ": " + e.what());
        continue;
      }
      ++plans;
      const std::string what = name + "/" + planner.name;
      check_variants(p, what, sweep);
      if (p.mission.terrain) {  // the same plan flown flat (terrain "off")
        Plan off = p;
        off.mission.terrain->mode = "off";
        check_variants(off, what + " terrain off", sweep);
      }
    }
  }
  // heterogeneous cameras: one UAV shoots with its own camera
  {
    json j = example_v1("olive-grove.json");
    j["planner"] = "boustrophedon";
    j["uavs"][0]["camera"] = {{"altitude_m", 50}, {"hfov_deg", 60}, {"overlap", 0.5}, {"front_overlap", 0.8}};
    check_variants(plan(parse_mission(j.dump())), "olive grove, own camera", sweep);
    ++plans;
  }
  for (const auto& s : skipped) std::cout << "[ skipped  ] " << s << "\n";
  std::cout << "[ checked  ] " << plans << " plans, " << sweep.missions << " missions, " << sweep.items
            << " items, " << sweep.files << " files; " << sweep.images << " images taken as estimated, "
            << sweep.shared << " shared corners, " << sweep.coincident << " leg ends on a distance shot\n";
  RecordProperty("plans", plans);
  RecordProperty("items", sweep.items);
  EXPECT_GE(plans, 6);
  EXPECT_GT(sweep.shared, 0) << "no shared corner: the double-trigger case was not exercised";
}

}  // namespace
}  // namespace uavcover

namespace uavcover {
namespace {

// issue 34 section 5 / issue 31's interface: the export option "autopilot" sets the .plan firmwareType
TEST(ConsumerRules, AutopilotSetsTheFirmwareType) {
  json j = example_v1("olive-grove.json");
  j["planner"] = "boustrophedon";
  const Plan p = plan(parse_mission(j.dump()));
  ex::ExportOptions opt;
  EXPECT_EQ(ex::qgc_plan(p, 0, opt)["mission"]["firmwareType"], 12);  // default: PX4
  opt.autopilot = "ardupilot";
  EXPECT_EQ(ex::qgc_plan(p, 0, opt)["mission"]["firmwareType"], 3);
  // the exported file too
  for (const auto& a : ex::export_artifacts(p, {"qgc"}, opt))
    EXPECT_EQ(json::parse(a.bytes)["mission"]["firmwareType"], 3) << a.name;
  opt.autopilot = "px4";
  EXPECT_EQ(ex::qgc_plan(p, 0, opt)["mission"]["firmwareType"], 12);
  opt.autopilot = "litchi";
  EXPECT_EQ(ex::qgc_plan(p, 0, opt)["mission"]["firmwareType"], 12);
  opt.qgc_firmware_type = 3;  // an explicit firmware type (the CLI's --firmware-type) wins
  EXPECT_EQ(ex::qgc_plan(p, 0, opt)["mission"]["firmwareType"], 3);

  // a bad value is refused naming the field, before anything is produced
  ex::ExportOptions bad;
  bad.autopilot = "APM";
  try {
    (void)ex::export_artifacts(p, {"qgc"}, bad);
    ADD_FAILURE() << "exported for autopilot 'APM'";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "autopilot");
    EXPECT_NE(std::string(e.what()).find("\"ardupilot\""), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)ex::qgc_plan(p, 0, bad), InputError);
}

}  // namespace
}  // namespace uavcover
