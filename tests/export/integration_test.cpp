// The exports on a real plan: parse a mission, plan it with the facade, write and reload the plan
// folder, export every format, and check separation, the grid convention and the trajectories.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "codec/plan_codec.hpp"
#include "export/export.hpp"
#include "export/separation.hpp"
#include "io/plan_io.hpp"
#include "trajectory/trajectory.hpp"
#include "uavcover/uavcover.hpp"

using namespace uavcover;
namespace fs = std::filesystem;

namespace {

const char* kMission = R"({
  "name": "export integration",
  "area": {"type": "Polygon", "coordinates": [[[8.5445711, 47.3966865], [8.5475586, 47.3978563],
      [8.5468289, 47.3987135], [8.5438414, 47.3975437], [8.5445711, 47.3966865]]]},
  "no_fly_zones": [{"type": "Polygon", "coordinates": [[[8.5461442, 47.3977181], [8.546374, 47.3978081],
      [8.5462413, 47.3979639], [8.5460115, 47.3978739], [8.5461442, 47.3977181]]]}],
  "spacing_m": 12,
  "altitude_m": 35,
  "uavs": [{"id": "east", "share": 0.5, "start": [8.5478879, 47.3978294], "speed_mps": 6, "max_accel_mps2": 2.5},
           {"id": "west", "share": 0.5, "start": [8.5444408, 47.3964796]}],
  "mode": "strict",
  "seed": 3
})";

}  // namespace

TEST(ExportIntegration, RealPlanThroughThePlanFolder) {
  Mission mission = parse_mission(kMission);
  mission.planner_params["placement_evaluations"] = 200;
  const Plan planned = plan(mission);
  const fs::path dir =
      fs::temp_directory_path() / ("uavcover_export_integration_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  io::write_file_atomic(dir / "paths.geojson", codec::paths_geojson(planned).dump(1) + "\n");
  io::write_file_atomic(dir / "plan.json", codec::plan_json(planned).dump(1) + "\n");
  const Plan loaded = io::load_plan_dir(dir);
  ASSERT_EQ(loaded.uavs.size(), 2u);

  const double rotation = planned.diagnostics.at("grid").at("rotation_deg").get<double>();
  RecordProperty("grid_rotation_deg", std::to_string(rotation));
  // the area is a rectangle rotated by 30 degrees: the grid follows it, so the regions are rotated too
  EXPECT_GT(std::abs(std::remainder(rotation, 90.0)), 1.0);
  // every coverage waypoint lies in (or on the edge of) its own UAV's region, and separation holds
  for (const Plan* p : {&planned, &loaded}) {
    const exporting::RegionMap regions(*p);
    for (std::size_t u = 0; u < p->uavs.size(); ++u)
      for (const auto& part : p->uavs[u].parts)
        if (part.kind == PartKind::Coverage)
          for (const auto& pt : part.local) {
            const int o = regions.owner(pt);
            EXPECT_TRUE(o == static_cast<int>(u) || o == -1) << p->uavs[u].id;
          }
    const auto problems = exporting::check_separation(*p, {});
    EXPECT_TRUE(problems.empty()) << (problems.empty() ? "" : problems.front());
  }
  // the reloaded plan gives the same mission items as the planned one
  for (std::size_t u = 0; u < 2; ++u) {
    const auto a = waypoints::mission_items(planned, u);
    const auto b = waypoints::mission_items(loaded, u);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
      EXPECT_EQ(a[k].command, b[k].command);
      EXPECT_NEAR(a[k].lat, b[k].lat, 1e-9);
      EXPECT_NEAR(a[k].lon, b[k].lon, 1e-9);
      EXPECT_FLOAT_EQ(a[k].alt, b[k].alt);
    }
  }
  // every format is written; the GeoJSON validates; trajectories respect each UAV's limits
  const auto files =
      io::write_artifacts(dir, exporting::export_artifacts(loaded, exporting::known_formats()));
  EXPECT_EQ(files.size(), 18u);
  for (std::size_t u = 0; u < 2; ++u) {
    std::ifstream in(dir / "export" / (loaded.uavs[u].id + ".geojson"));
    EXPECT_TRUE(exporting::validate_geojson(nlohmann::json::parse(in)).empty());
    const auto traj = trajectory::uav_trajectory(loaded, u);
    const Uav& uav = loaded.mission.uavs[u];
    for (const auto& s : traj.sample(0.2)) {
      ASSERT_LE(std::hypot(s.v[0], s.v[1], s.v[2]), uav.speed_mps * (1 + 1e-9));
      ASSERT_LE(std::hypot(s.a[0], s.a[1], s.a[2]), uav.max_accel_mps2 * (1 + 1e-9));
    }
    EXPECT_GT(traj.duration(), loaded.uavs[u].length_m / uav.speed_mps);
  }
  // the lead's paths.geojson validates too
  std::ifstream in(dir / "paths.geojson");
  const auto problems = exporting::validate_geojson(nlohmann::json::parse(in));
  EXPECT_TRUE(problems.empty()) << (problems.empty() ? "" : problems.front());
  fs::remove_all(dir);
}
