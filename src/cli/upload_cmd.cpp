// `uavcover upload PLAN_DIR --uav ID --to ENDPOINT`: sends one UAV's mission to a vehicle with the
// MAVLink mission upload protocol (MISSION_COUNT / MISSION_REQUEST_INT / MISSION_ITEM_INT / MISSION_ACK)
// over UDP, TCP (connect or listen) or a serial port (mavlink/link.hpp). A failed upload is followed by
// MISSION_CLEAR_ALL; when that is not acknowledged the message says the vehicle may hold a partial mission.
#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <stdexcept>

#include "autopilot/fence.hpp"
#include "cli/command.hpp"
#include "cli/mission_file.hpp"
#include "cli/validators.hpp"
#include "export/export.hpp"
#include "io/plan_io.hpp"
#include "mavlink/mission_protocol.hpp"
#include "mavlink/stream.hpp"
#include "uavcover/error.hpp"
#include "uavcover/vehicle.hpp"
#include "waypoints/ardupilot.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::cli {
namespace {

struct UploadArgs {
  std::string plan_dir;
  std::string uav;
  std::string to;
  double timeout_s = 1.5;
  int retries = mavlink::kMaxRetries;
  int target_system = 1;
  int target_component = 1;
  int sysid = 255;
  int compid = 190;
  bool no_home = false;
  bool no_fence = false;
  std::string autopilot;  ///< empty: the plan's (the UAV's profile, the mission's), else px4
  int max_items = 0;      ///< 0: the profile's capacity (with the mission's max_mission_items)
  waypoints::AltitudeOptions altitude;
};

void run_upload(const UploadArgs& a) {
  const mavlink::LinkAddress to = mavlink::parse_link_address(a.to, "--to");
  if (!(a.timeout_s > 0) || a.timeout_s > 60) throw InputError("--timeout", "must be in (0, 60] seconds");
  if (a.retries < 0 || a.retries > 100) throw InputError("--retries", "must be in 0..100");
  if (!a.autopilot.empty() && a.autopilot != "px4" && a.autopilot != "ardupilot")
    throw InputError("--autopilot", "must be 'px4' or 'ardupilot', got '" + a.autopilot.substr(0, 64) + "'");
  auto byte_option = [](int v, const char* field, int lo) {
    if (v < lo || v > 255) throw InputError(field, fmt::format("must be in {}..255", lo));
    return static_cast<std::uint8_t>(v);
  };
  mavlink::UploadOptions opt;
  opt.target_system = byte_option(a.target_system, "--target-system", 1);
  opt.target_component = byte_option(a.target_component, "--target-component", 0);
  opt.timeout = std::chrono::milliseconds(std::max<long>(1, std::lround(a.timeout_s * 1000.0)));
  opt.retries = a.retries;

  const Plan plan = read_plan_dir(a.plan_dir);
  std::size_t index = plan.uavs.size();
  for (std::size_t i = 0; i < plan.uavs.size(); ++i)
    if (plan.uavs[i].id == a.uav) index = i;
  if (index == plan.uavs.size()) {
    std::string ids;
    for (const auto& u : plan.uavs) ids += (ids.empty() ? "" : ", ") + u.id;
    throw InputError("--uav", fmt::format("no UAV '{}' in the plan (it has: {})", a.uav, ids));
  }
  if (exporting::idle(plan.uavs[index])) {  // like the exporters: no coverage, nothing to fly
    std::cerr << fmt::format("uavcover: warning: UAV '{}' has no coverage path; nothing uploaded\n", a.uav);
    return;
  }
  // the vehicle profile (issue 31, docs/vehicle-limits.md): the option, else the plan's
  const std::string firmware =
      !a.autopilot.empty() ? a.autopilot : std::string(uav_autopilot(plan.mission, index));
  const VehicleProfile* profile = vehicle_profile(firmware);
  if (profile == nullptr || !profile->mavlink)
    throw InputError(a.autopilot.empty() ? "autopilot" : "--autopilot",
                     fmt::format("UAV '{}' flies {}, which takes no MAVLink upload; give --autopilot px4 or "
                                 "ardupilot, or export its files instead",
                                 a.uav, profile != nullptr ? profile->label : firmware));
  if (a.altitude.terrain_frame && firmware != "ardupilot")
    throw InputError(
        "--terrain-frame",
        "is for ArduPilot (PX4 refuses MAV_FRAME_GLOBAL_TERRAIN_ALT); give --autopilot ardupilot");
  std::vector<waypoints::MissionItem> exported;
  try {
    // ArduCopter turns to headings on CONDITION_YAW, which PX4 refuses (docs/exports.md "Attitude")
    exported = firmware == "ardupilot" ? waypoints::ardupilot_mission_items(plan, index, a.altitude)
                                       : waypoints::mission_items(plan, index, a.altitude);
  } catch (const InputError& e) {
    // the library names its fields; on the command line they are these options
    const std::string problem = std::string(e.what()).substr(e.field().empty() ? 0 : e.field().size() + 2);
    if (e.field() == "altitude.transition_ceiling_m") throw InputError("--transition-ceiling", problem);
    throw;
  }
  std::optional<LonLat> home;
  if (!a.no_home) home = plan.mission.uavs.at(index).start_resolved;
  const auto items = mavlink::to_mission_items(exported, home);
  // refused before anything is sent: a vehicle answers MAV_MISSION_NO_SPACE halfway, or drops items
  const std::size_t capacity = a.max_items > 0 ? static_cast<std::size_t>(a.max_items)
                                               : mission_capacity(*profile, plan.mission.max_mission_items);
  if (items.size() > capacity)
    throw InputError(
        a.max_items > 0 ? "--max-items" : "uavs",
        fmt::format("UAV '{}': the mission has {} items{}, more than {} stores ({}); nothing was "
                    "sent. Export it split (`uavcover export --split-capacity`) and upload each "
                    "part, or give a board's own capacity with --max-items",
                    a.uav, items.size(), home ? " with home" : "", profile->label, capacity));
  // the geofence and the rally points (issue 31): sent after the mission with their own mission types
  std::vector<mavlink::MissionItemInt> fence, rally;
  if (!a.no_fence && profile->fence)
    fence = mavlink::to_mission_items(autopilot::fence_items(plan, index, exported, autopilot::kFenceMarginM),
                                      std::nullopt);
  if (!a.no_fence && profile->rally && !plan.rally.empty())
    rally = mavlink::to_mission_items(autopilot::rally_items(plan, index), std::nullopt);

  const std::uint8_t sysid = byte_option(a.sysid, "--sysid", 1);
  const std::uint8_t compid = byte_option(a.compid, "--compid", 0);
  const bool quiet = global_flags().quiet;
  std::unique_ptr<mavlink::Link> link;
  try {
    link = mavlink::open_link(to, sysid, compid);
  } catch (const std::runtime_error& e) {  // a port in use, a device that is not there
    throw OperationError(fmt::format("cannot open {}: {}", to.text(), e.what()));
  }
  // Connect / wait for the vehicle within the protocol's timeouts (the upload itself is bounded too).
  const auto wait = opt.timeout * (opt.retries + 1);
  if (auto* tcp = dynamic_cast<mavlink::TcpClientLink*>(link.get())) {
    const std::string why = tcp->connect(wait);
    if (!why.empty()) throw OperationError(fmt::format("cannot connect to {}: {}", to.text(), why));
  } else if (to.listens()) {
    if (!quiet) std::cerr << fmt::format("waiting on {} for the vehicle\n", link->describe());
    const auto deadline = std::chrono::steady_clock::now() + wait;
    while (!link->has_peer() && std::chrono::steady_clock::now() < deadline)
      (void)link->receive(std::chrono::milliseconds(50));  // accepts (TCP) or learns the peer (UDP)
    if (!link->has_peer())
      throw OperationError(fmt::format("no vehicle reached {} within {:.1f} s", link->describe(),
                                       std::chrono::duration<double>(wait).count()));
  }
  if (!quiet)
    std::cerr << fmt::format("uploading {} items for UAV '{}' to {} (system {}, component {}){}\n",
                             items.size(), a.uav, to.text(), opt.target_system, opt.target_component,
                             home ? ", item 0 = home" : "");
  const auto res = mavlink::upload_mission(*link, items, opt, [&](std::size_t done, std::size_t total) {
    if (!quiet) std::cerr << fmt::format("\r  {}/{} items", done, total) << std::flush;
  });
  if (!quiet && res.unique_items > 0) std::cerr << "\n";
  if (!res.ok) throw OperationError("upload failed: " + res.error);
  if (!quiet)
    std::cout << fmt::format(
        "{}: {} items accepted by system {} in {:.2f} s ({} item messages sent, {} timeouts, {} out-of-order "
        "requests)\n",
        a.uav, res.count, opt.target_system, res.elapsed_s, res.items_sent, res.timeouts, res.out_of_order);
  auto send_type = [&](const std::vector<mavlink::MissionItemInt>& extra, std::uint8_t type,
                       const char* what) {
    if (extra.empty()) return;
    mavlink::UploadOptions o = opt;
    o.mission_type = type;
    const auto r = mavlink::upload_mission(*link, extra, o);
    if (!r.ok)
      throw OperationError(fmt::format("the mission was accepted, the {} upload failed: {}", what, r.error));
    if (!quiet) std::cout << fmt::format("{}: {} {} items accepted\n", a.uav, r.count, what);
  };
  send_type(fence, mavlink::kMissionTypeFence, "fence");
  send_type(rally, mavlink::kMissionTypeRally, "rally");
}

const bool registered = CommandRegistry::add(50, [](CLI::App& app) {
  auto args = std::make_shared<UploadArgs>();
  auto* cmd = app.add_subcommand("upload",
                                 "Upload one UAV's mission to a vehicle over MAVLink 2 (UDP, TCP or serial)");
  cmd->add_option("PLAN_DIR", args->plan_dir,
                  "Plan folder written by `uavcover plan` (plan.json, paths.geojson)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--uav", args->uav, "Id of the UAV whose mission is sent")->required();
  cmd->add_option("--to", args->to,
                  "Vehicle address: udp:HOST:PORT (we send from an ephemeral port; it answers there), "
                  "udpin:HOST:PORT (wait for the vehicle's datagrams there), tcp:HOST:PORT (connect), "
                  "tcpin:HOST:PORT (wait for the vehicle to connect) or serial:DEVICE:BAUD (8N1)")
      ->required();
  cmd->add_option("--timeout", args->timeout_s, "Seconds to wait for the vehicle before resending")
      ->capture_default_str()
      ->check(number_in(0, 60, true));
  cmd->add_option("--retries", args->retries, "Resends after a timeout before giving up")
      ->capture_default_str()
      ->check(integer_in(0, 100));
  cmd->add_option("--target-system", args->target_system, "Vehicle MAVLink system id")
      ->capture_default_str()
      ->check(integer_in(1, 255));
  cmd->add_option("--target-component", args->target_component, "Vehicle MAVLink component id")
      ->capture_default_str()
      ->check(integer_in(0, 255));
  cmd->add_option("--sysid", args->sysid, "Our MAVLink system id")
      ->capture_default_str()
      ->check(integer_in(1, 255));
  cmd->add_option("--compid", args->compid, "Our MAVLink component id")
      ->capture_default_str()
      ->check(integer_in(0, 255));
  cmd->add_option("--autopilot", args->autopilot,
                  "Flight software of the vehicle: px4 or ardupilot (headings also as "
                  "MAV_CMD_CONDITION_YAW); default: the plan's vehicle profile, else px4");
  cmd->add_option("--max-items", args->max_items,
                  "Mission items the vehicle stores (default: the profile's: PX4 500, ArduPilot 700 or the "
                  "mission's max_mission_items); a larger mission is refused before anything is sent")
      ->check(integer_in(8, 65535));
  cmd->add_flag("--no-fence", args->no_fence,
                "Send only the mission, not the geofence (MAV_MISSION_TYPE_FENCE) and rally points "
                "(MAV_MISSION_TYPE_RALLY)");
  cmd->add_flag("--no-home", args->no_home,
                "Do not send the home position as item 0 (ArduPilot expects it there; PX4 does not)");
  cmd->add_option("--transition-base", args->altitude.transition_base_m,
                  "Transition altitude of the first UAV (m); 0 = max(60, mission altitude + 20)")
      ->capture_default_str()
      ->check(number_in(0, 10'000));
  cmd->add_option("--transition-step", args->altitude.transition_step_m,
                  "Transition altitude added per UAV (m)")
      ->capture_default_str()
      ->check(number_in(0, 1'000));
  cmd->add_option("--transition-ceiling", args->altitude.transition_ceiling_m,
                  "Highest transition altitude (m above take-off; 0 = none); the step is compressed to fit "
                  "while it stays >= --min-separation")
      ->capture_default_str()
      ->check(number_in(0, 10'000));
  cmd->add_option("--min-separation", args->altitude.min_vertical_separation_m,
                  "Smallest transition step (m) the ceiling may compress the step to")
      ->capture_default_str()
      ->check(number_in(0.1, 1'000));
  cmd->add_flag("--land", args->altitude.land_instead_of_rtl, "End with LAND at home instead of RTL");
  cmd->add_flag("--terrain-frame", args->altitude.terrain_frame,
                "ArduPilot, with a DEM: coverage heights above the terrain in MAV_FRAME_GLOBAL_TERRAIN_ALT "
                "(docs/photogrammetry.md)");
  cmd->footer(
      "The mission is the one `uavcover export` writes (take-off, speed, transition altitudes, coverage,\n"
      "RTL/land); latitude/longitude are sent as degrees * 1e7 in MISSION_ITEM_INT. Timeouts and retries\n"
      "follow the MAVLink mission protocol (1.5 s, 5 retries); requests are served in any order.\n"
      "A failed upload the vehicle had answered is followed by MISSION_CLEAR_ALL: the message says whether\n"
      "the vehicle acknowledged it, or warns that it may hold a partial mission (docs/upload.md).\n"
      "Then the geofence (the .plan's: an inclusion polygon around everything flown, the no-fly zones as\n"
      "exclusions) and the plan's rally points, each with its own mission type (docs/fence-rally.md).\n"
      "Exit codes: 0 accepted, 1 upload failed (no answer, vehicle refused, no connection), 2 bad input.");
  cmd->callback([args] { run_upload(*args); });
});

}  // namespace
}  // namespace uavcover::cli
