// The simulated fleet over real UDP on loopback: a ground station (our upload_mission / `uavcover upload`
// and COMMAND_LONG) drives simulated vehicles and checks their telemetry. Assertions are on simulated
// time and on what the vehicles report, never on wall time.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <thread>

#include "autopilot/fence.hpp"
#include "autopilot/rules.hpp"
#include "geodesy/local_frame.hpp"
#include "io/plan_io.hpp"
#include "mavlink/mission_protocol.hpp"
#include "sim/sim_vehicle.hpp"
#include "uavcover/error.hpp"
#include "waypoints/waypoints.hpp"

using namespace uavcover;
using namespace uavcover::mavlink;
using namespace std::chrono_literals;
namespace fs = std::filesystem;
namespace wp = uavcover::waypoints;

namespace {

const LonLat kHome{22.95, 40.60};

wp::MissionItem takeoff_at_home(float alt) {
  wp::MissionItem takeoff;
  takeoff.command = wp::kNavTakeoff;
  takeoff.lat = kHome.lat;
  takeoff.lon = kHome.lon;
  takeoff.alt = alt;
  return takeoff;
}

wp::MissionItem return_to_launch() {
  wp::MissionItem rtl;
  rtl.command = wp::kNavReturnToLaunch;
  rtl.frame = wp::kFrameMission;
  return rtl;
}

// home, take-off to 30 m, 10 m/s, a 300 m square (3 legs, each cut into `per_side` waypoints), RTL:
// about 1.2 km and 160 s.
std::vector<MissionItemInt> square_mission(int per_side = 1, double side = 300.0, double speed = 10.0) {
  geodesy::LocalFrame f(kHome);
  std::vector<wp::MissionItem> items{takeoff_at_home(30)};
  wp::MissionItem spd;
  spd.command = wp::kDoChangeSpeed;
  spd.frame = wp::kFrameMission;
  spd.param1 = 1;
  spd.param2 = static_cast<float>(speed);
  spd.param3 = -1;
  items.push_back(spd);
  std::vector<std::pair<double, double>> corners{{0, 0}, {side, 0}, {side, side}, {0, side}}, points;
  for (std::size_t c = 1; c < corners.size(); ++c)
    for (int k = 1; k <= per_side; ++k) {
      const double u = static_cast<double>(k) / per_side;
      points.emplace_back(corners[c - 1].first + u * (corners[c].first - corners[c - 1].first),
                          corners[c - 1].second + u * (corners[c].second - corners[c - 1].second));
    }
  for (const auto& [x, y] : points) {
    wp::MissionItem wp;
    const LonLat ll = f.to_wgs84(Point(x, y));
    wp.lat = ll.lat;
    wp.lon = ll.lon;
    wp.alt = 30;
    items.push_back(wp);
  }
  items.push_back(return_to_launch());
  return to_mission_items(items, kHome);
}

sim::VehicleConfig config(std::uint8_t sysid) {
  sim::VehicleConfig c;
  c.sysid = sysid;
  c.endurance_min = 600;
  return c;
}

// A fleet running in a thread for at most `max_sim_s` of simulated time.
struct RunningFleet {
  sim::Fleet fleet;
  std::jthread thread;
  RunningFleet(const std::vector<sim::VehicleConfig>& configs, double speedup, double max_sim_s)
      : fleet(configs, sim::FleetOptions{speedup, 0.05}) {
    thread = std::jthread([this, max_sim_s](std::stop_token st) { fleet.run(st, max_sim_s); });
  }
  sim::SimVehicle& vehicle(std::size_t i) { return *fleet.vehicles().at(i); }
  void join() {
    if (thread.joinable()) thread.join();
  }
};

// Our ground station: telemetry log and commands with retries.
struct Gcs {
  UdpLink link{Endpoint{"127.0.0.1", 0}, 255, 190};
  std::uint8_t target;
  std::vector<Received> log;
  Gcs(std::uint16_t port, std::uint8_t sysid) : target(sysid) { link.set_peer(Endpoint{"127.0.0.1", port}); }

