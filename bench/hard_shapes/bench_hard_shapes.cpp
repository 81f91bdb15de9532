// Every registered planner on the hard shapes of issue 26 (tests/support/hard_shapes.hpp, the same
// missions the planner property suite plans): per planner and shape the mission PoC (the evaluator's,
// as plan.json), each UAV's coverage of its own region (the smallest; the property suite asks >= 97 %),
// the regions' share of the free area (DARP's strict regions are its grid cells inside the area), the
// worst share deviation (a region's share of the regions against the requested share) and the planning
// time.
// Prints a Markdown table; bench/hard_shapes/run.sh writes it to bench/results/hard-shapes.md.
// usage: bench_hard_shapes [PLANNER...] [MISSION.json...]   (default: every registered planner, the
// fixtures; mission files replace the fixtures)
//        bench_hard_shapes --write-missions DIR   (the fixtures as DIR/<shape>.json; the folder must exist)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "evaluation/evaluate.hpp"
#include "planners/planner.hpp"
#include "support/hard_shapes.hpp"
#include "uavcover/uavcover.hpp"

using namespace uavcover;

int main(int argc, char** argv) {
  std::vector<std::string> names;
  std::vector<testing::HardShape> shapes = testing::hard_shapes();
  bool own_missions = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--write-missions" &&
        i + 1 < argc) {  // the fixtures as mission files, to plan or open in the app
      const std::string dir = argv[++i];
      for (const auto& shape : shapes) {
        std::ofstream out(dir + "/" + shape.name + ".json");
        out << shape.mission.dump(1) << '\n';
        if (!out) {
          std::fprintf(stderr, "cannot write %s/%s.json\n", dir.c_str(), shape.name.c_str());
          return 1;
        }
      }
      return 0;
    }
    if (a.size() > 5 && a.ends_with(".json")) {  // a mission file instead of the fixtures
      std::ifstream in(a);
      std::stringstream text;
      text << in.rdbuf();
      if (!own_missions) shapes.clear();
      own_missions = true;
      shapes.push_back({a, nlohmann::json::parse(text.str())});
    } else {
      names.push_back(a);
    }
  }
  if (names.empty())
    for (const auto& p : planners::registry()) names.push_back(p.name);
  std::printf(
      "| planner | shape | UAVs | mission PoC %% | own region, min %% | regions / free area %% | worst share "
      "deviation (points) | plan s |\n");
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|\n");
  for (const auto& name : names)
    for (const auto& shape : shapes) {
      nlohmann::json j = shape.mission;
      j["planner"] = name;
      try {
        const Mission m = parse_mission(j.dump());
        const auto t0 = std::chrono::steady_clock::now();
        const Plan p = plan(m);
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const evaluation::Evaluation ev = evaluation::evaluate_plan(p);
        const std::vector<double> own = testing::own_region_coverage(p);
        std::printf(
            "| %s | %s | %zu | %.2f | %.2f | %.1f | %.1f | %.2f |\n", name.c_str(), shape.name.c_str(),
            p.uavs.size(), 100.0 * ev.coverage.total.poc, 100.0 * *std::min_element(own.begin(), own.end()),
            100.0 * testing::regions_over_free_area(p), 100.0 * testing::worst_share_deviation(p), secs);
      } catch (const std::exception& e) {
        std::printf("| %s | %s | | X | X | X | X | %s |\n", name.c_str(), shape.name.c_str(), e.what());
      }
      std::fflush(stdout);
    }
  return 0;
}
