// Quality of the boustrophedon planner on the 20 regions of Apostolidis et al. 2022 (1 UAV, ds 40 m),
// measured the paper's way: square footprint w = 60 m swept along every straight coverage leg (w/2
// past both ends) on a 1 m lattice. Means over the paper's 18 regions (all but 6 and 18).
//   bench_boustrophedon [dir] [angle_deg]
// Length = coverage parts + the straight inter-cell transit between them (an honest estimate of
// what is flown between cells; the legs from and back to the start are not counted).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "engine/local_mission.hpp"
#include "evaluation/evaluate.hpp"
#include "planners/planner.hpp"
#include "uavcover/uavcover.hpp"

using namespace uavcover;

namespace {

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

struct Row {
  double poc = 0, turns = 0, length = 0, time = 0, cells = 0;
};

int run(const std::string& dir, const nlohmann::json& params) {
  const auto* info = planners::find("boustrophedon");
  if (!info) {
    std::fprintf(stderr, "boustrophedon planner not built in\n");
    return 1;
  }
  const auto planner = info->create();
  const nlohmann::json valid = planners::validate_params(*info, params);
  for (Mode mode : {Mode::Coverage, Mode::Strict}) {
    std::printf("\nmode %s\n%-5s %8s %6s %9s %7s %5s\n", mode == Mode::Strict ? "strict" : "coverage", "roi",
                "PoC%", "turns", "length_km", "time_s", "cells");
    Row sum;
    int n = 0;
    for (int r = 1; r <= 20; ++r) {
      char name[64];
      std::snprintf(name, sizeof name, "/roi%02d.json", r);
      Mission m = parse_mission(slurp(dir + name));
      m.mode = mode;
      const engine::LocalMission lm = engine::to_local(m);
      planners::Problem p;
      p.area = lm.area;
      p.no_fly = lm.no_fly;
      p.free = lm.free;
      Point start;
      bg::centroid(lm.free, start);
      if (m.uavs.at(0).start) start = lm.frame.to_local(*m.uavs[0].start);
      p.starts = {start};
      p.shares = {1.0};
      p.uavs = m.uavs;
      p.spacing_m = m.spacing_m;
      p.footprint_m = evaluation::footprint_for(m);
      p.mode = mode;
      const auto t0 = std::chrono::steady_clock::now();
      const planners::Assignment a = planner->plan(p, valid, Context{});
      const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

      evaluation::Flight flight;
      for (const auto& part : a.uavs[0].coverage) {
        if (!flight.empty())
          flight.push_back(PathPart{PartKind::Transit, {flight.back().local.back(), part.front()}, {}});
        flight.push_back(PathPart{PartKind::Coverage, part, {}});
      }
      evaluation::EvaluateOptions o;
      o.coverage.lattice_m = 1.0;
      const auto ev = evaluation::evaluate_flights(evaluation::free_area(m, lm.frame), {flight}, {m.uavs[0]},
                                                   evaluation::footprint_for(m), o);
      Row row{100 * ev.coverage.total.poc, static_cast<double>(ev.coverage.total.turns),
              ev.coverage.total.length_m / 1000, t, static_cast<double>(a.uavs[0].coverage.size())};
      std::printf("%-5d %8.2f %6.0f %9.3f %7.3f %5.0f%s\n", r, row.poc, row.turns, row.length, row.time,
                  row.cells, (r == 6 || r == 18) ? "  (not in the mean)" : "");
      if (r == 6 || r == 18) continue;
      sum.poc += row.poc, sum.turns += row.turns, sum.length += row.length, sum.time += row.time;
      sum.cells += row.cells;
      ++n;
    }
    std::printf("%-5s %8.2f %6.1f %9.3f %7.3f %5.1f   (targets: %s)\n", "mean", sum.poc / n, sum.turns / n,
                sum.length / n, sum.time / n, sum.cells / n,
                mode == Mode::Coverage ? "PoC >= 99.5, turns <= 100, length <= 34 km" : "PoC >= 98");
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string dir = argc > 1 ? argv[1] : std::string(UAVCOVER_BENCH_DATA) + "/apostolidis2022";
    nlohmann::json params = nlohmann::json::object();
    if (argc > 2) params["angle_deg"] = std::atof(argv[2]);
    return run(dir, params);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
