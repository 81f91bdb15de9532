// Issue 31, terrain in the server: a GeoTIFF uploaded through POST /api/v1/dems (checked as the CLI
// checks a DEM, stored content-addressed), a mission that names it with "terrain": {"dem_id": N}, its
// plan following the ground (AMSL heights in the exports); the tiles of `serve --dem-dir` with
// "source": "server"; and the refusals, each naming its field.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include "export/check.hpp"
#include "geodesy/local_frame.hpp"
#include "server/multipart.hpp"
#include "server/worker_fixture.hpp"
#include "support/dem.hpp"

namespace uavcover::server::testing {
namespace {

using nlohmann::json;

const LonLat kOrigin{22.95, 40.60};

std::string read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A 300 m x 200 m field on the hill, one UAV, 40 m above ground.
json field(const json& terrain) {
  const geodesy::LocalFrame f(kOrigin);
  json ring = json::array();
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{
           {-150, -100}, {150, -100}, {150, 100}, {-150, 100}, {-150, -100}}) {
    const LonLat p = f.to_wgs84({x, y});
    ring.push_back({p.lon, p.lat});
  }
  const LonLat s = f.to_wgs84({-160, -110});
  return {{"name", "hill field"}, {"area", {{"type", "Polygon"}, {"coordinates", {ring}}}}, {"spacing_m", 25},
          {"altitude_m", 40},     {"uavs", {{{"id", "a"}, {"start", {s.lon, s.lat}}}}},     {"seed", 3},
          {"terrain", terrain}};
}

class TerrainApi : public WorkerTest {
 protected:
  Answer upload(const std::string& name, const std::string& bytes) {
    return call("POST", "/api/v1/dems", form(part("file", name, bytes)), kHeaders);
  }
  /// Plans the mission and returns the QGC .plan of its UAV.
  json plan_and_export(const json& mission) {
    const store::Id id = create_mission(mission.dump());
    const Answer a = call("POST", "/api/v1/missions/" + std::to_string(id) + "/plans", "{}");
    EXPECT_EQ(a.status, 202) << a.body;
    const std::string url = "/api/v1/plans/" + std::to_string(a.json().at("id").get<store::Id>());
    const json job = wait_job(url, terminal);
    EXPECT_EQ(job.at("state"), "done") << job.dump();
    plan_url_ = url;
    const Answer e = call("GET", url + "/exports/qgc");
    EXPECT_EQ(e.status, 200) << e.body;
    return e.status == 200 ? json::parse(e.body) : json();
  }
  /// Every coverage waypoint of the .plan flies 40 m above the hill (AMSL heights, frame 0).
  void expect_follows_the_hill(const json& qgc) {
    ASSERT_TRUE(qgc.is_object());
    EXPECT_EQ(qgc["mission"]["globalPlanAltitudeMode"], 2);
    const geodesy::LocalFrame f(kOrigin);
    int checked = 0;
    for (const auto& it : qgc["mission"]["items"]) {
      if (it["command"] != 16 || it["frame"] != 0) continue;
      const LonLat p{it["params"][5].get<double>(), it["params"][4].get<double>()};
      const Point q = f.to_local(p);
      if (std::abs(q.x()) > 140 || std::abs(q.y()) > 90) continue;  // transit and turnaround points
      const double ground = hill_(q.x(), q.y());
      const double agl = it["params"][6].get<double>() - ground;
      if (agl > 60) continue;  // transit altitude
      EXPECT_NEAR(agl, 40.0, 2.0) << q.x() << " " << q.y();
      ++checked;
    }
    EXPECT_GT(checked, 10);
  }
  /// The web app's ground profile of the last plan: the flight 40 m above the hill over the coverage.
  void expect_profile() {
    const Answer a = call("GET", plan_url_ + "/profile?uav=a");
    ASSERT_EQ(a.status, 200) << a.body;
    const json p = a.json();
    EXPECT_NEAR(p["agl_min_m"].get<double>(), 40.0, 2.0);
    EXPECT_NEAR(p["agl_max_m"].get<double>(), 40.0, 2.0);
    ASSERT_GT(p["samples"].size(), 50U);
    int coverage = 0;
    for (const auto& s : p["samples"]) {
      const double ground = s[1].get<double>();
      EXPECT_GT(ground, 199.0);
      EXPECT_LT(ground, 261.0);
      coverage += s[3].get<bool>();
    }
    EXPECT_GT(coverage, 20);
    EXPECT_EQ(call("GET", plan_url_ + "/profile?uav=zz").error_field(), "uav");
  }
  testdem::Hill hill_{200.0, 60.0, 60.0, 0.0, 0.0};
  std::string plan_url_;
};

TEST_P(TerrainApi, UploadedDemIsStoredOnceAndPlansFollowIt) {
  const geodesy::LocalFrame f(kOrigin);
  const auto tif = testdem::write_hill(dir_ / "hill.tif", f, hill_);
  const std::string bytes = read_bytes(tif);
  Answer a = upload("hill.tif", bytes);
  ASSERT_EQ(a.status, 201) << a.body;
  const json dem = a.json();
  const auto id = dem.at("id").get<store::Id>();
  EXPECT_EQ(dem["size"], bytes.size());
  EXPECT_EQ(dem["sha256"].get<std::string>().size(), 64U);
  EXPECT_LT(dem["info"]["bbox"]["min_lon"].get<double>(), kOrigin.lon);
  EXPECT_GT(dem["info"]["bbox"]["max_lat"].get<double>(), kOrigin.lat);
  // the same bytes again: the stored one (content-addressed), 200
  a = upload("again.tif", bytes);
  EXPECT_EQ(a.status, 200) << a.body;
  EXPECT_EQ(a.json().at("id").get<store::Id>(), id);
  a = call("GET", "/api/v1/dems");
  ASSERT_EQ(a.status, 200);
  EXPECT_EQ(a.json()["items"].size(), 1U);
  EXPECT_EQ(a.json()["server_tiles"], false);
  EXPECT_EQ(call("GET", "/api/v1/dems/" + std::to_string(id)).json()["name"], "hill.tif");
  EXPECT_EQ(call("GET", "/api/v1/dems/999").status, 404);

  start_workers();
  expect_follows_the_hill(plan_and_export(field({{"dem_id", id}, {"tolerance_m", 1}})));
  expect_profile();
  // a flat plan has no profile
  json flat = field({});
  flat.erase("terrain");
  (void)plan_and_export(flat);
  EXPECT_EQ(call("GET", plan_url_ + "/profile").error_field(), "terrain");
}

TEST_P(TerrainApi, BadDemsAndTerrainBlocksAreRefusedNamingTheField) {
  const geodesy::LocalFrame f(kOrigin);
  testdem::DemSpec no_crs;
  no_crs.write_crs = false;
  Answer a = upload("flat.tif", read_bytes(testdem::write_hill(dir_ / "nocrs.tif", f, hill_, no_crs)));
  EXPECT_EQ(a.status, 422);
  EXPECT_EQ(a.error_field(), "file");
  EXPECT_NE(a.body.find("coordinate reference system"), std::string::npos) << a.body;
  a = upload("x.tif", "not a tiff at all");
  EXPECT_EQ(a.status, 422);
  EXPECT_EQ(a.error_field(), "file");
  EXPECT_EQ(call("POST", "/api/v1/dems", form(""), kHeaders).error_field(), "file");
  EXPECT_EQ(call("GET", "/api/v1/dems").json()["items"].size(), 0U);  // nothing stored
  // terrain blocks: a path on the server's disk, a DEM that is not stored, tiles the server has not
  auto refused = [&](const json& terrain) {
    const Answer r = call("POST", "/api/v1/missions", field(terrain).dump());
    EXPECT_EQ(r.status, 422) << r.body;
    return r.error_field();
  };
  EXPECT_EQ(refused({{"dem", "/etc/passwd"}}), "terrain.dem");
  EXPECT_EQ(refused({{"dem_id", 41}}), "terrain.dem_id");
  EXPECT_EQ(refused({{"source", "server"}}), "terrain.source");
  EXPECT_EQ(refused({{"source", "disk"}}), "terrain.source");
  EXPECT_EQ(refused({{"dem_id", 1}, {"source", "server"}}), "terrain");
}

TEST_P(TerrainApi, TheServersTileFolderServesSourceServer) {
  const geodesy::LocalFrame f(kOrigin);
  const auto tiles = dir_ / "tiles";
  std::filesystem::create_directories(tiles);
  (void)testdem::write_hill(tiles / "n40e022.tif", f, hill_);
  std::ofstream(tiles / "readme.txt") << "not a tile";
  close();
  export_config_.dem_dir = tiles;
  open();
  ctx_->config.dem_dir = tiles;
  EXPECT_EQ(call("GET", "/api/v1/dems").json()["server_tiles"], true);
  start_workers();
  expect_follows_the_hill(plan_and_export(field({{"source", "server"}})));
}

// Issue 31, the export route's options (the CLI's --terrain-frame, --split-capacity, --autopilot): the
// .waypoints in ArduPilot's terrain frame, the UAV's missions cut to its capacity and served as one zip
// (read with libzip), each variant apart from the default export in the cache; bad options name
// themselves (400), options the plan cannot take are refused naming them (422).
TEST_P(TerrainApi, ExportOptionsGiveTheTerrainFrameAndTheCapacitySplit) {
  const geodesy::LocalFrame f(kOrigin);
  const Answer a = upload("hill.tif", read_bytes(testdem::write_hill(dir_ / "hill.tif", f, hill_)));
  ASSERT_EQ(a.status, 201) << a.body;
  start_workers();
  json m = field({{"dem_id", a.json().at("id")}, {"tolerance_m", 1}});
  m["autopilot"] = "ardupilot";
  constexpr std::size_t kCapacity = 40;
  m["max_mission_items"] = kCapacity;
  const json whole = plan_and_export(m);
  ASSERT_TRUE(whole.is_object());
  const std::string base = plan_url_ + "/exports/";
  // the places of a .plan's waypoints (MAV_CMD_NAV_WAYPOINT), to 1e-7 degrees
  auto waypoints_of = [](const json& plan) {
    std::set<std::pair<long long, long long>> out;
    for (const auto& it : plan["mission"]["items"])
      if (it["command"] == 16)
        out.emplace(std::llround(it["params"][4].get<double>() * 1e7),
                    std::llround(it["params"][5].get<double>() * 1e7));
    return out;
  };
  ASSERT_GT(whole["mission"]["items"].size() + 1, kCapacity) << "the test needs a mission over the capacity";

  // the terrain frame: QGC WPL 110 lines "seq current frame command p1 p2 p3 p4 lat lon alt auto"
  Answer e = call("GET", base + "wpl?terrain_frame=true");
  ASSERT_EQ(e.status, 200) << e.body;
  std::istringstream lines(e.body);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line.rfind("QGC WPL 110", 0), 0U);
  int terrain = 0;
  while (std::getline(lines, line)) {
    std::istringstream in(line);
    std::vector<double> v;
    for (std::string field; std::getline(in, field, '\t');)
      v.push_back(std::strtod(field.c_str(), nullptr));  // NaN yaws
    ASSERT_EQ(v.size(), 12U) << line;
    if (v[2] == 10) {
      EXPECT_EQ(v[3], 16) << line;
      EXPECT_NEAR(v[10], 40.0, 1e-3) << line;  // metres above the ground
      ++terrain;
    }
  }
  EXPECT_GT(terrain, 4);
  const Answer amsl = call("GET", base + "wpl");
  ASSERT_EQ(amsl.status, 200);
  EXPECT_EQ(amsl.body.find("\t10\t16\t"), std::string::npos) << "the default stays AMSL";

