// (5) node-mavlink (tests/node/decode.js, an implementation that is not ours) decodes the raw telemetry
// stream of a simulated vehicle in flight without a checksum error or an unknown message.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "geodesy/local_frame.hpp"
#include "mavlink/frame.hpp"
#include "mavlink/mission_protocol.hpp"
#include "mavlink/test_util.hpp"
#include "sim/sim_vehicle.hpp"

using namespace uavcover;
using namespace uavcover::mavlink;
namespace fs = std::filesystem;

namespace {

const fs::path kNodeDir = fs::path(UAVCOVER_SOURCE_DIR) / "tests" / "node";

std::vector<MissionItemInt> short_mission(LonLat home) {
  geodesy::LocalFrame f(home);
  std::vector<MissionItemInt> m;
  auto item = [&](std::uint16_t cmd, double x, double y, float z, std::uint8_t frame) {
    MissionItemInt it;
    it.command = cmd;
    it.frame = frame;
    const LonLat ll = f.to_wgs84(Point(x, y));
    it.x = static_cast<std::int32_t>(std::llround(ll.lat * 1e7));
    it.y = static_cast<std::int32_t>(std::llround(ll.lon * 1e7));
    it.z = z;
    m.push_back(it);
  };
  item(22, 0, 0, 10, 3);
  item(16, 40, 0, 10, 3);
  item(16, 40, 40, 10, 3);
  item(21, 0, 0, 0, 3);
  return m;
}

}  // namespace

TEST(SimNodePeer, DecodesTheTelemetryStream) {
  if (std::system("node --version > /dev/null 2>&1") != 0) GTEST_SKIP() << "node is not installed";
  if (!fs::exists(kNodeDir / "node_modules" / "node-mavlink" / "package.json"))
    GTEST_SKIP() << "tests/node/node_modules missing (npm ci there)";

  // a raw UDP socket as the ground station: it keeps the datagrams as bytes
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_in me{};
  me.sin_family = AF_INET;
  me.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&me), sizeof me), 0);
  socklen_t len = sizeof me;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&me), &len);

  sim::VehicleConfig c;
  c.sysid = 7;
  c.home = LonLat{22.95, 40.60};
  c.endurance_min = 1.0;  // the battery runs low during the flight: STATUSTEXT warnings too
  sim::Fleet fleet({c}, sim::FleetOptions{50.0, 0.05});
  auto& v = *fleet.vehicles()[0];
  v.set_peer(Endpoint{"127.0.0.1", ntohs(me.sin_port)});
  v.set_mission(short_mission(*c.home));
  ASSERT_EQ(v.arm(true), kResultAccepted);
  ASSERT_EQ(v.start_mission(), kResultAccepted);
  std::jthread run([&](std::stop_token st) { fleet.run(st, 90.0); });

  std::string hex;
  std::size_t datagrams = 0;
  while (true) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 1000) <= 0) break;  // the fleet stopped (90 simulated seconds)
    std::uint8_t buf[2048];
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) break;
    hex += mavtest::to_hex(std::vector<std::uint8_t>(buf, buf + n)) + "\n";
    ++datagrams;
  }
  run.join();
  ::close(fd);
  ASSERT_GT(datagrams, 100U);

  const fs::path dir = fs::temp_directory_path() / ("uavcover-simnode-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "in.txt") << hex;
  const std::string cmd = "node '" + (kNodeDir / "decode.js").string() + "' < '" + (dir / "in.txt").string() +
                          "' > '" + (dir / "out.txt").string() + "'";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream out(dir / "out.txt");
  std::map<std::string, std::size_t> names;
  nlohmann::json summary;
  std::vector<std::uint16_t> reached;
  std::string line;
  while (std::getline(out, line)) {
    if (line.empty()) continue;
    const auto j = nlohmann::json::parse(line);
    if (j.contains("summary")) {
      summary = j["summary"];
      continue;
    }
    EXPECT_EQ(j["sysid"], 7);
    ++names[j["name"].get<std::string>()];
    if (j["name"] == "MISSION_ITEM_REACHED") reached.push_back(j["fields"]["seq"].get<std::uint16_t>());
    if (j["name"] == "GLOBAL_POSITION_INT") {
      EXPECT_NEAR(j["fields"]["lat"].get<double>() * 1e-7, 40.60, 0.01);
      EXPECT_NEAR(j["fields"]["lon"].get<double>() * 1e-7, 22.95, 0.01);
    }
  }
  fs::remove_all(dir);
  EXPECT_EQ(summary["invalid"], 0);
  EXPECT_EQ(summary["unknown"], 0);
  EXPECT_EQ(summary["valid"], datagrams);
  for (const char* n : {"HEARTBEAT", "GLOBAL_POSITION_INT", "MISSION_CURRENT", "MISSION_ITEM_REACHED",
                        "SYS_STATUS", "BATTERY_STATUS", "STATUSTEXT"})
    EXPECT_GT(names[n], 0U) << n;
  EXPECT_EQ(reached, (std::vector<std::uint16_t>{0, 1, 2, 3}));
}
