// `uavcover export PLAN_DIR --format F[,F...] [--out DIR]`: flight-ready files for every UAV of a plan.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <map>

#include "cli/command.hpp"
#include "cli/mission_file.hpp"
#include "cli/trajectory_options.hpp"
#include "cli/validators.hpp"
#include "export/export.hpp"
#include "io/plan_io.hpp"
#include "trajectory/trajectory.hpp"
#include "uavcover/error.hpp"

namespace uavcover::cli {
namespace {

struct ExportArgs {
  std::string plan_dir;
  std::vector<std::string> formats;
  std::string out;
  exporting::ExportOptions opt;
  std::string corners = "fillet";
};

void run_export(ExportArgs& a) {
  if (a.corners == "stop") {
    a.opt.trajectory.corners = trajectory::CornerMode::Stop;
  } else if (a.corners == "fillet") {
    a.opt.trajectory.corners = trajectory::CornerMode::Fillet;
  } else {
    throw InputError("--corners", "must be 'stop' or 'fillet'");
  }
  if (a.opt.trajectory.densify_m < 0) throw InputError("--densify", "must be >= 0");
  if (a.opt.trajectory.fillet_radius_m < 0) throw InputError("--fillet-radius", "must be >= 0");
  const Plan plan = read_plan_dir(a.plan_dir);
  const std::filesystem::path out =
      a.out.empty() ? std::filesystem::path(a.plan_dir) : std::filesystem::path(a.out);
  std::vector<std::string> warnings;
  a.opt.warnings = &warnings;
  std::map<std::string, trajectory::Trajectory> trajectories;  // made by the trajectory formats, if asked
  a.opt.trajectories = &trajectories;
  Artifacts artifacts;
  try {
    artifacts = exporting::export_artifacts(plan, a.formats, a.opt);
  } catch (const InputError& e) {
    // the library names its fields; on the command line they are these options
    const std::string problem = std::string(e.what()).substr(e.field().empty() ? 0 : e.field().size() + 2);
    if (e.field() == "formats") throw InputError("--format", problem);
    if (e.field() == "altitude.transition_ceiling_m") throw InputError("--transition-ceiling", problem);
    if (e.field() == "autopilot" && !a.opt.autopilot.empty()) throw InputError("--autopilot", problem);
    rethrow_as_flag(e);
  }
  const auto files = io::write_artifacts(out, artifacts);
  for (const auto& w : warnings) std::cerr << "uavcover: warning: " << w << "\n";
  if (global_flags().quiet) return;
  const auto altitudes =
      waypoints::resolve_altitudes(a.opt.altitude, waypoints::altitude_slots(plan), plan.mission.altitude_m);
  for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
    if (exporting::idle(plan.uavs[i])) continue;
    // the summary's trajectory: the one the export made, else made for it
    const auto made = trajectories.find(plan.uavs[i].id);
    const auto traj = made != trajectories.end()
                          ? made->second
                          : trajectory::uav_trajectory(plan, i, a.opt.trajectory, altitudes);
    std::string limits;
    if (traj.method() == trajectory::Method::Polynomial) {  // whether its bounds hold, and its extremes
      const auto& r = traj.report();
      limits = fmt::format(
          ", limits {} (v {:.2f}..{:.2f} m/s, |v| {:.2f}, a {:.2f}..{:.2f} m/s^2, |a| {:.2f}; "
          "{} of {} segments stretched)",
          r.hold ? "hold" : "BROKEN", r.v_lo, r.v_hi, r.speed_max, r.a_lo, r.a_hi, r.accel_max, r.stretched,
          traj.polynomials().size());
    }
    std::cout << fmt::format(
        "{:<12} transition altitude {:>6.1f} m, {} trajectory flight time {:>8.1f} s{}\n", plan.uavs[i].id,
        waypoints::transition_altitude(altitudes, waypoints::altitude_slot(plan, i), plan.mission.altitude_m),
        trajectory::method_name(traj.method()), traj.duration(), limits);
  }
  std::cout << fmt::format("wrote {} file(s) under {}\n", files.size(), out.string());
}

const bool registered = CommandRegistry::add(40, [](CLI::App& app) {
  auto args = std::make_shared<ExportArgs>();
  auto* cmd = app.add_subcommand(
      "export", "Write flight-ready files (QGC, Mission Planner, KML, DJI, Litchi, ...) for a plan");
  cmd->add_option("PLAN_DIR", args->plan_dir,
                  "Plan folder written by `uavcover plan` (plan.json, paths.geojson)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--format,-f", args->formats, "Formats, comma-separated: " + exporting::format_list())
      ->required()
      ->delimiter(',')
      ->check(export_format());
  cmd->add_option("--out,-o", args->out,
                  "Output folder (default: PLAN_DIR); files go to OUT/export/ and OUT/trajectory/")
      ->check(output_folder());
  cmd->add_option("--transition-base", args->opt.altitude.transition_base_m,
                  "Transition altitude of the first UAV (m); 0 = max(60, mission altitude + 20)")
      ->capture_default_str()
      ->check(number_in(0, 10'000));
  cmd->add_option("--transition-step", args->opt.altitude.transition_step_m,
                  "Transition altitude added per UAV (m)")
      ->capture_default_str()
      ->check(number_in(0, 1'000));
  cmd->add_option("--transition-ceiling", args->opt.altitude.transition_ceiling_m,
                  "Highest transition altitude (m above take-off; 0 = none); the step is compressed to fit "
                  "while it stays >= --min-separation")
      ->capture_default_str()
      ->check(number_in(0, 10'000));
  cmd->add_option("--min-separation", args->opt.altitude.min_vertical_separation_m,
                  "Smallest transition step (m) the ceiling may compress the step to")
      ->capture_default_str()
      ->check(number_in(0.1, 1'000));
  cmd->add_option("--geofence-margin", args->opt.geofence_margin_m,
                  "QGC .plan: inclusion fence margin around everything flown (m)")
      ->capture_default_str()
      ->check(number_in(0, 10'000));
  cmd->add_flag("--land", args->opt.altitude.land_instead_of_rtl, "End with LAND at home instead of RTL");
  cmd->add_option("--autopilot", args->opt.autopilot,
                  "Flight software the files are for: px4 (default), ardupilot, dji or litchi; sets the QGC "
                  ".plan firmwareType (3 ardupilot, 12 otherwise)");
  cmd->add_option("--firmware-type", args->opt.qgc_firmware_type,
                  "QGC .plan firmwareType (MAV_AUTOPILOT: 12 PX4, 3 ArduPilot); overrides --autopilot")
      ->check(integer_in(0, 255));
  cmd->add_option("--vehicle-type", args->opt.qgc_vehicle_type,
                  "QGC .plan vehicleType (MAV_TYPE: 2 quadrotor)")
      ->capture_default_str()
      ->check(integer_in(0, 255));
  cmd->add_flag("--kmz", args->opt.kmz, "Also write <id>.kmz next to each <id>.kml");
  cmd->add_flag(
      "--per-sortie", args->opt.per_sortie,
      "One file per battery sortie for " + per_sortie_format_list() + ": <id>.s<k>.<ext> (docs/sorties.md)");
  cmd->add_flag("--terrain-frame", args->opt.altitude.terrain_frame,
                "With a DEM and terrain following, for ArduPilot: coverage heights above the terrain in "
                "MAV_FRAME_GLOBAL_TERRAIN_ALT (the vehicle follows the ground from its own terrain data); "
                "default: above mean sea level (docs/photogrammetry.md)");
  cmd->add_flag("--split-capacity", args->opt.split_capacity,
                "Split each UAV's missions to the vehicle's item capacity (PX4 500, ArduPilot 700 or the "
                "mission's max_mission_items, DJI 65535 and Litchi 99 waypoints): <id>.s<k>.<ext> as "
                "--per-sortie, each sortie cut further where it holds more (docs/vehicle-limits.md)");
  cmd->add_option("--dji-drone", args->opt.dji_drone_enum, "DJI WPML droneEnumValue (77 Mavic 3 Enterprise)")
      ->capture_default_str()
      ->check(integer_in(0, 100'000));
  cmd->add_option("--dji-drone-sub", args->opt.dji_drone_sub_enum, "DJI WPML droneSubEnumValue")
      ->capture_default_str()
      ->check(integer_in(0, 100'000));
  cmd->add_option("--dji-payload", args->opt.dji_payload_enum,
                  "DJI WPML payloadEnumValue (-1 = the drone's own camera)")
      ->capture_default_str()
      ->check(integer_in(-1, 100'000));
  cmd->add_option("--trajectory-step", args->opt.trajectory_step_s,
                  "Trajectory: sample trajectory/<id>.csv every this many seconds; without it the file is "
                  "the segment form, one row per breakpoint (docs/trajectory.md)")
      ->check(number_in(0.001, 60));
  cmd->add_option("--dt", args->opt.trajectory_step_s, "The old name of --trajectory-step")
      ->check(number_in(0.001, 60));
  cmd->add_option("--densify", args->opt.trajectory.densify_m,
                  "Trajectory: split legs longer than this (m, 0 = off)")
      ->capture_default_str()
      ->check(number_in(0.1, 100'000, false, false, true));
  cmd->add_option("--corners", args->corners, "Trajectory corners: fillet or stop")
      ->capture_default_str()
      ->check(CLI::IsMember({"fillet", "stop"}));
  cmd->add_option("--fillet-radius", args->opt.trajectory.fillet_radius_m, "Trajectory corner radius (m)")
      ->capture_default_str()
      ->check(number_in(0, 1'000));
  add_trajectory_method_options(cmd, args->opt.trajectory);
  cmd->footer(
      std::string("Outputs (one file per UAV, named by its id):\n") +
      "  OUT/export/<id>.geojson     RFC 7946 FeatureCollection (area, no-fly zones, the UAV's path)\n"
      "  OUT/export/<id>.plan        QGroundControl plan (takeoff 22, waypoints 16 frame 3, speed 178,\n"
      "                              camera trigger 206, RTL 20 / land 21, geofence)\n"
      "  OUT/export/<id>.waypoints   Mission Planner QGC WPL 110 (row 0 home)\n"
      "  OUT/export/<id>.kml         KML (area, no-fly zones, 3D path); --kmz adds <id>.kmz\n"
      "  OUT/export/<id>.wpml.kmz    DJI WPML (wpmz/template.kml, wpmz/waylines.wpml)\n"
      "  OUT/export/<id>.litchi.csv  Litchi mission CSV (<id>.1.litchi.csv, ... beyond 99 waypoints)\n"
      "  OUT/export/<id>.csv         mission items as CSV\n"
      "  OUT/trajectory/<id>.csv     the segment form: t,kind,x,y,z,lat,lon,vx,vy,vz,ax,ay,az,v_max,a_max,\n"
      "                              one row per breakpoint (accelerate, cruise, decelerate, arc, end);\n"
      "                              with --trajectory-step S (or --trajectory-method polynomial, at S or\n"
      "                              0.1 s): t,x,y,z,lat,lon,vx,vy,vz,ax,ay,az every S s\n"
      "  OUT/export/<id>.trajectory.png  position, velocity, acceleration against time (trajectory_plot)\n"
      "With --per-sortie, <id>.s1.<ext>, <id>.s2.<ext>, ... (one whole mission per battery sortie) replace\n"
      "<id>.<ext> for " +
      per_sortie_format_list() +
      ".\n"
      "Each UAV climbs to its own transition altitude (base + index * step) for transit legs and covers\n"
      "at the mission altitude (Hong et al. 2021 §2.3), under --transition-ceiling.\n"
      "UAVs without coverage parts are skipped with a warning; values beyond a consumer's limits are\n"
      "clamped with a warning (speeds) or refused (altitudes): see docs/exports.md.\n"
      "Exit codes: 0 ok, 1 internal error, 2 bad input (unknown format, unusable plan folder).");
  cmd->callback([args] { run_export(*args); });
});

}  // namespace
}  // namespace uavcover::cli