  // the capacity split: one zip of whole missions, each within the capacity with ArduPilot's home
  e = call("GET", base + "qgc?split_capacity=true");
  ASSERT_EQ(e.status, 200) << e.body;
  const auto parts = check::unzip_bytes(e.body);
  ASSERT_GE(parts.size(), 2U);
  std::set<std::pair<long long, long long>> flown;
  int k = 1;
  for (const auto& [name, bytes] : parts) {
    EXPECT_TRUE(name.starts_with("a.s") && name.ends_with(".plan")) << name;
    const json part = json::parse(bytes);
    const auto& items = part["mission"]["items"];
    EXPECT_LE(items.size() + 1, kCapacity) << name;
    EXPECT_EQ(items.front()["command"], 22) << name << ": a whole mission takes off";
    EXPECT_TRUE(items.back()["command"] == 20 || items.back()["command"] == 21) << name;
    flown.merge(waypoints_of(part));
    EXPECT_TRUE(parts.contains("a.s" + std::to_string(k++) + ".plan"));
  }
  for (const auto& w : waypoints_of(whole)) EXPECT_TRUE(flown.contains(w)) << "the parts fly every waypoint";
  // the default export is still the single .plan (its own cache entry)
  EXPECT_EQ(json::parse(call("GET", base + "qgc").body)["mission"]["items"], whole["mission"]["items"]);

  // refusals name the option
  e = call("GET", base + "qgc?terrain_frame=maybe");
  EXPECT_EQ(e.status, 400);
  EXPECT_EQ(e.error_field(), "terrain_frame");
  e = call("GET", base + "qgc?autopilot=betaflight");
  EXPECT_EQ(e.status, 400);
  EXPECT_EQ(e.error_field(), "autopilot");
  e = call("GET", base + "qgc?terrain_frame=true&autopilot=px4");
  EXPECT_EQ(e.status, 422) << e.body;
  EXPECT_EQ(e.error_field(), "terrain_frame");
  e = call("GET", base + "dji?terrain_frame=1");
  EXPECT_EQ(e.status, 422) << e.body;
  EXPECT_EQ(e.error_field(), "terrain_frame");
}

INSTANTIATE_TEST_SUITE_P(Stores, TerrainApi, ::testing::ValuesIn(uavcover::testing::store_test_urls()),
                         backend_name);

}  // namespace
}  // namespace uavcover::server::testing