  void hello() {
    Heartbeat hb;
    hb.type = 6;
    hb.autopilot = 8;
    link.send(hb);
  }
  // COMMAND_LONG until its COMMAND_ACK arrives (resent every 200 ms, up to 25 times).
  std::optional<std::uint8_t> command(std::uint16_t cmd, float p1 = 0, float p2 = 0) {
    CommandLong c;
    c.command = cmd;
    c.param1 = p1;
    c.param2 = p2;
    c.target_system = target;
    c.target_component = 1;
    for (int attempt = 0; attempt < 25; ++attempt) {
      c.confirmation = static_cast<std::uint8_t>(attempt);
      link.send(c);
      const auto until = std::chrono::steady_clock::now() + 200ms;
      while (std::chrono::steady_clock::now() < until) {
        auto r = link.receive(20ms);
        if (!r) continue;
        log.push_back(*r);
        if (const auto* a = std::get_if<CommandAck>(&r->message); a && a->command == cmd) return a->result;
      }
    }
    return std::nullopt;
  }
  // Collects messages until `done` (checked on each message) or `limit` of wall time (a safety bound).
  template <typename Pred>
  bool collect(Pred done, std::chrono::milliseconds limit) {
    const auto until = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < until) {
      auto r = link.receive(50ms);
      if (!r) continue;
      log.push_back(*r);
      if (done(*r)) return true;
    }
    return false;
  }
  template <typename M>
  std::vector<M> all() const {
    std::vector<M> out;
    for (const auto& r : log)
      if (const auto* m = std::get_if<M>(&r.message)) out.push_back(*m);
    return out;
  }
  std::vector<std::string> texts() const {
    std::vector<std::string> out;
    for (const auto& t : all<StatusText>()) out.emplace_back(t.str());
    return out;
  }
};

bool is_text(const Received& r, std::string_view text) {
  const auto* t = std::get_if<StatusText>(&r.message);
  return t && t->str().find(text) != std::string_view::npos;
}

std::size_t index_of(const std::vector<std::string>& texts, std::string_view needle) {
  for (std::size_t i = 0; i < texts.size(); ++i)
    if (texts[i].find(needle) != std::string::npos) return i;
  return texts.size();
}

int run_cli(const std::string& args) {
  const std::string cmd = std::string("'") + UAVCOVER_CLI + "' " + args + " > /dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

// (1) `uavcover upload` sends a plan's mission; arm, start; at x50 every item is reported reached in order
// and the vehicle ends landed and disarmed; MISSION_CURRENT never goes back.
TEST(SimFleet, UploadedPlanIsFlownInOrderAndEndsLanded) {
  const fs::path dir = fs::temp_directory_path() / ("uavcover-sim-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  ASSERT_EQ(run_cli("-q plan '" + std::string(UAVCOVER_SOURCE_DIR) + "/examples/olive-grove.json' -o '" +
                    (dir / "plan").string() + "'"),
            0);
  const Plan plan = io::load_plan_dir(dir / "plan");
  const std::size_t count = wp::mission_items(plan, 0).size() + 1;  // + home as item 0

  RunningFleet f({config(1)}, 50.0, 3 * 3600.0);
  const std::uint16_t port = f.vehicle(0).port();
  ASSERT_EQ(run_cli("-q upload '" + (dir / "plan").string() + "' --uav " + plan.uavs[0].id +
                    " --to udp:127.0.0.1:" + std::to_string(port)),
            0);
  fs::remove_all(dir);

  Gcs gcs(port, 1);
  gcs.hello();
  ASSERT_EQ(gcs.command(kCmdComponentArmDisarm, 1), kResultAccepted);
  ASSERT_EQ(gcs.command(kCmdMissionStart), kResultAccepted);
  const bool landed = gcs.collect([](const Received& r) { return is_text(r, "landed"); }, 120s);
  gcs.collect([](const Received& r) { return std::holds_alternative<Heartbeat>(r.message); }, 5s);
  f.thread.request_stop();
  f.join();
  ASSERT_TRUE(landed) << "no 'landed' STATUSTEXT";

  std::vector<std::uint16_t> reached;
  for (const auto& m : gcs.all<MissionItemReached>()) reached.push_back(m.seq);
  ASSERT_EQ(reached.size(), count - 1);  // item 0 is home
  for (std::size_t i = 0; i < reached.size(); ++i) EXPECT_EQ(reached[i], i + 1);
  const auto current = gcs.all<MissionCurrent>();
  ASSERT_FALSE(current.empty());
  for (std::size_t i = 1; i < current.size(); ++i) EXPECT_GE(current[i].seq, current[i - 1].seq);
  EXPECT_EQ(current.back().mission_state, sim::kMissionStateComplete);
  EXPECT_EQ(current.back().total, count);
  const auto pos = gcs.all<GlobalPositionInt>();
  ASSERT_FALSE(pos.empty());
  EXPECT_LT(pos.back().relative_alt, 100);  // mm
  double max_alt = 0;
  for (const auto& p : pos) max_alt = std::max(max_alt, p.relative_alt / 1000.0);
  EXPECT_GT(max_alt, 20.0);
  EXPECT_EQ(gcs.all<Heartbeat>().back().base_mode & 128, 0);  // disarmed
  const auto texts = gcs.texts();
  EXPECT_LT(index_of(texts, "mission started"), index_of(texts, "reached last waypoint"));
  EXPECT_LT(index_of(texts, "reached last waypoint"), texts.size());
  // telemetry at 5 Hz of simulated time: consecutive positions about 200 ms apart
  EXPECT_NEAR(static_cast<double>(pos.back().time_boot_ms - pos.front().time_boot_ms) / (pos.size() - 1),
              200.0, 20.0);
}

