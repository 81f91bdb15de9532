// The MILP sweep planner (Hong et al. 2021) at the paper's sizes and beyond, against the boustrophedon
// planner's split of the same problem.
//   bench_milp [time_limit_s [model]]   (per MILP; default 10 s; model exact|contracted|auto, default auto)
//   bench_milp stop [model delay_s]      stop latency: a 400 m x 200 m field at 5 m (40 segments), 3 UAVs in
//                                        one MILP, exact and contracted, a stop requested 0.2-3 s in
// Scenarios (local metres, spacing as given):
//   4 lines    : 4 lines (8 waypoints) and 2 depots, 2 UAVs (where `model: auto` keeps the exact model)
//   pentagon   : 8 lines (16 waypoints) and 3 depots = the paper's 19 nodes, 3 UAVs (paper: 0.80 s Gurobi)
//   three-areas: 13 segments in 3 polygons (26 waypoints) and 2 depots = 28 nodes, 2 UAVs (paper: 4.61 s)
//   rect-200-5 : 200 segments, 5 UAVs; rect-1000-10: 1000 segments, 10 UAVs (clustered by share)
// Distances: each UAV's start -> its coverage legs in order -> start, straight transits (no no-fly
// zones here), the same measure for both planners.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <thread>
#include <vector>

#include "geometry/geometry.hpp"
#include "planners/planner.hpp"
#include "uavcover/error.hpp"

using namespace uavcover;
using namespace uavcover::planners;

