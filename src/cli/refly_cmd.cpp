// `uavcover refly PLAN_DIR --flown LOG | --photos DIR --out DIR` (issue 32, docs/refly.md, docs/photos.md):
// plan what a flight left out, from its log or from its photos.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli/command.hpp"
#include "cli/interrupt.hpp"
#include "cli/progress.hpp"
#include "cli/validators.hpp"
#include "io/exif.hpp"
#include "io/plan_io.hpp"
#include "io/write_artifacts.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/photos.hpp"
#include "usecases/plan_outputs.hpp"
#include "usecases/refly.hpp"

namespace uavcover::cli {
namespace {

struct ReflyArgs {
  std::string plan_dir;
  std::string flown;
  std::string photos;
  std::optional<double> takeoff_alt_m;
  std::string out;
  std::vector<std::string> uavs;
  std::optional<std::uint64_t> seed;
  bool no_images = false;
};

void run_refly(const ReflyArgs& a) {
  const bool quiet = global_flags().quiet;
  const Progress bar = make_progress_bar(quiet);
  const Context ctx(bar, interrupt_token());
  const Plan flown_plan = io::load_plan_dir(a.plan_dir);
  std::vector<flight::Track> tracks;
  std::vector<io::PhotoTags> photos;
  if (!a.photos.empty())
    photos = io::read_photo_folder(a.photos, "--photos");
  else
    tracks = usecases::parse_flight_log(io::read_text_file(a.flown, "--flown"), "--flown");
  usecases::ReflyGaps gaps;
  Plan result;
  usecases::PlanOutputs outputs;
  std::vector<std::filesystem::path> files;
  try {
    if (!a.photos.empty()) {
      usecases::PhotoOptions po;
      po.takeoff_altitude_m = a.takeoff_alt_m;
      gaps = usecases::photo_coverage(flown_plan, photos, po, ctx).gaps;
    } else {
      gaps = usecases::coverage_gaps(flown_plan, tracks, ctx);
    }
    const Mission mission = usecases::refly_mission(flown_plan, gaps, a.uavs);
    PlanOptions opt;
    opt.seed = a.seed;
    result = plan(mission, opt, ctx);
    usecases::OutputOptions oo;
    oo.images = !a.no_images;
    outputs = usecases::plan_outputs(result, oo, ctx);
    files = io::write_artifacts(a.out, outputs.artifacts, ctx);
  } catch (...) {
    finish_progress_bar();
    throw;
  }
  finish_progress_bar();
  for (const auto& w : outputs.warnings) std::cerr << "uavcover: warning: " << w << "\n";
  if (quiet) return;
  std::cout << fmt::format(
      "{} coverage {:.2f} % (plan {:.2f} %); {} gap(s), {:.0f} m^2, refly with {} UAV(s): coverage of the "
      "gaps {:.2f} %, flight time {:.1f} min; wrote {} files to {}\n",
      a.photos.empty() ? "flown" : "photo", gaps.flown_poc * 100, gaps.planned_poc * 100, gaps.local.size(),
      gaps.area_m2, result.uavs.size(), outputs.poc * 100, outputs.flight_time_min, files.size(), a.out);
}

const bool registered = CommandRegistry::add(15, [](CLI::App& app) {
  auto args = std::make_shared<ReflyArgs>();
  auto* cmd =
      app.add_subcommand("refly", "Plan what a flight did not scan: the gaps as a new plan of the mission");
  cmd->add_option("PLAN_DIR", args->plan_dir, "The plan that was flown (a `plan` output folder)")
      ->required()
      ->check(CLI::ExistingDirectory);
  auto* flown =
      cmd->add_option("--flown", args->flown,
                      "The flight's log: GET /api/v1/flights/{id}/log.geojson or log.csv (telemetry "
                      "per UAV)");
  auto* photos =
      cmd->add_option("--photos", args->photos,
                      "Instead of a log: the flight's geotagged photos (a folder of JPEGs); the gaps "
                      "are what no photo's footprint saw (docs/photos.md)")
          ->check(CLI::ExistingDirectory);
  flown->excludes(photos);
  cmd->add_option("--takeoff-alt-m", args->takeoff_alt_m,
                  "With --photos: the take-off's height above sea level, for photos with a GPS altitude only")
      ->check(number_in(-1000, 10000))
      ->needs(photos);
  cmd->add_option("--out,-o", args->out, "Output folder of the refly plan")
      ->required()
      ->check(output_folder());
  cmd->add_option("--uav", args->uavs, "A UAV that flies the refly (repeatable; default: all of the plan's)");
  cmd->add_option("--seed", args->seed, "Random seed (overrides the mission's)")
      ->check(integer_in<std::uint64_t>(0, std::numeric_limits<std::uint64_t>::max()));
  cmd->add_flag("--no-images", args->no_images, "Skip plan.png, plan.svg, heatmap.png, histogram.png");
  cmd->footer(
      "The gaps: the free area's lattice samples no track scanned (the plan's coverage simulation, each\n"
      "UAV's footprint, in the coverage band of the mission's altitude), slivers under an eighth of the\n"
      "spacing left out, grown by half the spacing and clipped to the free area (docs/refly.md).\n"
      "Exit codes: 0 ok, 1 internal error, 2 bad input (names the field), 130 interrupted.");
  cmd->callback([args] {
    if (args->flown.empty() && args->photos.empty())
      throw InputError("--flown", "give what the flight scanned: --flown LOG or --photos DIR");
    run_refly(*args);
  });
});

}  // namespace
}  // namespace uavcover::cli