// (2) 20 % loss on the vehicle's link both ways: the upload succeeds with retries, the commands too, and
// the flight completes (what the vehicle did is read from it after the run).
TEST(SimFleet, LossyLinkUploadRetriesAndFlightCompletes) {
  auto c = config(3);
  c.loss = 0.2;
  c.seed = 7;
  RunningFleet f({c}, 50.0, 3600.0);
  Gcs gcs(f.vehicle(0).port(), 3);
  const auto items = square_mission(10);  // 34 items: the loss cannot miss all of them
  UploadOptions opt;
  opt.target_system = 3;
  opt.timeout = 300ms;
  opt.retries = 10;
  const auto res = upload_mission(gcs.link, items, opt);
  ASSERT_TRUE(res.ok) << res.error;
  ASSERT_EQ(gcs.command(kCmdComponentArmDisarm, 1), kResultAccepted);
  ASSERT_EQ(gcs.command(kCmdMissionStart), kResultAccepted);
  // until the (repeated) MISSION_CURRENT says complete and a later HEARTBEAT says disarmed
  bool complete = false;
  const bool done = gcs.collect(
      [&](const Received& r) {
        if (const auto* m = std::get_if<MissionCurrent>(&r.message))
          complete = complete || m->mission_state == sim::kMissionStateComplete;
        const auto* hb = std::get_if<Heartbeat>(&r.message);
        return complete && hb && (hb->base_mode & 128) == 0;
      },
      120s);
  f.thread.request_stop();
  f.join();
  ASSERT_TRUE(done);
  const auto& st = f.vehicle(0).state();
  ASSERT_EQ(st.reached.size(), items.size() - 1);
  for (std::size_t i = 0; i < st.reached.size(); ++i) EXPECT_EQ(st.reached[i], i + 1);
  EXPECT_TRUE(st.mission_complete);
  EXPECT_FALSE(st.airborne);
  EXPECT_FALSE(st.armed);
  EXPECT_GT(f.vehicle(0).link().stats().dropped_tx + f.vehicle(0).link().stats().dropped_rx, 0U);
  EXPECT_GT(res.timeouts + res.items_sent - res.unique_items, 0U);  // it had to retry
}

// (3) failure injection at 40 % of the mission: link loss silences the vehicle there (it flies on),
// a forced landing brings it down there.
TEST(SimFleet, FailureAtFortyPercent) {
  auto link = config(1);
  link.failure = sim::Failure{0.4, sim::FailureKind::Link};
  auto land = config(2);
  land.failure = sim::Failure{0.4, sim::FailureKind::Land};
  RunningFleet f({link, land}, 50.0, 400.0);
  Gcs g1(f.vehicle(0).port(), 1), g2(f.vehicle(1).port(), 2);
  for (Gcs* g : {&g1, &g2}) {
    UploadOptions opt;
    opt.target_system = g->target;
    ASSERT_TRUE(upload_mission(g->link, square_mission(), opt).ok);
    ASSERT_EQ(g->command(kCmdComponentArmDisarm, 1), kResultAccepted);
    ASSERT_EQ(g->command(kCmdMissionStart), kResultAccepted);
  }
  // drain both until the run ends (the fleet stops at 400 s simulated)
  while (f.thread.joinable() && f.fleet.sim_time() < 399.0) {
    g1.collect([](const Received&) { return false; }, 50ms);
    g2.collect([](const Received&) { return false; }, 50ms);
  }
  f.join();
  g1.collect([](const Received&) { return false; }, 200ms);
  g2.collect([](const Received&) { return false; }, 200ms);

  const auto& s1 = f.vehicle(0).state();
  EXPECT_TRUE(s1.link_lost);
  EXPECT_TRUE(s1.mission_complete);  // it flew on, silently
  const auto p1 = g1.all<GlobalPositionInt>();
  ASSERT_FALSE(p1.empty());
  // silent from the moment it had flown 40 % of its mission
  EXPECT_NEAR(p1.back().time_boot_ms / 1000.0, s1.failed_at_s, 0.3);
  EXPECT_GT(s1.failed_at_s, 40.0);
  std::size_t reached_heard = g1.all<MissionItemReached>().size();
  EXPECT_LT(reached_heard, s1.reached.size());

  const auto& s2 = f.vehicle(1).state();
  EXPECT_TRUE(s2.failed);
  EXPECT_FALSE(s2.airborne);
  EXPECT_FALSE(s2.mission_complete);
  EXPECT_NEAR(s2.flown_m / s2.planned_m, 0.40, 0.01);  // the mission's odometer stops at the failure
  const auto texts = g2.texts();
  EXPECT_LT(index_of(texts, "failure: forced landing"), index_of(texts, "landed"));
  EXPECT_LT(index_of(texts, "landed"), texts.size());
  const auto p2 = g2.all<GlobalPositionInt>();
  ASSERT_FALSE(p2.empty());
  EXPECT_LT(p2.back().relative_alt, 100);
  // it came down 40 % along the path: on the second leg of the square (x = 300 m, 0 < y < 300)
  const Point at = geodesy::LocalFrame(kHome).to_local(LonLat{p2.back().lon * 1e-7, p2.back().lat * 1e-7});
  EXPECT_NEAR(at.x(), 300.0, 5.0);
  EXPECT_GT(at.y(), 50.0);
  EXPECT_LT(at.y(), 250.0);
}

