// The simulated vehicle as a TCP listener (issue 34): `uavcover upload --to tcp:...` (the real binary)
// uploads to it, a ground station over TCP arms and starts it and follows the flight, and a refused item
// leaves no partial mission behind (MISSION_CLEAR_ALL). Assertions are on what the vehicle stored and
// reported, never on wall time.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "io/plan_io.hpp"
#include "mavlink/mission_protocol.hpp"
#include "mavlink/stream.hpp"
#include "sim/sim_vehicle.hpp"
#include "waypoints/waypoints.hpp"

using namespace uavcover;
using namespace uavcover::mavlink;
using namespace std::chrono_literals;
namespace fs = std::filesystem;
namespace wp = uavcover::waypoints;

namespace {

struct CliResult {
  int code = -1;
  std::string out, err;
};

CliResult run_cli(const std::string& args, const fs::path& dir) {
  const std::string cmd = std::string("'") + UAVCOVER_CLI + "' " + args + " > '" + (dir / "out").string() +
                          "' 2> '" + (dir / "err").string() + "'";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::stringstream o, e;
  o << std::ifstream(dir / "out").rdbuf();
  e << std::ifstream(dir / "err").rdbuf();
  r.out = o.str();
  r.err = e.str();
  return r;
}

class SimOverTcp : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("uavcover-simtcp-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    const auto r = run_cli("-q plan '" + std::string(UAVCOVER_SOURCE_DIR) +
                               "/examples/olive-grove.json' -o '" + (dir_ / "plan").string() + "'",
                           dir_);
    ASSERT_EQ(r.code, 0) << r.err;
    plan_ = io::load_plan_dir(dir_ / "plan");
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string upload_args(std::uint16_t port) const {
    return "upload '" + (dir_ / "plan").string() + "' --uav " + plan_.uavs[0].id +
           " --to tcp:127.0.0.1:" + std::to_string(port);
  }
  fs::path dir_;
  Plan plan_;
};

struct RunningFleet {
  sim::Fleet fleet;
  std::jthread thread;
  RunningFleet(const std::vector<sim::VehicleConfig>& configs, double speedup)
      : fleet(configs, sim::FleetOptions{speedup, 0.05}) {
    thread = std::jthread([this](std::stop_token st) { fleet.run(st, 3 * 3600.0); });
  }
  sim::SimVehicle& vehicle() { return *fleet.vehicles().at(0); }
  void stop() {
    thread.request_stop();
    if (thread.joinable()) thread.join();
  }
};

sim::VehicleConfig tcp_vehicle() {
  sim::VehicleConfig c;
  c.sysid = 1;
  c.tcp = true;
  c.endurance_min = 600;
  return c;
}

// COMMAND_LONG over `link` until its COMMAND_ACK (resent every 200 ms, 25 times at most).
std::optional<std::uint8_t> command(Link& link, std::uint16_t cmd, float p1 = 0) {
  CommandLong c;
  c.command = cmd;
  c.param1 = p1;
  c.target_system = 1;
  c.target_component = 1;
  for (int attempt = 0; attempt < 25; ++attempt) {
    c.confirmation = static_cast<std::uint8_t>(attempt);
    link.send(c);
    const auto until = std::chrono::steady_clock::now() + 200ms;
    while (std::chrono::steady_clock::now() < until)
      if (auto r = link.receive(20ms))
        if (const auto* a = std::get_if<CommandAck>(&r->message); a && a->command == cmd) return a->result;
  }
  return std::nullopt;
}

}  // namespace

TEST_F(SimOverTcp, UploadWithTheCliThenFlyTheMissionOverTheSameTransport) {
  RunningFleet f({tcp_vehicle()}, 50.0);
  const std::uint16_t port = f.vehicle().port();
  ASSERT_NE(port, 0);
  const auto r = run_cli(upload_args(port), dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("items accepted by system 1"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("to tcp:127.0.0.1:" + std::to_string(port)), std::string::npos) << r.err;
  const std::size_t count = wp::mission_items(plan_, 0).size() + 1;  // + home

  // a ground station connects (the CLI's connection is gone: the vehicle takes the new client)
  TcpClientLink gcs(Endpoint{"127.0.0.1", port}, 255, 190);
  ASSERT_EQ(gcs.connect(2s), "");
  gcs.send(Heartbeat{});
  ASSERT_EQ(command(gcs, kCmdComponentArmDisarm, 1), kResultAccepted);
  ASSERT_EQ(command(gcs, kCmdMissionStart), kResultAccepted);
  std::vector<std::uint16_t> reached;
  const auto cap = std::chrono::steady_clock::now() + 120s;  // a bound against hangs, not a measurement
  while (std::chrono::steady_clock::now() < cap && (reached.empty() || reached.back() + 1U < count))
    if (auto m = gcs.receive(100ms))
      if (const auto* it = std::get_if<MissionItemReached>(&m->message)) reached.push_back(it->seq);
  f.stop();
  ASSERT_FALSE(reached.empty());
  EXPECT_EQ(reached.back() + 1U, count);
  for (std::size_t k = 1; k < reached.size(); ++k) EXPECT_LT(reached[k - 1], reached[k]);  // in order
  EXPECT_EQ(f.vehicle().stored_mission().size(), count);
  EXPECT_GE(f.vehicle().link().stats().connections, 2U);
}

TEST_F(SimOverTcp, ARefusedItemLeavesNoPartialMissionAndTheCliSaysSo) {
  sim::VehicleConfig c = tcp_vehicle();
  c.store_as_received = true;  // ArduPilot: items 0..3 stay stored when item 4 is refused
  c.refuse_item = 4;
  RunningFleet f({c}, 5.0);
  const auto r = run_cli(upload_args(f.vehicle().port()), dir_);
  f.stop();
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("MAV_MISSION_INVALID_PARAM3"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("the vehicle's mission was cleared"), std::string::npos) << r.err;
  EXPECT_TRUE(f.vehicle().stored_mission().empty());
}

TEST_F(SimOverTcp, NobodyListeningIsExitOneNamingTheAddress) {
  std::uint16_t port = 0;
  {
    TcpListenLink probe(Endpoint{"127.0.0.1", 0}, 1, 1);
    port = probe.local_port();
  }
  const auto r = run_cli(upload_args(port) + " --timeout 0.2 --retries 1", dir_);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("cannot connect to tcp:127.0.0.1:" + std::to_string(port)), std::string::npos)
      << r.err;
}
