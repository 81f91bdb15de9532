// `uavcover evaluate MISSION.json PATHS.geojson [--out DIR]`: coverage, time and cost of any plan given
// as GeoJSON LineStrings per UAV (ours or another tool's), Apostolidis et al. 2022 §3.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli/command.hpp"
#include "cli/cost_options.hpp"
#include "cli/interrupt.hpp"
#include "cli/mission_file.hpp"
#include "cli/validators.hpp"
#include "io/plan_io.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/evaluate_paths.hpp"

namespace uavcover::cli {
namespace {

struct EvaluateArgs {
  std::string mission;
  std::string paths;
  std::string out = ".";
  double footprint_m = 0.0;
  double lattice_m = 0.0;
  std::size_t max_samples = evaluation::CoverageOptions{}.max_samples;
  bool count_transit = false;
  bool no_images = false;
  evaluation::CostOptions cost;
};

void run_evaluate(const EvaluateArgs& a) {
  const Mission mission = read_mission(a.mission);
  const std::string text = io::read_text_file(a.paths, "PATHS");
  evaluation::EvaluateOptions opt;
  opt.coverage.footprint_m = a.footprint_m;
  opt.coverage.lattice_m = a.lattice_m;
  opt.coverage.max_samples = a.max_samples;
  opt.coverage.count_transit = a.count_transit;
  opt.cost = a.cost;
  const auto result = usecases::evaluate_paths(mission, text, opt, Context({}, interrupt_token()));
  const auto& ev = result.evaluation;
  const std::filesystem::path dir(a.out);
  io::write_artifacts(dir, usecases::evaluation_outputs(result, a.paths, !a.no_images));
  if (global_flags().quiet) return;
  const auto& t = ev.coverage.total;
  const auto& c = ev.cost;
  std::cout << fmt::format("{} — {} UAV(s), footprint {:.1f} m, lattice {:.2f} m ({} samples)\n",
                           mission.name, ev.uav_ids.size(), ev.footprint_m, ev.coverage.lattice_m,
                           ev.coverage.samples);
  std::cout << fmt::format("{:<12} {:>7} {:>7} {:>6} {:>9} {:>6} {:>8} {:>6}\n", "uav", "share", "PoC%",
                           "turns", "length_km", "bat", "min", "w_m");
  for (std::size_t i = 0; i < ev.uav_ids.size(); ++i) {
    const auto& u = ev.coverage.uavs[i];
    std::cout << fmt::format("{:<12} {:>7.3f} {:>7.2f} {:>6} {:>9.3f} {:>6} {:>8.2f} {:>6.1f}\n",
                             ev.uav_ids[i], u.area_share, 100 * u.stats.poc, u.stats.turns,
                             u.stats.length_m / 1000, c.uavs[i].batteries, c.uavs[i].flight_duration_min,
                             u.footprint_m);
  }
  std::cout << fmt::format(
      "PoC {:.2f}%  PoOC {:.2f}%  max scans {}  turns {} ({:.3f}/1000 m²)  length {:.3f} km ({:.1f} m/1000 "
      "m²)\n",
      100 * t.poc, 100 * t.pooc, t.max_scans, t.turns, t.turns_per_1000m2, t.length_m / 1000,
      t.length_per_1000m2);
  std::cout << fmt::format(
      "flight time {:.2f} min  deployment {:.2f} min  battery changes {:.2f} min  total {:.2f} min  cost "
      "{:.2f} EUR\n",
      c.flight_time_min, c.deployment_time_min, c.change_battery_delay_min, c.total_time_min,
      c.flight_cost_eur);
  if (ev.facade) {  // a structure scan (docs/patterns.md): the wall, not the ground
    const auto& f = ev.facade->total;
    std::cout << fmt::format(
        "facade {:.2f} % seen ({} samples at {:.1f} m), by 0/1/2/3+ photos {:.1f} / {:.1f} / {:.1f} / {:.1f} "
        "%, "
        "{} images{}\n",
        100 * f.covered_share, f.samples, ev.facade->sample_m, 100 * f.shares[0], 100 * f.shares[1],
        100 * f.shares[2], 100 * f.shares[3], f.images,
        ev.facade->gsd_wall_m ? fmt::format(", GSD on the wall {:.2f} cm/px", *ev.facade->gsd_wall_m * 100)
                              : "");
  }
  if (t.poc == 0.0 && t.length_m > 0.0)
    std::cout << "warning: the paths scan none of the area: do they belong to this mission?\n";
  std::cout << "wrote " << (dir / "evaluation.json").string()
            << (a.no_images ? "" : ", heatmap.png, histogram.png and paths.png") << "\n";
}

const bool registered = CommandRegistry::add(30, [](CLI::App& app) {
  auto a = std::make_shared<EvaluateArgs>();
  auto* cmd = app.add_subcommand(
      "evaluate",
      "Evaluate any plan (GeoJSON LineStrings per UAV): coverage, overlap, turns, length, time, cost");
  cmd->add_option("MISSION", a->mission, "Mission file (area, no-fly zones, spacing/camera, UAV parameters)")
      ->required();
  cmd->add_option("PATHS", a->paths,
                  "GeoJSON LineStrings: properties.uav names the UAV (else one UAV per line), "
                  "properties.kind = transit marks transit legs")
      ->required();
  cmd->add_option("--out,-o", a->out,
                  "Output folder for evaluation.json, heatmap.png, histogram.png, paths.png")
      ->capture_default_str()
      ->force_callback()  // the default (the current folder) is checked too
      ->check(output_folder());
  cmd->add_option("--footprint", a->footprint_m,
                  "Footprint width w in metres for every UAV (default: each UAV's own camera, "
                  "uavs[i].camera, else the mission's camera, else 1.5 x spacing)")
      ->check(number_in(0, 10'000, true));
  cmd->add_option("--lattice", a->lattice_m, "Sample spacing in metres (default: adaptive, 0.5-2 m)")
      ->check(number_in(0, 1'000, true));
  cmd->add_option("--max-samples", a->max_samples, "Cap on lattice samples")
      ->capture_default_str()
      ->check(integer_in<std::size_t>(1'000, 200'000'000));
  cmd->add_flag("--count-transit", a->count_transit, "Transit legs scan too");
  cmd->add_flag("--no-images", a->no_images, "Do not write the pictures");
  add_cost_options(cmd, a->cost);
  cmd->footer(
      "evaluation.json: totals at top level (poc, pooc, max_scans, histogram, turns, length_m, "
      "flight_time_min,\n"
      "total_time_min, cost_eur, ...) and per-UAV figures under \"uavs\".\n"
      "Exit codes: 0 ok, 1 internal error, 2 bad input (message names the field).");
  cmd->callback([a] { run_evaluate(*a); });
});

}  // namespace
}  // namespace uavcover::cli