// (4) battery: a mission longer than the endurance ends in a forced landing, announced by the
// low-battery STATUSTEXT first.
TEST(SimFleet, BatteryRunsOutMidMission) {
  auto c = config(4);
  c.endurance_min = 1.5;  // 90 s for a 160 s mission
  RunningFleet f({c}, 50.0, 3600.0);
  Gcs gcs(f.vehicle(0).port(), 4);
  UploadOptions opt;
  opt.target_system = 4;
  ASSERT_TRUE(upload_mission(gcs.link, square_mission(), opt).ok);
  ASSERT_EQ(gcs.command(kCmdComponentArmDisarm, 1), kResultAccepted);
  ASSERT_EQ(gcs.command(kCmdMissionStart), kResultAccepted);
  ASSERT_TRUE(gcs.collect([](const Received& r) { return is_text(r, "landed"); }, 60s));
  f.thread.request_stop();
  f.join();
  const auto texts = gcs.texts();
  const std::size_t low = index_of(texts, "battery low"),
                    empty = index_of(texts, "battery empty: forced landing"),
                    landed = index_of(texts, "landed");
  ASSERT_LT(low, texts.size());
  EXPECT_LT(low, empty);
  EXPECT_LT(empty, landed);
  EXPECT_LT(landed, texts.size());
  const auto& st = f.vehicle(0).state();
  EXPECT_FALSE(st.mission_complete);
  EXPECT_FALSE(st.airborne);
  EXPECT_EQ(st.battery, 0.0);
  // battery reported in SYS_STATUS / BATTERY_STATUS goes down
  const auto sys = gcs.all<SysStatus>();
  ASSERT_GE(sys.size(), 2U);
  EXPECT_GT(sys.front().battery_remaining, sys.back().battery_remaining);
  EXPECT_LE(gcs.all<BatteryStatus>().back().battery_remaining, 1);
}

// Commands: arming checks, pause/continue, RTL.
TEST(SimFleet, CommandsPauseContinueAndReturnToLaunch) {
  RunningFleet f({config(5)}, 50.0, 900.0);
  Gcs gcs(f.vehicle(0).port(), 5);
  UploadOptions opt;
  opt.target_system = 5;
  ASSERT_TRUE(upload_mission(gcs.link, square_mission(), opt).ok);
  EXPECT_EQ(gcs.command(kCmdMissionStart), kResultDenied);       // not armed
  EXPECT_EQ(gcs.command(kCmdNavReturnToLaunch), kResultDenied);  // on the ground
  EXPECT_EQ(gcs.command(999), kResultUnsupported);
  ASSERT_EQ(gcs.command(kCmdComponentArmDisarm, 1), kResultAccepted);
  ASSERT_EQ(gcs.command(kCmdMissionStart), kResultAccepted);
  ASSERT_TRUE(gcs.collect(
      [](const Received& r) {
        const auto* m = std::get_if<MissionItemReached>(&r.message);
        return m && m->seq == 3;
      },
      30s));
  ASSERT_EQ(gcs.command(kCmdDoPauseContinue, 0), kResultAccepted);
  EXPECT_EQ(gcs.command(kCmdComponentArmDisarm, 0), kResultDenied);  // in the air
  ASSERT_TRUE(gcs.collect(
      [](const Received& r) {
        const auto* m = std::get_if<MissionCurrent>(&r.message);
        return m && m->mission_state == sim::kMissionStatePaused;
      },
      10s));
  ASSERT_EQ(gcs.command(kCmdDoPauseContinue, 1), kResultAccepted);
  ASSERT_EQ(gcs.command(kCmdNavReturnToLaunch), kResultAccepted);
  ASSERT_TRUE(gcs.collect([](const Received& r) { return is_text(r, "landed"); }, 60s));
  f.thread.request_stop();
  f.join();
  const auto& st = f.vehicle(0).state();
  EXPECT_FALSE(st.armed);
  EXPECT_FALSE(st.mission_complete);
  EXPECT_LT(std::hypot(st.p.x, st.p.y), 1.0);  // back home
  const auto hb = gcs.all<Heartbeat>();
  ASSERT_FALSE(hb.empty());
  EXPECT_EQ(hb.front().type, 2);
  EXPECT_EQ(hb.front().autopilot, 12);
}

