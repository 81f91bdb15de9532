// End to end: `uavcover upload` (the real binary) against our simulated vehicle on 127.0.0.1.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include <cmath>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "io/plan_io.hpp"
#include "mavlink/mission_protocol.hpp"
#include "mavlink/stream.hpp"
#include "waypoints/waypoints.hpp"

using namespace uavcover;
using namespace uavcover::mavlink;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

struct CliResult {
  int code = -1;
  std::string out, err;
};

CliResult run_cli(const std::string& args, const fs::path& dir) {
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string cmd =
      std::string("'") + UAVCOVER_CLI + "' " + args + " > '" + out.string() + "' 2> '" + err.string() + "'";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::stringstream o, e;
  o << std::ifstream(out).rdbuf();
  e << std::ifstream(err).rdbuf();
  r.out = o.str();
  r.err = e.str();
  return r;
}

class CliUpload : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("uavcover-upload-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    plan_dir_ = dir_ / "plan";
    const auto r = run_cli("-q plan '" + std::string(UAVCOVER_SOURCE_DIR) +
                               "/examples/olive-grove.json' -o '" + plan_dir_.string() + "'",
                           dir_);
    ASSERT_EQ(r.code, 0) << r.err;
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_, plan_dir_;
};

struct VehicleThread {
  UdpLink link;
  Vehicle vehicle;
  std::atomic<bool> stop{false};
  std::thread thread;
  explicit VehicleThread(std::uint8_t sysid) : link(Endpoint{"127.0.0.1", 0}, sysid, 1), vehicle(link) {
    // until joined: after the mission come the fence and the rally points (issue 31)
    thread = std::thread([this] { vehicle.run(30s, &stop); });
  }
  ~VehicleThread() { join(); }
  void join() {
    stop = true;
    if (thread.joinable()) thread.join();
  }
  [[nodiscard]] std::string address() const { return "udp:127.0.0.1:" + std::to_string(link.local_port()); }
};

}  // namespace

TEST_F(CliUpload, UploadsTheExportedMissionWithHomeFirst) {
  const Plan plan = io::load_plan_dir(plan_dir_);
  ASSERT_GE(plan.uavs.size(), 2U);
  const std::size_t index = 1;
  const std::string id = plan.uavs[index].id;
  VehicleThread v(1);
  const auto r = run_cli("upload '" + plan_dir_.string() + "' --uav " + id + " --to " + v.address(), dir_);
  v.join();
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("items accepted by system 1"), std::string::npos) << r.out;
  const auto exported = waypoints::mission_items(plan, index);
  const LonLat home = plan.mission.uavs[index].start_resolved;
  auto want = to_mission_items(exported, home);
  const auto& got = v.vehicle.mission();
  ASSERT_EQ(got.size(), exported.size() + 1);
  for (std::size_t i = 0; i < want.size(); ++i) {
    want[i].target_system = 1;
    want[i].target_component = 1;
    // positioned items carry yaw NaN ("keep heading"), the gimbal item unset rates (NaN), which no float
    // compares equal to
    MissionItemInt g = got[i];
    for (auto member : {&MissionItemInt::param1, &MissionItemInt::param2, &MissionItemInt::param3,
                        &MissionItemInt::param4}) {
      EXPECT_EQ(std::isnan(g.*member), std::isnan(want[i].*member)) << "item " << i;
      if (std::isnan(g.*member) && std::isnan(want[i].*member)) g.*member = want[i].*member = 0.0F;
    }
    EXPECT_EQ(g, want[i]) << "item " << i;
  }
  // item 0: home; item 1: take-off at the UAV's transition altitude
  EXPECT_EQ(got[0].x, static_cast<std::int32_t>(std::llround(home.lat * 1e7)));
  EXPECT_EQ(got[0].y, static_cast<std::int32_t>(std::llround(home.lon * 1e7)));
  EXPECT_EQ(got[1].command, waypoints::kNavTakeoff);
  EXPECT_FLOAT_EQ(got[1].z,
                  static_cast<float>(waypoints::transition_altitude({}, index, plan.mission.altitude_m)));
}