namespace {

Polygon poly(std::vector<Point> pts) {
  Polygon p;
  for (const auto& q : pts) bg::append(p.outer(), q);
  bg::append(p.outer(), pts.front());
  bg::correct(p);
  return p;
}

Problem problem(const MultiPolygon& area, std::vector<Point> starts, double spacing) {
  Problem p;
  p.area = geometry::unite(area);
  p.free = p.area;
  p.starts = std::move(starts);
  p.shares.assign(p.starts.size(), 1.0 / static_cast<double>(p.starts.size()));
  p.uavs.resize(p.starts.size());
  p.spacing_m = spacing;
  p.footprint_m = 1.5 * spacing;
  return p;
}

std::pair<double, double> max_mean_distance(const Problem& p, const Assignment& a) {
  double mx = 0.0, sum = 0.0;
  for (std::size_t k = 0; k < a.uavs.size(); ++k) {
    Point here = p.starts[k];
    double d = 0.0;
    for (const auto& part : a.uavs[k].coverage) {
      if (part.empty()) continue;
      d += bg::distance(here, part.front()) + geometry::length(part);
      here = part.back();
    }
    d += bg::distance(here, p.starts[k]);
    mx = std::max(mx, d);
    sum += d;
  }
  return {mx, sum / static_cast<double>(a.uavs.size())};
}

struct Scenario {
  std::string name;
  Problem problem;
  nlohmann::json params;
};

/// Seconds from a stop request (after `delay` s) to Cancelled, or -1 when the plan ended first.
double stop_latency(const PlannerInfo& milp, const Problem& p, const nlohmann::json& params, double delay) {
  std::stop_source stop;
  std::chrono::steady_clock::time_point asked{};
  std::jthread timer([&](std::stop_token own) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(delay);
    while (!own.stop_requested() && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (own.stop_requested()) return;
    asked = std::chrono::steady_clock::now();
    stop.request_stop();
  });
  try {
    (void)milp.create()->plan(p, params, Context([](std::string_view, double) {}, stop.get_token()));
  } catch (const Cancelled&) {
    const auto now = std::chrono::steady_clock::now();
    timer.join();
    return std::chrono::duration<double>(now - asked).count();
  }
  timer.request_stop();
  return -1.0;
}

int stop_bench(const PlannerInfo& milp, const std::vector<std::string>& models,
               const std::vector<double>& delays) {
  MultiPolygon a;
  a.push_back(poly({{0, 0}, {400, 0}, {400, 200}, {0, 200}}));
  const Problem p = problem(a, {{-20, 0}, {-20, 100}, {-20, 200}}, 5.0);
  std::printf("| model | stop after s | latency s |\n|---|---:|---:|\n");
  for (const std::string& model : models)
    for (double delay : delays) {
      const nlohmann::json params = validate_params(milp, {{"max_segments", 60},
                                                           {"max_uavs_per_milp", 3},
                                                           {"node_limit", 10000000},
                                                           {"time_limit_s", 60},
                                                           {"model", model}});
      const double l = stop_latency(milp, p, params, delay);
      std::printf("| %s | %.1f | %s |\n", model.c_str(), delay,
                  l < 0 ? "finished first" : std::to_string(l).substr(0, 5).c_str());
      std::fflush(stdout);
    }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "stop") {
    const PlannerInfo* m = find("milp");
    if (!m) return 1;
    if (argc > 3) return stop_bench(*m, {argv[2]}, {std::atof(argv[3])});
    return stop_bench(*m, {"exact", "contracted"}, {0.2, 0.5, 1.0, 2.0, 3.0});
  }
  const double limit = argc > 1 ? std::atof(argv[1]) : 10.0;
  const std::string model = argc > 2 ? argv[2] : "auto";
  std::vector<Scenario> sc;
  // the paper's sizes in one joint MILP (all UAVs, every segment), searched up to the time limit
  const nlohmann::json paper = {{"max_uavs_per_milp", 10},
                                {"max_segments", 60},
                                {"node_limit", 10000000},
                                {"time_limit_s", limit},
                                {"model", model}};
  // large ones clustered by share (the default), each cluster's MILP searched up to the time limit
  const nlohmann::json large = {{"node_limit", 10000000}, {"time_limit_s", limit}, {"model", model}};
  const nlohmann::json defaults = {{"model", model}};
  {
    MultiPolygon a;
    a.push_back(poly({{0, 0}, {60, 0}, {60, 20}, {0, 20}}));
    sc.push_back({"4 lines (10 nodes, 2 UAVs)", problem(a, {{-5, 0}, {-5, 20}}, 5.0), paper});
  }
  {
    MultiPolygon a;
    a.push_back(poly({{10, -16}, {40, -20}, {48, 4}, {32, 17}, {8, 10}}));
    sc.push_back({"pentagon (19 nodes, 3 UAVs)", problem(a, {{0, 0}, {0, 5}, {0, -5}}, 5.0), paper});
  }
  {
    MultiPolygon a;
    a.push_back(poly({{10, 10}, {40, 10}, {40, 30}, {10, 30}}));
    a.push_back(poly({{50, 0}, {75, 0}, {75, 20}, {50, 20}}));
    a.push_back(poly({{20, 45}, {75, 45}, {47, 70}}));
    sc.push_back({"three areas (28 nodes, 2 UAVs)", problem(a, {{30, -5}, {35, -5}}, 5.0), paper});
  }
  {
    MultiPolygon a;
    a.push_back(poly({{0, 0}, {4000, 0}, {4000, 2000}, {0, 2000}}));
    std::vector<Point> s5, s10;
    for (int k = 0; k < 5; ++k) s5.push_back({-50.0, 200.0 + 400.0 * k});
    for (int k = 0; k < 10; ++k) s10.push_back({-50.0, 100.0 + 200.0 * k});
    sc.push_back({"200 segments, 5 UAVs (defaults)", problem(a, s5, 10.0), defaults});
    sc.push_back({"200 segments, 5 UAVs", problem(a, s5, 10.0), large});
    sc.push_back({"1000 segments, 10 UAVs (defaults)", problem(a, s10, 2.0), defaults});
    sc.push_back({"1000 segments, 10 UAVs", problem(a, s10, 2.0), large});
  }
  const PlannerInfo* milp = find("milp");
  const PlannerInfo* boustro = find("boustrophedon");
  if (!milp || !boustro) {
    std::fprintf(stderr, "milp or boustrophedon planner not built in\n");
    return 1;
  }
  std::printf(
      "| scenario | model | segments | clusters | MILP nodes / binaries (largest) | optimal | time s | CPU s "
      "| "
      "first CBC incumbent s | max gap | max / mean distance m | boustrophedon max / mean m | "
      "boustrophedon time s |\n|---|---|---:|---:|---|---|---:|---:|---:|---:|---|---|---:|\n");
  if (const char* only = std::getenv("BENCH_MILP_ONLY"))
    sc.resize(std::min<std::size_t>(sc.size(), std::atoi(only)));
  for (const auto& s : sc) {
    const nlohmann::json params = validate_params(*milp, s.params);
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    const Assignment a = milp->create()->plan(s.problem, params, Context{});
    const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto t1 = std::chrono::steady_clock::now();
    const Assignment b = boustro->create()->plan(s.problem, validate_params(*boustro, nullptr), Context{});
    const double tb = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    const auto [amax, amean] = max_mean_distance(s.problem, a);
    const auto [bmax, bmean] = max_mean_distance(s.problem, b);
    int nodes = 0, bins = 0;
    double first = -1.0;
    for (const auto& c : a.diagnostics["clusters"]) {
      if (c["nodes"].get<int>() > nodes) nodes = c["nodes"].get<int>(), bins = c["binaries"].get<int>();
      if (!c["incumbent_is_warm_start"].get<bool>())
        first = std::max(first, c["first_incumbent_s"].get<double>());
    }
    std::string models;
    for (const auto& c : a.diagnostics["clusters"])
      if (models.find(c["model"].get<std::string>()) == std::string::npos)
        models += (models.empty() ? "" : "+") + c["model"].get<std::string>();
    std::printf(
        "| %s | %s | %d | %zu | %d / %d | %s | %.2f | %.2f | %s | %.1f %% | %.0f / %.0f | %.0f / %.0f | %.2f "
        "|\n",
        s.name.c_str(), models.c_str(), a.diagnostics["segments"].get<int>(),
        a.diagnostics["clusters"].size(), nodes, bins,
        a.diagnostics["proven_optimal"].get<bool>() ? "yes" : "no", t, cpu,
        first >= 0 ? std::to_string(first).substr(0, 5).c_str() : "warm start",
        100.0 * a.diagnostics["max_gap"].get<double>(), amax, amean, bmax, bmean, tb);
    std::fflush(stdout);
    if (std::getenv("BENCH_MILP_DIAG")) std::fprintf(stderr, "%s\n", a.diagnostics.dump(1).c_str());
  }
  return 0;
}