// Flight model without a link: wind slows the legs flown against it, speed and acceleration stay in
// their limits, and the same inputs give the same flight.
TEST(SimVehicleModel, WindLimitsAndDeterminism) {
  auto fly = [](double wind) {
    auto c = config(9);
    c.home = kHome;
    c.wind_mps = wind;
    c.wind_from_deg = 90;  // from the east: the first leg (eastwards) is against it
    sim::SimVehicle v(c);
    v.set_mission(square_mission());
    EXPECT_EQ(v.arm(true), kResultAccepted);
    EXPECT_EQ(v.start_mission(), kResultAccepted);
    double t_leg1 = 0, vmax = 0, amax = 0;
    sim::Vec3 prev_v{};
    for (int i = 0; i < 20000 && !v.state().mission_complete; ++i) {
      v.step(0.05);
      const auto& s = v.state();
      if (t_leg1 == 0 && s.reached.size() >= 3) t_leg1 = s.t;  // take-off, speed, first corner
      vmax = std::max(vmax, std::hypot(s.v.x, s.v.y));
      if (s.airborne)  // (touchdown stops it at once: ground contact, not the controller)
        amax = std::max(amax, std::hypot(s.v.x - prev_v.x, s.v.y - prev_v.y, s.v.z - prev_v.z) / 0.05);
      prev_v = s.v;
    }
    EXPECT_TRUE(v.state().mission_complete);
    EXPECT_LE(vmax, 10.0 + 1e-9);
    EXPECT_LE(amax, 2.0 + 1e-6);
    return std::pair{t_leg1, v.state().t};
  };
  const auto calm = fly(0), windy = fly(6), again = fly(6);
  EXPECT_GT(windy.first, calm.first + 30.0);  // 300 m at 4 m/s (10 - 6) instead of 10 m/s
  EXPECT_EQ(windy, again);
}

// Arming at home after a flight swaps the used battery (the next sortie starts full); a vehicle that
// landed away from home keeps what it has.
TEST(SimVehicleModel, BatterySwappedWhenArmingAtHome) {
  auto flown = [](std::optional<sim::Failure> failure) {
    auto c = config(9);
    c.home = kHome;
    c.endurance_min = 30;
    c.failure = failure;
    auto v = std::make_unique<sim::SimVehicle>(c);
    v->set_mission(square_mission());
    EXPECT_EQ(v->arm(true), kResultAccepted);
    EXPECT_EQ(v->start_mission(), kResultAccepted);
    for (int i = 0; i < 40000 && (v->state().armed || v->state().t < 1); ++i) v->step(0.05);
    EXPECT_FALSE(v->state().armed);
    return v;
  };
  auto home = flown(std::nullopt);
  EXPECT_LT(std::hypot(home->state().p.x, home->state().p.y), 1.0);
  const double used = home->state().battery;
  EXPECT_LT(used, 0.95);
  EXPECT_EQ(home->arm(true), kResultAccepted);
  EXPECT_DOUBLE_EQ(home->state().battery, 1.0);

  auto away = flown(sim::Failure{0.4, sim::FailureKind::Land});
  EXPECT_GT(std::hypot(away->state().p.x, away->state().p.y), 50.0);
  const double left = away->state().battery;
  EXPECT_EQ(away->arm(true), kResultAccepted);
  EXPECT_DOUBLE_EQ(away->state().battery, left);
}

// Issue 33: the `stuck` fault holds the vehicle where it is in its mission (no item reached after it),
// with MAV_CMD_DO_SET_MISSION_CURRENT accepted (kept in set_current) without getting it moving; RTL still
// brings it home. Without the fault, set_current skips ahead to the item given.
TEST(SimVehicleModel, StuckHoldsAndSetCurrentRetargets) {
  auto c = config(9);
  c.home = kHome;
  c.failure = sim::Failure{0.3, sim::FailureKind::Stuck};
  sim::SimVehicle v(c);
  v.set_mission(square_mission());
  ASSERT_EQ(v.arm(true), kResultAccepted);
  ASSERT_EQ(v.start_mission(), kResultAccepted);
  for (int i = 0; i < 40000 && !v.state().failed; ++i) v.step(0.05);
  ASSERT_TRUE(v.state().failed);
  const std::size_t reached = v.state().reached.size();
  const auto seq = v.state().current_seq;
  ASSERT_TRUE(seq.has_value());
  EXPECT_EQ(v.set_current(*seq), kResultAccepted);
  const sim::Vec3 at = v.state().p;
  for (int i = 0; i < 4000; ++i) v.step(0.05);  // 200 s
  EXPECT_EQ(v.state().reached.size(), reached);
  EXPECT_EQ(v.state().current_seq, seq);
  EXPECT_LT(std::hypot(v.state().p.x - at.x, v.state().p.y - at.y), 1.0);
  EXPECT_EQ(v.state().set_current, (std::vector<std::uint16_t>{*seq}));
  EXPECT_EQ(v.set_current(9999), kResultFailed);
  EXPECT_EQ(v.return_to_launch(), kResultAccepted);
  for (int i = 0; i < 40000 && v.state().armed; ++i) v.step(0.05);
  EXPECT_FALSE(v.state().armed);
  EXPECT_LT(std::hypot(v.state().p.x, v.state().p.y), 1.0);

  auto healthy = config(9);
  healthy.home = kHome;
  sim::SimVehicle w(healthy);
  w.set_mission(square_mission());
  ASSERT_EQ(w.arm(true), kResultAccepted);
  ASSERT_EQ(w.start_mission(), kResultAccepted);
  const auto last = static_cast<int>(square_mission().size()) - 2;  // the item before the RTL
  EXPECT_EQ(w.set_current(last), kResultAccepted);
  EXPECT_EQ(w.state().current_seq, static_cast<std::uint16_t>(last));
  for (int i = 0; i < 40000 && !w.state().mission_complete; ++i) w.step(0.05);
  ASSERT_FALSE(w.state().reached.empty());
  EXPECT_EQ(w.state().reached.front(), last);  // the items before it were skipped
}

