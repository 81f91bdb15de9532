// `uavcover plan MISSION.json --out DIR`: parse, plan through the facade, write the plan directory.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli/command.hpp"
#include "cli/progress.hpp"
#include "io/plan_io.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover::cli {
namespace {

struct PlanArgs {
  std::string mission;
  std::string out;
  std::optional<std::uint64_t> seed;
  std::size_t max_cells = ParseOptions{}.max_cells;
};

void run_plan(const PlanArgs& a) {
  ParseOptions po;
  po.max_cells = a.max_cells;
  const Mission mission = parse_mission(read_file(a.mission, "MISSION"), po);
  PlanOptions opt;
  opt.seed = a.seed;
  const bool quiet = global_flags().quiet;
  Plan result;
  try {
    result = plan(mission, opt, make_progress_bar(quiet));
  } catch (...) {
    finish_progress_bar();
    throw;
  }
  finish_progress_bar();
  const std::filesystem::path dir(a.out);
  io::write_file_atomic(dir / "paths.geojson", io::paths_geojson(result).dump(1) + "\n");
  io::write_file_atomic(dir / "plan.json", io::plan_json(result).dump(1) + "\n");
  if (quiet) return;
  std::cout << fmt::format("{} — {} UAV(s), spacing {:.1f} m, mode {}, seed {}\n", result.mission.name,
                           result.uavs.size(), result.mission.spacing_m,
                           result.mission.mode == Mode::Strict ? "strict" : "coverage", result.mission.seed);
  std::cout << fmt::format("{:<12} {:>8} {:>8} {:>7} {:>7} {:>11}\n", "uav", "share", "actual", "cells", "turns",
                           "length_km");
  for (const auto& u : result.uavs)
    std::cout << fmt::format("{:<12} {:>8.3f} {:>8.3f} {:>7} {:>7} {:>11.3f}\n", u.id, u.share_requested,
                             u.share_actual, u.cells, u.turns, u.length_m / 1000.0);
  for (const auto& w : result.warnings) std::cout << "warning: " << w << "\n";
  std::cout << fmt::format("wrote {} and {} ({:.3f} s)\n", (dir / "paths.geojson").string(),
                           (dir / "plan.json").string(), result.compute_time_s);
}

const bool registered = CommandRegistry::add(10, [](CLI::App& app) {
  auto args = std::make_shared<PlanArgs>();
  auto* cmd = app.add_subcommand("plan", "Plan a coverage mission: divide the area among the UAVs and build their paths");
  cmd->add_option("MISSION", args->mission, "Mission file (uavcover v1 JSON, or mCPP-optimized-DARP input)")
      ->required();
  cmd->add_option("--out,-o", args->out, "Output folder: paths.geojson and plan.json are written there")->required();
  cmd->add_option("--seed", args->seed, "Random seed (overrides the mission's seed); same seed, same plan");
  cmd->add_option("--max-cells", args->max_cells, "Refuse missions whose grid needs more cells than this")
      ->capture_default_str();
  cmd->footer(
      "Outputs:\n"
      "  DIR/paths.geojson  FeatureCollection: per UAV LineStrings (kind coverage|transit, uav, share_requested,\n"
      "                     share_actual, length_m, turns) and Polygons for the area and no-fly zones (role).\n"
      "  DIR/plan.json      normalised mission, spacing, GSD/footprint, grid placement (J, J1-J3), per-UAV and\n"
      "                     total metrics.\n"
      "Exit codes: 0 ok, 1 internal error, 2 bad input (message names the field; no files written).");
  cmd->callback([args] { run_plan(*args); });
});

}  // namespace
}  // namespace uavcover::cli
