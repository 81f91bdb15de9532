// `uavcover simulate --vehicles N --listen udp|tcp:HOST:PORT[,PORT...]`: N simulated MAVLink 2 multirotors in
// one process (src/sim, docs/simulate.md), until Ctrl-C / SIGTERM.
#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <iostream>
#include <map>
#include <sstream>

#include "cli/command.hpp"
#include "cli/interrupt.hpp"
#include "cli/mission_file.hpp"
#include "cli/validators.hpp"
#include "export/export.hpp"
#include "io/plan_io.hpp"
#include "mavlink/mission_protocol.hpp"
#include "sim/sim_vehicle.hpp"
#include "uavcover/error.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::cli {
namespace {

struct SimulateArgs {
  int vehicles = 1;
  std::string listen = "udp:127.0.0.1:14540";
  double speedup = 1.0;
  std::vector<std::string> fail;
  double battery_min = 20.0;
  double wind = 0.0;
  double wind_from = 270.0;
  double loss = 0.0;
  std::uint64_t seed = 1;
  std::string home;
  double rate = 5.0;
  double speed = 5.0;
  double accel = 2.0;
  double radius = 2.0;
  std::string autopilot = "px4";
  std::string gcs;
  std::string plan_dir;
  bool autostart = false;
  double duration = 0.0;
};

// "udp:HOST:PORT[,PORT...]" or "tcp:HOST:PORT[,PORT...]" (tcpin: is the same: the vehicles listen).
std::vector<std::uint16_t> parse_ports(const std::string& text, int n, std::string& host, bool& tcp) {
  const std::string field = "--listen";
  const std::string usage =
      "expected udp:HOST:PORT[,PORT...] or tcp:HOST:PORT[,PORT...] (e.g. tcp:127.0.0.1:5760), got '" + text +
      "'";
  const auto colon = text.find(':');
  const std::string scheme = colon == std::string::npos ? "" : text.substr(0, colon);
  if (scheme != "udp" && scheme != "tcp" && scheme != "tcpin") throw InputError(field, usage);
  tcp = scheme != "udp";
  const std::string spec = text.substr(colon + 1);
  const auto comma = spec.find(',');
  const std::string first = spec.substr(0, comma);
  std::vector<std::uint16_t> ports;
  const mavlink::Endpoint e = mavlink::parse_host_port(first, field, usage, comma == std::string::npos);
  host = e.host;
  if (e.port == 0) return std::vector<std::uint16_t>(static_cast<std::size_t>(n), 0);  // any free ports
  ports.push_back(e.port);
  if (comma == std::string::npos) {
    if (static_cast<long>(e.port) + n - 1 > 65535)
      throw InputError(field, fmt::format("base port {} + {} vehicles runs past 65535", e.port, n));
    for (int i = 1; i < n; ++i) ports.push_back(static_cast<std::uint16_t>(e.port + i));
    return ports;
  }
  std::stringstream rest(spec.substr(comma + 1));
  std::string p;
  while (std::getline(rest, p, ',')) {
    unsigned v = 0;
    const auto [ptr, ec] = std::from_chars(p.data(), p.data() + p.size(), v);
    if (ec != std::errc{} || ptr != p.data() + p.size() || v == 0 || v > 65535)
      throw InputError(field, "port must be an integer in 1..65535, got '" + p + "'");
    ports.push_back(static_cast<std::uint16_t>(v));
  }
  if (ports.size() != static_cast<std::size_t>(n))
    throw InputError(field,
                     fmt::format("{} ports given for {} vehicles: give one base port or one per vehicle",
                                 ports.size(), n));
  for (std::size_t i = 0; i < ports.size(); ++i)
    for (std::size_t j = i + 1; j < ports.size(); ++j)
      if (ports[i] == ports[j]) throw InputError(field, fmt::format("port {} is listed twice", ports[i]));
  return ports;
}

LonLat parse_home(const std::string& text) {
  const auto comma = text.find(',');
  double lat = 0, lon = 0;
  auto num = [&](const std::string& s, double& out) {
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc{} && p == s.data() + s.size() && std::isfinite(out);
  };
  if (comma == std::string::npos || !num(text.substr(0, comma), lat) || !num(text.substr(comma + 1), lon))
    throw InputError("--home", "expected LAT,LON in degrees (e.g. 40.6,22.9), got '" + text + "'");
  if (lat < -90 || lat > 90)
    throw InputError("--home", fmt::format("latitude must be in [-90, 90], got {}", lat));
  if (lon < -180 || lon > 180)
    throw InputError("--home", fmt::format("longitude must be in [-180, 180], got {}", lon));
  return LonLat{lon, lat};
}

void run_simulate(const SimulateArgs& a) {
  std::string host;
  bool tcp = false;
  const auto ports = parse_ports(a.listen, a.vehicles, host, tcp);
  std::map<std::uint8_t, sim::Failure> failures;
  for (const auto& f : a.fail) {
    const auto [id, failure] = sim::parse_failure(f, "--fail");
    if (id > a.vehicles)
      throw InputError("--fail", fmt::format("no vehicle {} (system ids are 1..{})", id, a.vehicles));
    failures[id] = failure;
  }
  if (a.autopilot != "px4" && a.autopilot != "generic")
    throw InputError("--autopilot", "must be 'px4' or 'generic', got '" + a.autopilot + "'");
  std::optional<LonLat> home;
  if (!a.home.empty()) home = parse_home(a.home);
  std::optional<mavlink::Endpoint> gcs;
  if (!a.gcs.empty()) gcs = mavlink::parse_udp_endpoint(a.gcs, "--gcs");
  if (gcs && tcp)
    throw InputError("--gcs", "applies to UDP vehicles only (a TCP vehicle talks to its client)");
  if (a.autostart && a.plan_dir.empty()) throw InputError("--autostart", "needs --plan (a mission to fly)");

  // Optional preloaded missions: vehicle i flies UAV i of the plan (cycling when there are more vehicles).
  std::vector<std::vector<mavlink::MissionItemInt>> missions;
  std::vector<LonLat> starts;
  std::shared_ptr<const HeightGrid> ground;  // the plan's DEM: heights above the terrain are flown over it
  if (!a.plan_dir.empty()) {
    const Plan plan = read_plan_dir(a.plan_dir);
    if (plan.mission.terrain) ground = plan.mission.terrain->grid;
    for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
      if (exporting::idle(plan.uavs[i])) continue;
      const LonLat start = plan.mission.uavs.at(i).start_resolved;
      missions.push_back(mavlink::to_mission_items(waypoints::mission_items(plan, i), start));
      starts.push_back(start);
    }
    if (missions.empty()) throw InputError("--plan", "the plan has no UAV with a coverage path");
  }