TEST(SimVehicleModel, ParseFailure) {
  const auto [id, f] = sim::parse_failure("3@0.4:land");
  EXPECT_EQ(id, 3);
  EXPECT_EQ(f.kind, sim::FailureKind::Land);
  EXPECT_DOUBLE_EQ(f.fraction, 0.4);
  EXPECT_EQ(sim::parse_failure("1@0.25").second.kind, sim::FailureKind::Link);
  EXPECT_EQ(sim::parse_failure("2@0.5:stuck").second.kind, sim::FailureKind::Stuck);
  for (const char* bad : {"", "@0.4", "0@0.4", "256@0.4", "1@1", "1@0", "1@x", "1@0.4:crash", "1@0.4:"})
    EXPECT_THROW(sim::parse_failure(bad), InputError) << bad;
}

// Untrusted items: a waypoint off the globe or with a NaN altitude, an absurd speed, are not flown; the
// rest of the mission is.
TEST(SimVehicleModel, InvalidItemsAreSkipped) {
  auto c = config(9);
  c.home = kHome;
  sim::SimVehicle v(c);
  auto items = square_mission();
  items[3].x = 1'000'000'000;  // latitude 100 degrees
  items[4].z = std::numeric_limits<float>::quiet_NaN();
  items[2].param2 = std::numeric_limits<float>::infinity();  // DO_CHANGE_SPEED: ignored
  v.set_mission(items);
  ASSERT_EQ(v.arm(true), kResultAccepted);
  ASSERT_EQ(v.start_mission(), kResultAccepted);
  for (int i = 0; i < 40000 && !v.state().mission_complete; ++i) v.step(0.05);
  const auto& s = v.state();
  EXPECT_TRUE(s.mission_complete);
  EXPECT_FALSE(s.airborne);
  EXPECT_TRUE(std::isfinite(s.p.x) && std::isfinite(s.p.y) && std::isfinite(s.p.z));
  EXPECT_LT(std::hypot(s.p.x, s.p.y), 1.0);  // RTL brought it home
  EXPECT_EQ(s.reached.size(), items.size() - 1);
}

// The simulator accepts items by ArduPilot's rules (AP_Mission::sanity_check_params and
// mavlink_int_to_mission_cmd, src/autopilot/rules.hpp): the gimbal item the exports carried before
// issue 34 (NaN rates in params 3 and 4) is refused with MAV_MISSION_INVALID_PARAM3, and the items
// received before it stay stored, as on ArduPilot; with finite rates the same mission is accepted.
TEST(SimFleet, RefusesWhatArduPilotRefuses) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  struct Case {
    float p3, p4;
    std::uint16_t command;
    std::optional<std::uint8_t> ack;  ///< expected refusal, none = accepted
  };
  const std::vector<Case> cases = {
      {nan, nan, wp::kDoGimbalManagerPitchyaw, std::uint8_t{autopilot::kMissionInvalidParam1 + 2}},
      {0, nan, wp::kDoGimbalManagerPitchyaw, std::uint8_t{autopilot::kMissionInvalidParam1 + 3}},
      {0, 0, 31999, std::uint8_t{kMissionUnsupported}},
      {0, 0, wp::kDoGimbalManagerPitchyaw, std::nullopt},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(::testing::Message() << "command " << c.command << ", params 3/4 " << c.p3 << " " << c.p4);
    auto items = square_mission();  // home, take-off, speed, 3 waypoints, RTL
    MissionItemInt gimbal;
    gimbal.command = c.command;
    gimbal.frame = wp::kFrameMission;
    gimbal.param1 = -90;
    gimbal.param3 = c.p3;
    gimbal.param4 = c.p4;
    items.insert(items.begin() + 3, gimbal);
    for (std::size_t k = 0; k < items.size(); ++k) items[k].seq = static_cast<std::uint16_t>(k);
    RunningFleet f({config(6)}, 50.0, 600.0);
    Gcs gcs(f.vehicle(0).port(), 6);
    UploadOptions opt;
    opt.target_system = 6;
    const auto res = upload_mission(gcs.link, items, opt);
    f.thread.request_stop();
    f.join();
    // as sent: the uploader addresses every item to the vehicle
    std::vector<MissionItemInt> stored = f.vehicle(0).mission();
    for (auto& it : stored) it.target_system = it.target_component = 0;
    if (c.ack) {
      EXPECT_FALSE(res.ok);
      ASSERT_TRUE(res.ack.has_value()) << res.error;
      EXPECT_EQ(*res.ack, *c.ack) << mission_result_name(*res.ack);
      // ArduPilot keeps home, take-off and speed after such a refusal (issue 34): the uploader then
      // clears them, so no partial mission stays behind
      EXPECT_TRUE(res.clear_sent);
      EXPECT_TRUE(res.cleared) << res.error;
      EXPECT_TRUE(stored.empty()) << stored.size() << " items left on the vehicle";
    } else {
      EXPECT_TRUE(res.ok) << res.error;
      EXPECT_EQ(stored, items);
    }
  }
}