TEST_F(CliUpload, NoHomeSendsTheItemsOnly) {
  const Plan plan = io::load_plan_dir(plan_dir_);
  VehicleThread v(4);
  const auto r = run_cli("-q upload '" + plan_dir_.string() + "' --uav " + plan.uavs[0].id + " --to " +
                             v.address() + " --target-system 4 --no-home --land",
                         dir_);
  v.join();
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.out.empty());  // --quiet
  waypoints::AltitudeOptions alt;
  alt.land_instead_of_rtl = true;
  const auto exported = waypoints::mission_items(plan, 0, alt);
  ASSERT_EQ(v.vehicle.mission().size(), exported.size());
  EXPECT_EQ(v.vehicle.mission().front().command, waypoints::kNavTakeoff);
  EXPECT_EQ(v.vehicle.mission().back().command, waypoints::kNavLand);
}

TEST_F(CliUpload, BadInputIsExitCode2AndSilenceIs1) {
  const Plan plan = io::load_plan_dir(plan_dir_);
  const std::string base = "upload '" + plan_dir_.string() + "' ";
  auto r = run_cli(base + "--uav " + plan.uavs[0].id + " --to ftp:127.0.0.1:5760", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--to"), std::string::npos) << r.err;
  for (const char* bad :
       {"tcp:127.0.0.1", "tcpin:127.0.0.1:0", "serial:/dev/ttyUSB0:12345", "serial:ttyS0:9600"}) {
    r = run_cli(base + "--uav " + plan.uavs[0].id + " --to " + bad, dir_);
    EXPECT_EQ(r.code, 2) << bad;
    EXPECT_NE(r.err.find("--to: "), std::string::npos) << bad << ": " << r.err;
  }
  // a serial device that is not there: exit 1, naming it
  r = run_cli(base + "--uav " + plan.uavs[0].id + " --to serial:/dev/uavcover-no-such-tty:57600", dir_);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("/dev/uavcover-no-such-tty"), std::string::npos) << r.err;
  r = run_cli(base + "--uav " + plan.uavs[0].id + " --to udp:127.0.0.1:99999", dir_);
  EXPECT_EQ(r.code, 2);
  r = run_cli(base + "--uav nobody --to udp:127.0.0.1:14550", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--uav"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(plan.uavs[0].id), std::string::npos) << r.err;  // lists the ids it has
  r = run_cli(base + "--uav " + plan.uavs[0].id + " --to udp:127.0.0.1:14550 --timeout 0", dir_);
  EXPECT_EQ(r.code, 2);
  // Nobody answers: gives up after the retries, exit 1.
  UdpLink silent(Endpoint{"127.0.0.1", 0}, 1, 1);
  r = run_cli(base + "--uav " + plan.uavs[0].id + " --to udp:127.0.0.1:" +
                  std::to_string(silent.local_port()) + " --timeout 0.05 --retries 2",
              dir_);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("no answer from the vehicle after 2 retries"), std::string::npos) << r.err;
}

// Issue 34: a vehicle that refuses an item and then ignores MISSION_CLEAR_ALL keeps a truncated mission;
// the CLI fails (exit 1) and says so loudly.
TEST_F(CliUpload, RefusedAndNotClearedWarnsOfAPartialMission) {
  const Plan plan = io::load_plan_dir(plan_dir_);
  VehicleOptions vo;
  vo.store_as_received = true;
  vo.refuse_item = 3;
  TcpListenLink link(Endpoint{"127.0.0.1", 0}, 1, 1);
  Vehicle vehicle(link, vo);
  std::atomic<bool> stop{false};
  std::size_t clears_ignored = 0;
  std::thread t([&] {
    while (!stop) {
      if (auto r = link.receive(20ms)) {
        if (std::holds_alternative<MissionClearAll>(r->message))
          ++clears_ignored;
        else
          vehicle.handle(*r);
      }
      vehicle.on_timeout();
    }
  });
  const auto r =
      run_cli("upload '" + plan_dir_.string() + "' --uav " + plan.uavs[0].id +
                  " --to tcp:127.0.0.1:" + std::to_string(link.local_port()) + " --timeout 0.1 --retries 2",
              dir_);
  stop = true;
  t.join();
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("MAV_MISSION_INVALID_PARAM3"), std::string::npos) << r.err;
  EXPECT_NE(
      r.err.find("WARNING: MISSION_CLEAR_ALL was not acknowledged: the vehicle may hold a partial mission"),
      std::string::npos)
      << r.err;
  EXPECT_EQ(clears_ignored, 3U);  // the clear and its 2 resends
  EXPECT_EQ(vehicle.mission().size(), 3U);
}

