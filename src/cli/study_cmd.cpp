// `uavcover study MISSION.json --uavs 1..15 [--out DIR]`: the multi-robot marginal utility study of
// Apostolidis et al. 2022 §3.2 (Tables 7 and 8): plan for each UAV count, evaluate, compare.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli/command.hpp"
#include "cli/cost_options.hpp"
#include "cli/interrupt.hpp"
#include "cli/mission_file.hpp"
#include "cli/progress.hpp"
#include "cli/validators.hpp"
#include "io/plan_io.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/study.hpp"

namespace uavcover::cli {
namespace {

struct StudyArgs {
  std::string mission;
  std::string uavs = "1..15";
  std::string out = ".";
  std::optional<std::uint64_t> seed;
  bool no_images = false;
  evaluation::CostOptions cost;
};

void run_study(const StudyArgs& a) {
  const Mission mission = read_mission(a.mission);
  usecases::StudyOptions so;
  so.counts = usecases::parse_uav_counts(a.uavs, "--uavs");
  so.seed = a.seed;
  so.cost = a.cost;
  const bool quiet = global_flags().quiet;
  const auto study =
      with_progress(quiet, [&](const Context& ctx) { return usecases::run_study(mission, so, ctx); });
  const auto& counts = so.counts;
  const auto& rows = study.rows;
  const int best = study.recommended, single = study.min_single_battery;
  double best_total = 0.0;
  for (const auto& r : rows)
    if (r.ok && r.uavs == best) best_total = r.evaluation.cost.total_time_min;
  Artifacts outputs{{"study.json", "application/json", usecases::study_json(study).dump(1) + "\n"}};
  if (!a.no_images) outputs.push_back(usecases::study_picture(study));
  const std::filesystem::path dir(a.out);
  io::write_artifacts(dir, outputs);
  if (quiet) return;

  std::cout << fmt::format("{} — study over {} UAV count(s)\n", mission.name, counts.size());
  if (mission.wind && mission.wind->speed_mps > 0.0)
    std::cout << fmt::format("times in the mission's wind: {} m/s from {} degrees\n", mission.wind->speed_mps,
                             mission.wind->from_deg);
  std::cout << fmt::format("{:>5} {:>7} {:>7} {:>8} {:>10} {:>10} {:>10} {:>10} {:>9} {:>9}\n", "#UAVs",
                           "PoC%", "PoOC%", "#Bat/UAV", "Flight", "Deploy", "ChangeBat", "Total", "Cost",
                           "Compute");
  std::cout << fmt::format("{:>5} {:>7} {:>7} {:>8} {:>10} {:>10} {:>10} {:>10} {:>9} {:>9}\n", "", "", "",
                           "", "(min)", "(min)", "(min)", "(min)", "(EUR)", "(s)");
  for (const auto& r : rows) {
    if (!r.ok) {
      std::cout << fmt::format("{:>5}  failed: {}\n", r.uavs, r.error);
      continue;
    }
    const auto& t = r.evaluation.coverage.total;
    const auto& c = r.evaluation.cost;
    std::cout << fmt::format(
        "{:>5} {:>7.2f} {:>7.2f} {:>8} {:>10.2f} {:>10.2f} {:>10.2f} {:>10.2f} {:>9.2f} {:>9.2f}{}\n", r.uavs,
        100 * t.poc, 100 * t.pooc, c.batteries_per_uav, c.flight_time_min, c.deployment_time_min,
        c.change_battery_delay_min, c.total_time_min, c.flight_cost_eur, r.compute_s,
        r.uavs == best ? "  <- minimum total time" : "");
  }
  std::cout << fmt::format("recommended: {} UAV(s) (minimum total time {:.2f} min)\n", best, best_total);
  if (single > 0)
    std::cout << fmt::format("fewest UAVs in this study with which every UAV finishes on one battery: {}\n",
                             single);
  else
    std::cout << "no UAV count in this study lets every UAV finish on one battery\n";
  std::cout << "wrote " << (dir / "study.json").string() << (a.no_images ? "" : " and study.png") << "\n";
}

const bool registered = CommandRegistry::add(40, [](CLI::App& app) {
  auto a = std::make_shared<StudyArgs>();
  auto* cmd = app.add_subcommand(
      "study",
      "Multi-UAV study: plan and evaluate the mission for several UAV counts, recommend the best count");
  cmd->add_option("MISSION", a->mission,
                  "Mission file (its first UAV's speed/endurance are used for added UAVs)")
      ->required();
  cmd->add_option("--uavs", a->uavs, "UAV counts: 1..15, or 1,2,3,5, or a mix")->capture_default_str();
  cmd->add_option("--out,-o", a->out, "Output folder for study.json and study.png")
      ->capture_default_str()
      ->force_callback()  // the default (the current folder) is checked too
      ->check(output_folder());
  cmd->add_option("--seed", a->seed, "Random seed (overrides the mission's seed)")
      ->check(integer_in<std::uint64_t>(0, std::numeric_limits<std::uint64_t>::max()));
  cmd->add_flag("--no-images", a->no_images, "Do not write study.png");
  add_cost_options(cmd, a->cost);
  cmd->footer(
      "UAVs beyond those the mission lists copy the first UAV's parameters and get seeded random starts;\n"
      "shares are equal. Exit codes: 0 ok, 1 internal error, 2 bad input.");
  cmd->callback([a] { run_study(*a); });
});

}  // namespace
}  // namespace uavcover::cli
