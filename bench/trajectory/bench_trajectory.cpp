// The two trajectory methods on one plan (docs/trajectory.md, issue 33): per UAV and method the flight
// time, the largest |v|, |a| and jerk and the length, measured on samples (trajectory::measure), the build
// time and the size of the trajectory export's file (fillet-lines: the segment form; polynomial: sampled
// every 0.1 s, its only form). Markdown on stdout.
//   bench_trajectory PLAN_DIR [ORDER]   (PLAN_DIR written by `uavcover plan`; ORDER 5 by default)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "io/plan_io.hpp"
#include "trajectory/trajectory.hpp"

using namespace uavcover;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_trajectory PLAN_DIR [ORDER]\n");
    return 2;
  }
  const Plan plan = io::load_plan_dir(argv[1]);
  const int order = argc > 2 ? std::atoi(argv[2]) : 5;
  std::printf(
      "| UAV | method | waypoints | flight time s | length m | max \\|v\\| m/s | max \\|a\\| m/s² | "
      "max jerk m/s³ | sampled every s | build s | file MB |\n"
      "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
    if (plan.uavs[i].parts.empty()) continue;
    for (const auto method : {trajectory::Method::FilletLines, trajectory::Method::Polynomial}) {
      trajectory::Options o;
      o.method = method;
      o.order = order;
      const auto t0 = std::chrono::steady_clock::now();
      const auto t = trajectory::uav_trajectory(plan, i, o);
      const double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double dt = std::max(0.01, t.duration() / 1.9e6);
      const auto m = trajectory::measure(t, dt);
      const std::string file = method == trajectory::Method::FilletLines
                                   ? trajectory::segments_csv(plan, t)
                                   : trajectory::trajectory_csv(plan, t.sample(0.1));
      std::string name = trajectory::method_name(method);
      double jerk = m.jerk_max;
      if (method == trajectory::Method::Polynomial) {
        jerk = t.report().jerk_max;
        const auto& r = t.report();
        name += " P" + std::to_string(order) + (r.hold ? "" : " (limits BROKEN)") + ", " +
                std::to_string(r.stretched) + " stretched, " + std::to_string(r.iterations) + " solves";
      }
      std::printf("| %s | %s | %zu | %.1f | %.1f | %.3f | %.3f | %.2f | %g | %.3f | %.3f |\n",
                  plan.uavs[i].id.c_str(), name.c_str(), t.waypoints().size(), m.duration_s, m.length_m,
                  m.speed_max, m.accel_max, jerk, dt, build, static_cast<double>(file.size()) / 1e6);
    }
  }
  return 0;
}