namespace {

/// A ring of local (east, north) metres around kHome.
GeoRing ring_around(std::vector<std::pair<double, double>> pts) {
  const geodesy::LocalFrame f(kHome);
  GeoRing r;
  for (const auto& [x, y] : pts) r.push_back(f.to_wgs84({x, y}));
  return r;
}

}  // namespace

// Issue 31: the simulator holds a fence as PX4 reads it. A mission with a waypoint outside it is refused
// at start; a flight that crosses an exclusion zone between two allowed waypoints breaches it and
// returns to launch.
TEST(SimVehicleModel, RefusesToFlyOutOfItsFence) {
  auto c = config(9);
  c.home = kHome;
  autopilot::Fence inside_all;
  inside_all.inclusion.push_back(ring_around({{-50, -50}, {350, -50}, {350, 350}, {-50, 350}}));
  autopilot::Fence too_small;
  too_small.inclusion.push_back(ring_around({{-50, -50}, {200, -50}, {200, 350}, {-50, 350}}));
  autopilot::Fence crossed = inside_all;
  crossed.exclusion.push_back(ring_around({{130, -20}, {170, -20}, {170, 20}, {130, 20}}));
  auto run = [&](const autopilot::Fence& fence, std::uint8_t want_start) {
    auto v = std::make_unique<sim::SimVehicle>(c);
    v->set_mission(square_mission());
    v->set_fence(fence);
    EXPECT_EQ(v->arm(true), kResultAccepted);
    EXPECT_EQ(v->start_mission(), want_start);
    for (int i = 0; i < 40000 && want_start == kResultAccepted && (v->state().armed || v->state().t < 1); ++i)
      v->step(0.05);
    return v;
  };
  const auto ok = run(inside_all, kResultAccepted);
  EXPECT_TRUE(ok->state().mission_complete);
  EXPECT_FALSE(ok->state().fence_breach);
  (void)run(too_small, kResultDenied);  // (300, 0) lies outside
  const auto breached = run(crossed, kResultAccepted);
  const auto& s = breached->state();
  EXPECT_TRUE(s.fence_breach);
  EXPECT_FALSE(s.mission_complete);
  EXPECT_FALSE(s.airborne);
  EXPECT_LT(std::hypot(s.p.x, s.p.y), 1.0);  // back home
  EXPECT_LT(s.reached.size(), square_mission().size());
}