  std::vector<sim::VehicleConfig> configs;
  for (int i = 0; i < a.vehicles; ++i) {
    sim::VehicleConfig c;
    c.sysid = static_cast<std::uint8_t>(i + 1);
    c.listen = mavlink::Endpoint{host, ports[static_cast<std::size_t>(i)]};
    c.tcp = tcp;
    c.home = home;
    if (!home && !starts.empty()) c.home = starts[static_cast<std::size_t>(i) % starts.size()];
    // a plan with a DEM: the ground under the vehicle (AMSL heights, and the terrain frame of an upload)
    c.set_ground(ground);
    c.v_max = a.speed;
    c.a_max = a.accel;
    c.acceptance_radius_m = a.radius;
    c.endurance_min = a.battery_min;
    c.wind_mps = a.wind;
    c.wind_from_deg = a.wind_from;
    c.loss = a.loss;
    c.seed = a.seed;
    c.telemetry_hz = a.rate;
    c.autopilot = a.autopilot == "px4" ? sim::Autopilot::Px4 : sim::Autopilot::Generic;
    if (auto it = failures.find(c.sysid); it != failures.end()) c.failure = it->second;
    configs.push_back(c);
  }
  sim::FleetOptions fo;
  fo.speedup = a.speedup;
  std::unique_ptr<sim::Fleet> fleet;
  try {
    fleet = std::make_unique<sim::Fleet>(configs, fo);
  } catch (const std::runtime_error& e) {  // a port in use
    throw OperationError(std::string("cannot open the vehicles' sockets: ") + e.what());
  }
  for (std::size_t i = 0; i < fleet->vehicles().size(); ++i) {
    auto& v = *fleet->vehicles()[i];
    if (gcs) v.set_peer(*gcs);
    if (!missions.empty()) {
      v.set_mission(missions[i % missions.size()]);
      if (a.autostart) {
        v.arm(true);
        v.start_mission();
      }
    }
    std::cout << fmt::format("vehicle {}: {}:{}:{} system id {}\n", i + 1, tcp ? "tcp" : "udp", host,
                             v.port(), v.sysid());
  }
  std::cout << std::flush;
  if (!global_flags().quiet)
    std::cerr << fmt::format("simulating {} vehicle(s) at x{} speed; Ctrl-C to stop\n", a.vehicles,
                             a.speedup);
  std::optional<double> until;
  if (a.duration > 0) until = a.duration;
  try {
    fleet->run(interrupt_token(), until);
  } catch (const Cancelled&) {
    // a stop (SIGINT/SIGTERM) is how a simulation ends: not an error, the summary follows
  }
  if (!global_flags().quiet)
    for (const auto& v : fleet->vehicles()) {
      const auto& s = v->state();
      std::cerr << fmt::format("vehicle {}: {:.0f} s simulated, {} items reached, battery {:.0f}%, {}{}\n",
                               v->sysid(), s.t, s.reached.size(), s.battery * 100.0,
                               s.airborne ? "airborne" : "on the ground",
                               s.failed ? ", failed (injected)" : "");
    }
}