// Issue 31: after the mission, the geofence (inclusion polygon around everything flown, no-fly zones as
// exclusions) and the rally points, each with its own mission type; --no-fence leaves them out.
TEST_F(CliUpload, SendsTheFenceAndTheRallyPointsAfterTheMission) {
  // the olive grove with the planner's proposed rally points
  std::stringstream src;
  src << std::ifstream(fs::path(UAVCOVER_SOURCE_DIR) / "examples" / "olive-grove.json").rdbuf();
  std::string text = src.str();
  const auto brace = text.find('{');
  text.insert(brace + 1, "\"propose_rally\": true, ");
  const fs::path mission = dir_ / "rally.json", rally_dir = dir_ / "rally-plan";
  std::ofstream(mission) << text;
  auto r = run_cli("-q plan '" + mission.string() + "' -o '" + rally_dir.string() + "'", dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  const Plan plan = io::load_plan_dir(rally_dir);
  ASSERT_EQ(plan.rally.size(), plan.uavs.size());
  VehicleThread v(1);
  r = run_cli("upload '" + rally_dir.string() + "' --uav " + plan.uavs[0].id + " --to " + v.address(), dir_);
  v.join();
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("fence items accepted"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("rally items accepted"), std::string::npos) << r.out;
  EXPECT_FALSE(v.vehicle.mission().empty());
  const auto& fence = v.vehicle.fence();
  ASSERT_GE(fence.size(), 3U);
  std::size_t exclusion = 0;
  for (const auto& it : fence) {
    EXPECT_TRUE(it.command == 5001 || it.command == 5002) << it.command;
    EXPECT_EQ(it.mission_type, kMissionTypeFence);
    exclusion += it.command == 5002;
  }
  std::size_t zone_vertices = 0;
  for (const auto& z : plan.mission.no_fly_zones) zone_vertices += z.front().size() - 1;
  EXPECT_EQ(exclusion, zone_vertices);
  const auto& rally = v.vehicle.rally();
  ASSERT_EQ(rally.size(), plan.rally.size());
  for (std::size_t k = 0; k < rally.size(); ++k) {
    EXPECT_EQ(rally[k].command, 5100);
    EXPECT_EQ(rally[k].x, static_cast<std::int32_t>(std::llround(plan.rally[k].lat * 1e7)));
    EXPECT_EQ(rally[k].y, static_cast<std::int32_t>(std::llround(plan.rally[k].lon * 1e7)));
  }
  VehicleThread bare(2);
  r = run_cli("-q upload '" + rally_dir.string() + "' --uav " + plan.uavs[0].id + " --to " + bare.address() +
                  " --target-system 2 --no-fence",
              dir_);
  bare.join();
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(bare.vehicle.mission().empty());
  EXPECT_TRUE(bare.vehicle.fence().empty());
  EXPECT_TRUE(bare.vehicle.rally().empty());
}

// Issue 31: a mission over the vehicle's capacity is refused before anything is sent (a real vehicle
// answers MAV_MISSION_NO_SPACE halfway, or drops items), naming the option and the split export.
TEST_F(CliUpload, OverCapacityIsRefusedBeforeAnythingIsSent) {
  const Plan plan = io::load_plan_dir(plan_dir_);
  VehicleThread v(1);
  const auto r = run_cli("upload '" + plan_dir_.string() + "' --uav " + plan.uavs[0].id + " --to " +
                             v.address() + " --max-items 20",
                         dir_);
  v.join();
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--max-items"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nothing was sent"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--split-capacity"), std::string::npos) << r.err;
  EXPECT_EQ(v.vehicle.stats().requests_sent, 0U);
  EXPECT_TRUE(v.vehicle.mission().empty());
}
