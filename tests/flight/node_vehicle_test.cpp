// Issue 12, independent peer: a vehicle written on node-mavlink (tests/node/vehicle.js "fly") takes the
// place of our simulator. The flight uploads to it, arms it, starts it and follows its telemetry to the
// end: every waypoint reached, the flight done. Skipped only when node or tests/node/node_modules is
// missing (scripts/setup installs both).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "flight/flight.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;

const fs::path kNodeDir = fs::path(UAVCOVER_SOURCE_DIR) / "tests" / "node";

struct Quiet : flight::Observer {
  std::mutex m;
  std::vector<flight::LogRecord> records;
  void on_records(std::int64_t, const std::vector<flight::LogRecord>& r) override {
    std::lock_guard lock(m);
    records.insert(records.end(), r.begin(), r.end());
  }
  void on_changed(std::int64_t) override {}
};

std::string read_line(FILE* f) {
  std::string line;
  int c = 0;
  while ((c = std::fgetc(f)) != EOF && c != '\n') line += static_cast<char>(c);
  return line;
}

template <typename Pred>
bool wait_wall(std::chrono::seconds cap, Pred pred) {
  const auto until = std::chrono::steady_clock::now() + cap;
  while (!pred()) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(20ms);
  }
  return true;
}

TEST(NodeVehicle, AFlightFollowsANodeMavlinkVehicleToTheEnd) {
  if (std::system("node --version > /dev/null 2>&1") != 0) GTEST_SKIP() << "node is not installed";
  if (!fs::exists(kNodeDir / "node_modules" / "node-mavlink" / "package.json"))
    GTEST_SKIP() << "tests/node/node_modules missing (npm ci there)";
  // one UAV over a 120 m x 60 m field, 20 m lines
  const double lon0 = 22.95, lat0 = 40.60, mlat = 1.0 / 111320.0, mlon = mlat / std::cos(lat0 * M_PI / 180.0);
  auto at = [&](double x, double y) { return json::array({lon0 + x * mlon, lat0 + y * mlat}); };
  const json doc{
      {"area",
       {{"type", "Polygon"}, {"coordinates", {{at(0, 0), at(120, 0), at(120, 60), at(0, 60), at(0, 0)}}}}},
      {"spacing_m", 20},
      {"altitude_m", 25},
      {"uavs", {{{"id", "A"}, {"start", at(10, -20)}}}},
      {"seed", 5}};
  const Plan p = plan(parse_mission(doc.dump()));

  const std::string cmd = "node '" + (kNodeDir / "vehicle.js").string() + "' fly 7";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  const auto port = json::parse(read_line(pipe)).at("port").get<std::uint16_t>();

  flight::FlightConfig config;
  flight::VehicleBinding b;
  b.uav = "A";
  b.endpoint = {"127.0.0.1", port};
  b.sysid = 7;
  config.vehicles.push_back(b);
  Quiet obs;
  flight::Flight f(1, p, config, obs);
  f.start();
  f.command({"upload", "", std::nullopt});
  const bool ready = wait_wall(30s, [&] { return f.snapshot()["uavs"][0]["phase"] == "ready"; });
  EXPECT_TRUE(ready) << f.snapshot().dump();
  if (ready) {
    f.command({"start", "", std::nullopt});
    EXPECT_TRUE(wait_wall(40s, [&] { return f.finished(); })) << f.snapshot().dump();
  }
  f.stop();
  // {"items": [...]} as node-mavlink decoded them, {"fence": [...]} (issue 31), then {"flown": [seqs]}
  std::string uploaded, flown, fence;
  for (int k = 0; k < 4 && flown.empty(); ++k) {
    const std::string line = read_line(pipe);
    if (line.empty()) break;
    const json j = json::parse(line);
    if (j.contains("items")) uploaded = line;
    if (j.contains("fence")) fence = line;
    if (j.contains("flown")) flown = line;
  }
  EXPECT_EQ(::pclose(pipe), 0);
  // the geofence came after the mission with its own mission type: one inclusion polygon around
  // everything flown, each vertex a MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION with the vertex count
  ASSERT_FALSE(fence.empty());
  const json fence_items = json::parse(fence).at("fence");
  ASSERT_GE(fence_items.size(), 3U);
  for (const auto& it : fence_items) {
    EXPECT_EQ(it.at("command").get<int>(), 5001);
    EXPECT_EQ(it.at("param1").get<double>(), static_cast<double>(fence_items.size()));
    EXPECT_EQ(it.at("missionType").get<int>(), 1);
  }
  ASSERT_TRUE(ready);

  EXPECT_EQ(f.state(), "done");
  const json u = f.snapshot()["uavs"][0];
  const std::string wp = u["waypoints"];
  ASSERT_FALSE(wp.empty());
  EXPECT_EQ(wp, std::string(wp.size(), 'R'));
  EXPECT_EQ(u["phase"], "done");
  // the vehicle got the first sortie's items and flew every one of them
  const json items = json::parse(uploaded).at("items");
  const json seqs = json::parse(flown).at("flown");
  EXPECT_EQ(seqs.size(), items.size());
  int coverage = 0;
  for (const auto& it : items)
    coverage += it.at("command").get<int>() == 16 && std::abs(it.at("z").get<double>() - 25.0) < 1e-3;
  EXPECT_GE(coverage, static_cast<int>(wp.size()));
  // and the flight logged the ACKs of the vehicle's COMMAND_ACKs
  int acks = 0;
  {
    std::lock_guard lock(obs.m);
    for (const auto& r : obs.records) acks += r.kind == "ack";
  }
  EXPECT_GE(acks, 2);
}

}  // namespace
}  // namespace uavcover
