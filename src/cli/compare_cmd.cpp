// `uavcover compare MISSION.json --planners darp,boustrophedon [--out DIR]`: one mission, several
// planners, one evaluator; a side-by-side table (compare.json, compare.md) and picture (compare.png).
#include <iostream>

#include "cli/command.hpp"
#include "cli/cost_options.hpp"
#include "cli/interrupt.hpp"
#include "cli/mission_file.hpp"
#include "cli/progress.hpp"
#include "io/plan_io.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/compare.hpp"

namespace uavcover::cli {
namespace {

struct CompareArgs {
  std::string mission;
  std::vector<std::string> planners;
  std::string out = ".";
  double footprint_m = 0.0;
  double lattice_m = 0.0;
  bool no_images = false;
  evaluation::CostOptions cost;
};

void run_compare(const CompareArgs& a) {
  const Mission mission = read_mission(a.mission);
  usecases::CompareOptions co;
  co.planners = a.planners;
  co.evaluation.coverage.footprint_m = a.footprint_m;
  co.evaluation.coverage.lattice_m = a.lattice_m;
  co.evaluation.cost = a.cost;
  const bool quiet = global_flags().quiet;
  const auto result =
      with_progress(quiet, [&](const Context& ctx) { return usecases::compare(mission, co, ctx); });
  const auto files = io::write_artifacts(a.out, usecases::compare_outputs(result, !a.no_images));
  if (quiet) return;
  std::cout << usecases::compare_markdown(result);
  std::cout << "wrote " << files.size() << " file(s) to " << a.out << "\n";
}

const bool registered = CommandRegistry::add(25, [](CLI::App& app) {
  auto a = std::make_shared<CompareArgs>();
  auto* cmd = app.add_subcommand(
      "compare", "Plan one mission with several planners and compare them with the same evaluator");
  cmd->add_option("MISSION", a->mission, "Mission file")->required();
  cmd->add_option("--planners", a->planners, "Planners, comma-separated (default: every planner)")
      ->delimiter(',');
  cmd->add_option("--out,-o", a->out, "Output folder for compare.json, compare.md, compare.png")
      ->capture_default_str();
  cmd->add_option("--footprint", a->footprint_m,
                  "Footprint width w in metres (default: camera, else 1.5 x spacing)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--lattice", a->lattice_m, "Sample spacing in metres (default: adaptive, 0.5-2 m)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--no-images", a->no_images, "Do not write compare.png");
  add_cost_options(cmd, a->cost);
  cmd->footer("Exit codes: 0 ok, 1 internal error, 2 bad input, 130 interrupted.");
  cmd->callback([a] { run_compare(*a); });
});

const bool registered_list = CommandRegistry::add(26, [](CLI::App& app) {
  auto* cmd = app.add_subcommand("planners", "List the planners with their parameters (JSON with --json)");
  auto json_out = std::make_shared<bool>(false);
  cmd->add_flag("--json", *json_out, "Print the planners' schemas as JSON");
  cmd->callback([json_out] {
    nlohmann::json all = nlohmann::json::array();
    for (const auto& p : available_planners()) {
      if (*json_out) {
        all.push_back(p.schema);
        continue;
      }
      std::cout << p.name << " — " << p.summary << "\n";
      for (const auto& prm : p.schema.at("params"))
        std::cout << "    planner_params." << prm.at("name").get<std::string>() << " ("
                  << prm.at("type").get<std::string>() << ", default " << prm.at("default").dump()
                  << "): " << prm.at("description").get<std::string>() << "\n";
      // capabilities (docs/patterns.md): what the engine refuses for this planner
      std::string yes, no;
      for (const auto& [k, v] : p.schema.at("supports").items()) (v.get<bool>() ? yes : no) += " " + k;
      std::cout << "    supports:" << (yes.empty() ? " -" : yes) << "\n";
      if (!no.empty()) std::cout << "    not supported:" << no << "\n";
    }
    if (*json_out)
      std::cout << all.dump(1) << "\n";
    else
      std::cout << "auto — \"planner\": \"auto\": plans with every planner above that supports the mission "
                   "(time limit shared), keeps the best by \"objective\" (time | poc | turns | length) among "
                   "those within 0.5 PoC points of the best (docs/planners.md)\n";
  });
});

}  // namespace
}  // namespace uavcover::cli
