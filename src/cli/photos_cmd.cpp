// `uavcover photos DIR --plan PLAN_DIR --out OUT` (issue 32, docs/photos.md): what the photos really saw.
#include <fmt/format.h>

#include <iostream>

#include "cli/command.hpp"
#include "cli/interrupt.hpp"
#include "cli/progress.hpp"
#include "cli/validators.hpp"
#include "io/exif.hpp"
#include "io/plan_io.hpp"
#include "io/write_artifacts.hpp"
#include "usecases/photos.hpp"

namespace uavcover::cli {
namespace {

struct PhotosArgs {
  std::string dir;
  std::string plan_dir;
  std::string out;
  std::optional<double> takeoff_alt_m;
};

void run_photos(const PhotosArgs& a) {
  const bool quiet = global_flags().quiet;
  const Progress bar = make_progress_bar(quiet);
  const Context ctx(bar, interrupt_token());
  const Plan plan = io::load_plan_dir(a.plan_dir);
  const auto tags = io::read_photo_folder(a.dir, "DIR");
  usecases::PhotoOptions po;
  po.takeoff_altitude_m = a.takeoff_alt_m;
  usecases::PhotoCoverage c;
  std::vector<std::filesystem::path> files;
  try {
    c = usecases::photo_coverage(plan, tags, po, ctx);
    std::vector<Artifact> artifacts;
    artifacts.push_back({"photos.geojson", "application/geo+json", usecases::photos_geojson(c)});
    artifacts.push_back({"photos.json", "application/json", usecases::photo_summary(c).dump(1) + "\n"});
    artifacts.push_back(c.overlay);
    files = io::write_artifacts(a.out, artifacts, ctx);
  } catch (...) {
    finish_progress_bar();
    throw;
  }
  finish_progress_bar();
  for (const auto& s : c.skipped) std::cerr << "uavcover: warning: skipped " << s << "\n";
  if (quiet) return;
  std::cout << fmt::format(
      "{} photo(s): coverage {:.2f} % of the free area (seen twice {:.2f} %; the plan {:.2f} %); {} gap(s), "
      "{:.0f} m^2; wrote {} files to {}\n",
      c.photos.size(), c.poc * 100, c.pooc * 100, c.planned_poc * 100, c.gaps.local.size(), c.gaps.area_m2,
      files.size(), a.out);
}

const bool registered = CommandRegistry::add(16, [](CLI::App& app) {
  auto args = std::make_shared<PhotosArgs>();
  auto* cmd = app.add_subcommand(
      "photos", "What a flight's photos saw: footprints from their geotags, the coverage map and the gaps");
  cmd->add_option("DIR", args->dir, "A folder of geotagged JPEGs (EXIF GPS; DJI XMP altitude and gimbal)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--plan", args->plan_dir, "The plan that was flown (a `plan` output folder)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out,-o", args->out, "Output folder: photos.geojson, photos.json, photo-coverage.png")
      ->required()
      ->check(output_folder());
  cmd->add_option("--takeoff-alt-m", args->takeoff_alt_m,
                  "The take-off's height above sea level, for photos with a GPS altitude only")
      ->check(number_in(-1000, 10000));
  cmd->footer(
      "Each photo's footprint: the camera's frustum on flat ground (or the plan's DEM) from its height,\n"
      "gimbal pitch and yaw; the plan's lattice samples inside a footprint are seen. Refly what is left:\n"
      "`uavcover refly PLAN_DIR --photos DIR --out DIR2` (docs/photos.md).\n"
      "Exit codes: 0 ok, 1 internal error, 2 bad input (names the photo and tag), 130 interrupted.");
  cmd->callback([args] { run_photos(*args); });
});

}  // namespace
}  // namespace uavcover::cli