const bool registered = CommandRegistry::add(55, [](CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  auto* cmd = app.add_subcommand("simulate", "Run N simulated MAVLink 2 vehicles (rehearsal, demos, tests)");
  cmd->add_option("--vehicles", args->vehicles, "Number of vehicles (system ids 1..N)")
      ->capture_default_str()
      ->check(integer_in(1, 255));
  cmd->add_option(
         "--listen", args->listen,
         "udp:HOST:PORT (vehicles on PORT..PORT+N-1), udp:HOST:P1,P2,... (one port each) or "
         "udp:HOST:0 (any free ports); tcp:... the same with each vehicle a TCP listener (one client "
         "at a time, the newest wins; tcpin: is a synonym)")
      ->capture_default_str();
  cmd->add_option("--speedup", args->speedup, "Simulated seconds per wall second")
      ->capture_default_str()
      ->check(number_in(0.1, 1000));
  cmd->add_option("--fail", args->fail,
                  "ID@FRACTION[:link|:land|:stuck]: vehicle ID fails when it has flown FRACTION of its "
                  "mission (link: stops sending and receiving, the default; land: forced landing; stuck: "
                  "holds where it is in its mission). Repeatable");
  cmd->add_option("--battery-min", args->battery_min, "Minutes a full battery lasts armed")
      ->capture_default_str()
      ->check(number_in(0.5, 600));
  cmd->add_option("--wind", args->wind, "Constant wind speed (m/s)")
      ->capture_default_str()
      ->check(number_in(0, 30));
  cmd->add_option("--wind-from", args->wind_from, "Direction the wind blows from (degrees, 0 = north)")
      ->capture_default_str()
      ->check(number_in(0, 360));
  cmd->add_option("--loss", args->loss,
                  "Drop this fraction of sent and received datagrams (seeded; over TCP: of the frames sent)")
      ->capture_default_str()
      ->check(number_in(0, 0.9));
  cmd->add_option("--seed", args->seed, "Seed of the packet loss")->capture_default_str();
  cmd->add_option(
      "--home", args->home,
      "LAT,LON where every vehicle stands; default: the plan's start (--plan) or the home/take-off "
      "position of the first mission uploaded");
  cmd->add_option("--rate", args->rate, "GLOBAL_POSITION_INT and MISSION_CURRENT per simulated second")
      ->capture_default_str()
      ->check(number_in(1, 50));
  cmd->add_option("--speed", args->speed, "Horizontal speed limit (m/s) until the mission's DO_CHANGE_SPEED")
      ->capture_default_str()
      ->check(number_in(0.5, 50));
  cmd->add_option("--accel", args->accel, "Acceleration limit (m/s^2)")
      ->capture_default_str()
      ->check(number_in(0.1, 20));
  cmd->add_option("--radius", args->radius, "Waypoint acceptance radius (m)")
      ->capture_default_str()
      ->check(number_in(0.1, 100));
  cmd->add_option("--autopilot", args->autopilot, "HEARTBEAT autopilot and custom modes: px4 or generic")
      ->capture_default_str();
  cmd->add_option("--gcs", args->gcs,
                  "udp:HOST:PORT to send telemetry to before any ground station has spoken (otherwise each "
                  "vehicle answers whoever sent to it last)");
  cmd->add_option("--plan", args->plan_dir, "Plan folder: vehicle i starts with UAV i's mission loaded")
      ->check(CLI::ExistingDirectory);
  cmd->add_flag("--autostart", args->autostart, "With --plan: arm and start every mission at once");
  cmd->add_option("--duration", args->duration,
                  "Stop after this many simulated seconds (0 = run until Ctrl-C)")
      ->capture_default_str()
      ->check(number_in(0, 1e7));
  cmd->footer(
      "Each vehicle answers HEARTBEAT, the mission upload, and COMMAND_LONG arm/disarm (400), mission start\n"
      "(300), pause/continue (193), RTL (20) and land (21); it reports GLOBAL_POSITION_INT, "
      "MISSION_CURRENT,\n"
      "MISSION_ITEM_REACHED, SYS_STATUS, BATTERY_STATUS, HEARTBEAT and STATUSTEXT. See docs/simulate.md.\n"
      "Exit codes: 0 stopped (Ctrl-C, SIGTERM or --duration), 1 sockets unavailable, 2 bad input.");
  cmd->callback([args] { run_simulate(*args); });
});

}  // namespace
}  // namespace uavcover::cli
