// `uavcover plan MISSION.json --out DIR`: parse, plan through the facade, write the plan directory.
#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <iostream>

#include "cli/command.hpp"
#include "cli/interrupt.hpp"
#include "cli/mission_file.hpp"
#include "cli/progress.hpp"
#include "cli/trajectory_options.hpp"
#include "cli/validators.hpp"
#include "export/export.hpp"
#include "io/plan_io.hpp"
#include "io/write_artifacts.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/plan_outputs.hpp"

namespace uavcover::cli {
namespace {

struct PlanArgs {
  std::string mission;
  std::string out;
  std::optional<std::uint64_t> seed;
  std::optional<double> time_limit_s;
  std::size_t max_cells = ParseOptions{}.max_cells;
  std::vector<std::string> exports;
  bool no_evaluate = false;
  bool no_images = false;
  bool per_sortie = false;
  double trajectory_step_s = 0;
  trajectory::Options trajectory;
};

void run_plan(const PlanArgs& a) {
  const bool quiet = global_flags().quiet;
  std::optional<Context::Clock::duration> limit;
  if (a.time_limit_s)
    limit =
        std::chrono::duration_cast<Context::Clock::duration>(std::chrono::duration<double>(*a.time_limit_s));
  const Progress bar = make_progress_bar(quiet);
  // one context for the whole command, its time limit counted from here (reading the mission too):
  // Ctrl-C and the time limit land in every stage, the writing too
  const Context ctx(bar, interrupt_token(), limit);
  ParseOptions po;
  po.max_cells = a.max_cells;
  const Mission mission = read_mission(a.mission, po);
  PlanOptions opt;
  opt.seed = a.seed;
  usecases::OutputOptions oo;
  oo.evaluate = !a.no_evaluate;
  oo.images = !a.no_images;
  oo.exports = a.exports;
  oo.per_sortie = a.per_sortie;
  oo.trajectory_step_s = a.trajectory_step_s;
  oo.trajectory = a.trajectory;
  // what the exports would refuse after planning (transition altitudes over the ceiling, trajectory
  // bounds no UAV can keep) is refused now
  try {
    usecases::check_outputs(mission, oo);
  } catch (const InputError& e) {
    rethrow_as_flag(e);
  }
  Plan result;
  usecases::PlanOutputs outputs;
  std::vector<std::filesystem::path> files;
  const std::filesystem::path dir(a.out);
  try {
    result = plan(mission, opt, ctx);
    outputs = usecases::plan_outputs(result, oo, ctx);
    files = io::write_artifacts(dir, outputs.artifacts, ctx);
  } catch (...) {
    finish_progress_bar();
    throw;
  }
  finish_progress_bar();
  for (const auto& w : outputs.warnings) std::cerr << "uavcover: warning: " << w << "\n";
  if (quiet) return;
  std::cout << fmt::format("{} — {} UAV(s), planner {}, spacing {:.1f} m, mode {}, seed {}\n",
                           result.mission.name, result.uavs.size(), result.planner, result.mission.spacing_m,
                           result.mission.mode == Mode::Strict ? "strict" : "coverage", result.mission.seed);
  std::cout << fmt::format("{:<12} {:>8} {:>8} {:>7} {:>11}\n", "uav", "share", "actual", "turns",
                           "length_km");
  for (const auto& u : result.uavs)
    std::cout << fmt::format("{:<12} {:>8.3f} {:>8.3f} {:>7} {:>11.3f}\n", u.id, u.share_requested,
                             u.share_actual, u.turns, u.length_m / 1000.0);
  for (const auto& w : result.warnings) std::cout << "warning: " << w << "\n";
  if (outputs.poc >= 0)
    std::cout << fmt::format(
        "coverage {:.2f} % (overlap {:.2f} %), flight time {:.1f} min (trajectories: "
        "{:.1f} min), total {:.1f} min, cost {:.2f} EUR\n",
        outputs.poc * 100, outputs.pooc * 100, outputs.flight_time_min, outputs.trajectory_flight_time_min,
        outputs.total_time_min, outputs.cost_eur);
  std::cout << fmt::format("planned in {:.3f} s{}; wrote {} files to {}\n", result.compute_time_s,
                           result.complete ? "" : " (time limit: best plan so far)", files.size(),
                           dir.string());
}

const bool registered = CommandRegistry::add(10, [](CLI::App& app) {
  auto args = std::make_shared<PlanArgs>();
  auto* cmd = app.add_subcommand(
      "plan", "Plan a coverage mission: divide the area among the UAVs and build their paths");
  cmd->add_option("MISSION", args->mission, "Mission file (uavcover v1 JSON, or mCPP-optimized-DARP input)")
      ->required();
  cmd->add_option("--out,-o", args->out, "Output folder: paths.geojson and plan.json are written there")
      ->required()
      ->check(output_folder());
  cmd->add_option("--seed", args->seed, "Random seed (overrides the mission's seed); same seed, same plan")
      ->check(integer_in<std::uint64_t>(0, std::numeric_limits<std::uint64_t>::max()));
  cmd->add_option("--time-limit", args->time_limit_s,
                  "Time budget of the whole command in seconds: the planner's best complete plan so far "
                  "is returned with a warning (evaluation, pictures and exports that do not fit are left "
                  "out and named; plan.json and paths.geojson are always written), or the command fails "
                  "with exit code 3 when it has no complete plan")
      ->check(number_in(0.0, 1e6, true));
  cmd->add_option("--max-cells", args->max_cells, "Refuse missions whose grid needs more cells than this")
      ->capture_default_str()
      ->check(integer_in<std::size_t>(1, kMaxCellsLimit));
  cmd->add_option(
         "--export", args->exports,
         "Also export these formats, comma-separated: " + exporting::format_list() + " (docs/exports.md)")
      ->delimiter(',')
      ->check(export_format());
  cmd->add_flag("--per-sortie", args->per_sortie,
                "With --export: one file per battery sortie for " + per_sortie_format_list() +
                    ", export/<id>.s<k>.<ext> (docs/sorties.md)");
  cmd->add_option("--trajectory-step", args->trajectory_step_s,
                  "With --export trajectory: sample trajectory/<id>.csv every this many seconds (t,x,y,z,lat,"
                  "lon,vx,vy,vz,ax,ay,az); without it the file is the segment form, one row per breakpoint "
                  "(docs/trajectory.md)")
      ->check(number_in(0.001, 60));
  add_trajectory_method_options(cmd, args->trajectory);
  cmd->add_flag("--no-evaluate", args->no_evaluate, "Skip the coverage simulation and cost model");
  cmd->add_flag("--no-images", args->no_images, "Skip plan.png, plan.svg, heatmap.png, histogram.png");
  cmd->footer(
      "Outputs:\n"
      "  DIR/paths.geojson  FeatureCollection: per UAV LineStrings (kind coverage|transit, uav, "
      "share_requested,\n"
      "                     share_actual, length_m, turns) and Polygons for the area and no-fly zones "
      "(role).\n"
      "  DIR/plan.json      normalised mission, planner and its diagnostics, per-UAV regions and metrics,\n"
      "                     coverage (PoC, PoOC, histogram) and time/cost (eq. 15-22).\n"
      "  DIR/plan.png, plan.svg, heatmap.png, histogram.png   pictures for the report.\n"
      "  DIR/export/, DIR/trajectory/   with --export (--per-sortie: export/<id>.s<k>.<ext> per sortie).\n"
      "Exit codes: 0 ok, 1 internal error, 2 bad input (message names the field; no files written),\n"
      "3 time limit reached without a complete plan, 130 interrupted (Ctrl-C; no files written).");
  cmd->callback([args] { run_plan(*args); });
});

}  // namespace
}  // namespace uavcover::cli