// Issue 31, the terrain frame: heights in MAV_FRAME_GLOBAL_TERRAIN_ALT are above the ground under the
// vehicle along the whole leg (ArduPilot's terrain following), where the same height relative to home
// comes down to a fraction of it over a hill; without terrain data MISSION_START is refused.
TEST(SimVehicleModel, TerrainFrameItemsFollowTheGround) {
  const geodesy::LocalFrame f(kHome);
  // a 30 m hill 150 m east of home on a 200 m plain, on a 201 x 201 grid of 1e-4 degrees
  auto grid = std::make_shared<HeightGrid>();
  grid->cols = grid->rows = 201;
  grid->dlon = grid->dlat = 1e-4;
  grid->lon0 = kHome.lon - 100 * grid->dlon;
  grid->lat0 = kHome.lat - 100 * grid->dlat;
  for (int r = 0; r < grid->rows; ++r)
    for (int c = 0; c < grid->cols; ++c) {
      const Point q = f.to_local(LonLat{grid->lon0 + c * grid->dlon, grid->lat0 + r * grid->dlat});
      const double d2 = (q.x() - 150) * (q.x() - 150) + q.y() * q.y();
      grid->heights.push_back(static_cast<float>(200.0 + 30.0 * std::exp(-d2 / (2 * 60.0 * 60.0))));
    }
  grid->step_m = 8.4;
  grid->max_m = 230;
  auto mission = [&](std::uint8_t frame) {
    std::vector<wp::MissionItem> items{takeoff_at_home(40)};
    for (const double x : {0.0, 300.0}) {
      wp::MissionItem w;
      const LonLat ll = f.to_wgs84(Point(x, 0));
      w.lat = ll.lat;
      w.lon = ll.lon;
      w.alt = 40;
      w.frame = frame;
      items.push_back(w);
    }
    items.push_back(return_to_launch());
    return to_mission_items(items, kHome);
  };
  // the lowest height above the ground on the leg over the hill (to item 3, home item 0), and the end
  auto fly = [&](std::uint8_t frame, std::shared_ptr<const HeightGrid> ground, std::uint8_t want_start) {
    auto c = config(9);
    c.home = kHome;
    c.ground = std::move(ground);
    c.home_amsl_m = grid->at(kHome);
    c.v_max = 5;
    sim::SimVehicle v(c);
    v.set_mission(mission(frame));
    EXPECT_EQ(v.arm(true), kResultAccepted);
    EXPECT_EQ(v.start_mission(), want_start);
    double lowest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 40000 && want_start == kResultAccepted && !v.state().mission_complete; ++i) {
      v.step(0.05);
      const auto& s = v.state();
      if (s.current_seq == 3 && std::hypot(s.p.x, s.p.y) > 30)
        lowest = std::min(lowest, s.p.z - (grid->at(v.position_wgs84()) - c.home_amsl_m));
    }
    if (want_start == kResultAccepted) {
      EXPECT_TRUE(v.state().mission_complete);
    }
    return std::pair{lowest, v.state().agl_min_m};
  };
  const auto [terrain, tracked] = fly(wp::kFrameGlobalTerrainAlt, grid, kResultAccepted);
  EXPECT_GT(terrain, 37.0) << "40 m above the ground over the hill";
  EXPECT_LT(terrain, 41.0);
  EXPECT_GT(tracked, 37.0);
  const auto [relative, untracked] = fly(wp::kFrameGlobalRelativeAlt, grid, kResultAccepted);
  EXPECT_LT(relative, 20.0) << "40 m above home is about 15 m above the hill's top";
  EXPECT_TRUE(std::isinf(untracked));
  (void)fly(wp::kFrameGlobalTerrainAlt, nullptr, kResultDenied);  // no terrain data
}

// Issue 31: a fence uploaded over MAVLink (MAV_MISSION_TYPE_FENCE) is stored apart from the mission; one
// that does not read as a fence (a vertex count that does not match its group) is refused whole.
TEST(SimFleet, FenceUploadIsStoredApartAndCheckedWhole) {
  const GeoRing ring = ring_around({{-50, -50}, {350, -50}, {350, 350}, {-50, 350}});
  std::vector<MissionItemInt> fence;
  for (const auto& p : ring) {
    MissionItemInt it;
    it.command = autopilot::kFencePolygonVertexInclusion;
    it.frame = 0;
    it.param1 = static_cast<float>(ring.size());
    it.x = static_cast<std::int32_t>(std::llround(p.lat * 1e7));
    it.y = static_cast<std::int32_t>(std::llround(p.lon * 1e7));
    fence.push_back(it);
  }
  auto bad = fence;
  bad[2].param1 = 3;  // a vertex of another polygon in the middle of this one
  RunningFleet f({config(6)}, 50.0, 600.0);
  Gcs gcs(f.vehicle(0).port(), 6);
  UploadOptions opt;
  opt.target_system = 6;
  const auto mission = upload_mission(gcs.link, square_mission(), opt);
  opt.mission_type = kMissionTypeFence;
  const auto good = upload_mission(gcs.link, fence, opt);
  const auto refused = upload_mission(gcs.link, bad, opt);
  // the protocol stores (clears) the fence before it acknowledges; the parsed fence() follows after the ack
  const std::size_t after_refusal = f.vehicle(0).stored_fence().size();
  const auto again = upload_mission(gcs.link, fence, opt);
  f.thread.request_stop();
  f.join();
  EXPECT_TRUE(mission.ok) << mission.error;
  EXPECT_TRUE(good.ok) << good.error;
  EXPECT_FALSE(refused.ok);
  ASSERT_TRUE(refused.ack.has_value());
  EXPECT_EQ(*refused.ack, kMissionInvalid);
  // the uploader then clears the fence (MISSION_CLEAR_ALL of the fence type): no fence, the mission kept
  EXPECT_TRUE(refused.cleared) << refused.error;
  EXPECT_EQ(after_refusal, 0U);
  EXPECT_EQ(f.vehicle(0).mission().size(), square_mission().size());
  EXPECT_TRUE(again.ok) << again.error;
  ASSERT_EQ(f.vehicle(0).fence().inclusion.size(), 1U);
  EXPECT_EQ(f.vehicle(0).fence().inclusion[0].size(), ring.size());
}
