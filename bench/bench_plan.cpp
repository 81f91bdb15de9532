// Benchmarks of the DARP planner.
//   bench_plan paper [strict|coverage] [dir|-] [seed]  the 20 regions of Apostolidis et al. 2022: PoC, turns,
//                                              length and time per region, means over the paper's 18
//   bench_plan scaling|scaling-hard [max_cells] mega-cells x UAVs -> time and peak RSS (one process per
//                                              row, so peak RSS is that row's)
//   bench_plan cancel                            stop latency of plan() at 0.5-7.5 s into a 100k-cell plan
//   bench_plan mission CELLS UAVS                the scaling field as a mission file (seeded random starts)
//   bench_plan gbench [google benchmark flags]  Google Benchmark timings (when built with it)
//   bench_plan nfz N [planner] [uavs]            a 2 km field with a lattice of N small (2 m) no-fly zones
//                                              (ds 40 m): parse and plan times
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stop_token>
#include <string>
#include <vector>

#include "engine/local_mission.hpp"
#include "evaluation/coverage.hpp"
#include "uavcover/uavcover.hpp"

#ifdef UAVCOVER_HAVE_GBENCH
#include <benchmark/benchmark.h>
#endif

using namespace uavcover;

namespace {

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// paper_results.csv: "J1 + J2 + J3 Optimization" rows
std::vector<double> paper_row(const std::string& dir, const std::string& metric) {
  std::ifstream f(dir + "/paper_results.csv");
  std::string line;
  while (std::getline(f, line)) {
    if (line.rfind("\"J1 + J2 + J3 Optimization\",\"" + metric + "\"", 0) != 0) continue;
    std::vector<double> v;
    std::stringstream ss(line);
    std::string cell;
    int col = 0;
    while (std::getline(ss, cell, ',')) {
      if (col++ >= 2) v.push_back(std::atof(cell.c_str()));
    }
    return v;
  }
  return {};
}

int paper(Mode mode, const std::string& dir, std::uint64_t seed) {
  const auto ppoc = paper_row(dir, "PoC"), pturns = paper_row(dir, "# WP (turns)"),
             plen = paper_row(dir, "Path Length (m)");
  std::printf("mode %s\n%-5s %7s %7s %6s %6s %9s %9s %7s %5s\n", mode == Mode::Strict ? "strict" : "coverage",
              "roi", "PoC%", "paper", "turns", "paper", "length", "paper", "time_s", "cells");
  double s_poc = 0, s_turns = 0, s_len = 0, s_t = 0, max_t = 0;
  int n = 0, worse = 0;
  for (int r = 1; r <= 20; ++r) {
    char name[64];
    std::snprintf(name, sizeof name, "/roi%02d.json", r);
    Mission m;
    try {
      m = parse_mission(slurp(dir + name));
    } catch (const std::exception& e) {
      std::printf("%-5d skipped: %s\n", r, e.what());
      continue;
    }
    m.mode = mode;
    m.seed = seed;
    const auto t0 = std::chrono::steady_clock::now();
    const Plan p = plan(m);
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const engine::LocalMission lm = engine::to_local(p.mission);
    std::vector<evaluation::Flight> flights;
    for (const auto& u : p.uavs) flights.push_back(u.parts);
    evaluation::CoverageOptions co;
    co.footprint_m = 1.5 * m.spacing_m;
    co.lattice_m = 1.0;
    const auto cov = evaluation::evaluate_coverage(lm.free, flights, co);
    int turns = 0, cells = 0;
    double len = 0;
    for (const auto& u : p.uavs)
      turns += u.turns, len += u.coverage_length_m, cells += u.diagnostics.value("cells", 0);
    const bool counted = r != 6 && r != 18;
    const double pp = r - 1 < static_cast<int>(ppoc.size()) ? ppoc[r - 1] * 100 : NAN;
    const double pt = r - 1 < static_cast<int>(pturns.size()) ? pturns[r - 1] : NAN;
    const double pl = r - 1 < static_cast<int>(plen.size()) ? plen[r - 1] : NAN;
    const bool w = mode == Mode::Strict && cov.total.poc * 100 < pp - 1e-9;
    std::printf("%-5d %7.2f %7.2f %6d %6.0f %9.0f %9.0f %7.3f %5d%s%s\n", r, cov.total.poc * 100, pp, turns,
                pt, len, pl, t, cells, counted ? "" : "  (not averaged)", w && counted ? "  lower PoC" : "");
    if (counted) {
      s_poc += cov.total.poc * 100, s_turns += turns, s_len += len, s_t += t, ++n;
      if (w) ++worse;
    }
    max_t = std::max(max_t, t);
  }
  std::printf(
      "mean over %d regions: PoC %.2f %%  turns %.2f  length %.3f km  time %.3f s (max %.3f s)  "
      "PoC below the paper on %d\n",
      n, s_poc / n, s_turns / n, s_len / n / 1000, s_t / n, max_t, worse);
  return 0;
}

/// A square field of about `cells` mega-cells (ds = 10 m) with two no-fly zones, `uavs` UAVs.
Mission synthetic(long cells, int uavs, bool hard = false) {
  Mission m;
  m.name = "scaling";
  m.spacing_m = 10.0;
  const double side_m = std::sqrt(static_cast<double>(cells)) * 20.0 * 1.02;
  const double lat0 = 45.0, lon0 = 9.0;
  const double dlat = side_m / 111320.0, dlon = side_m / (111320.0 * std::cos(lat0 * M_PI / 180));
  auto rect = [&](double a, double b, double c, double d) {  // fractions of the side
    GeoRing ring{{lon0 + a * dlon, lat0 + b * dlat},
                 {lon0 + c * dlon, lat0 + b * dlat},
                 {lon0 + c * dlon, lat0 + d * dlat},
                 {lon0 + a * dlon, lat0 + d * dlat},
                 {lon0 + a * dlon, lat0 + b * dlat}};
    return GeoPolygon{ring};
  };
  m.area.push_back(rect(0, 0, 1, 1));
  m.no_fly_zones.push_back(rect(0.3, 0.3, 0.35, 0.4));
  m.no_fly_zones.push_back(rect(0.6, 0.55, 0.7, 0.62));
  // hard: unequal shares 1..n and scattered starts (a fixed pseudo-random pattern)
  std::uint64_t h = 88172645463325252ULL;
  auto next = [&] {
    h ^= h << 13, h ^= h >> 7, h ^= h << 17;
    return static_cast<double>(h % 1000003) / 1000003.0;
  };
  for (int i = 0; i < uavs; ++i) {
    Uav u;
    u.id = "uav" + std::to_string(i);
    u.share = hard ? 2.0 * (i + 1) / (uavs * (uavs + 1.0)) : 1.0 / uavs;
    const double f = (i + 0.5) / uavs;
    u.start = hard ? LonLat{lon0 + (0.05 + 0.9 * next()) * dlon, lat0 + (0.05 + 0.9 * next()) * dlat}
                   : LonLat{lon0 + f * dlon, lat0 + (i % 2 ? 0.1 : 0.9) * dlat};
    m.uavs.push_back(u);
  }
  m.seed = 7;
  return m;
}

/// Stop latency: plans the ~100k mega-cell field with 20 UAVs, requests a stop after 0.5, 3, 6 and 7.5 s
/// (placement, division, STC) and reports how long plan() takes to return (Cancelled) after the request.
int cancel_latency() {
  std::printf("%10s %12s %14s\n", "stop_at_s", "stage", "latency_ms");
  for (double at : {0.5, 3.0, 6.0, 7.5}) {
    const Mission m = synthetic(100000, 20);
    std::stop_source stop;
    std::string stage;
    const auto t0 = std::chrono::steady_clock::now();
    std::chrono::steady_clock::time_point asked{};
    const Context ctx(
        [&](std::string_view s, double) {
          stage = std::string(s);
          if (!stop.stop_requested() &&
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >= at) {
            asked = std::chrono::steady_clock::now();
            stop.request_stop();
          }
        },
        stop.get_token());
    try {
      (void)plan(m, {}, ctx);
      std::printf("%10.1f %12s %14s\n", at, "finished", "-");
    } catch (const Cancelled&) {
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - asked).count();
      std::printf("%10.1f %12s %14.1f\n", at, stage.c_str(), ms);
    }
    std::fflush(stdout);
  }
  return 0;
}

/// A 2 km square field with a k x k lattice (k = ceil(sqrt(n))) of 2 m square no-fly zones, ds 40 m.
Mission nfz_lattice(int n, const std::string& planner, int uavs) {
  Mission m;
  m.name = "nfz-lattice";
  m.planner = planner;
  m.spacing_m = 40.0;
  const double side_m = 2000.0, lat0 = 45.0, lon0 = 9.0;
  const double mlat = 1.0 / 111320.0, mlon = 1.0 / (111320.0 * std::cos(lat0 * M_PI / 180));
  auto rect = [&](double x0, double y0, double x1, double y1) {  // metres east/north of the corner
    GeoRing ring{{lon0 + x0 * mlon, lat0 + y0 * mlat},
                 {lon0 + x1 * mlon, lat0 + y0 * mlat},
                 {lon0 + x1 * mlon, lat0 + y1 * mlat},
                 {lon0 + x0 * mlon, lat0 + y1 * mlat},
                 {lon0 + x0 * mlon, lat0 + y0 * mlat}};
    return GeoPolygon{ring};
  };
  m.area.push_back(rect(0, 0, side_m, side_m));
  const int k = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  const double pitch = side_m / k;
  for (int i = 0, placed = 0; i < k && placed < n; ++i)
    for (int j = 0; j < k && placed < n; ++j, ++placed) {
      const double cx = (i + 0.5) * pitch, cy = (j + 0.5) * pitch;
      m.no_fly_zones.push_back(rect(cx - 1, cy - 1, cx + 1, cy + 1));
    }
  for (int i = 0; i < uavs; ++i) {
    Uav u;
    u.id = "uav" + std::to_string(i);
    u.share = 1.0 / uavs;
    u.start = LonLat{lon0 + (0.5 + i * pitch) * mlon, lat0 + 0.5 * mlat};
    m.uavs.push_back(u);
  }
  m.seed = 1;
  return m;
}

int nfz(int n, const std::string& planner, int uavs) {
  const auto t0 = std::chrono::steady_clock::now();
  const Mission m = parse_mission(mission_to_json(nfz_lattice(n, planner, uavs)));
  const auto t1 = std::chrono::steady_clock::now();
  const Plan p = plan(m);
  const auto t2 = std::chrono::steady_clock::now();
  std::size_t transit = 0, vertices = 0;
  for (const auto& u : p.uavs)
    for (const auto& part : u.parts) {
      vertices += part.local.size();
      if (part.kind == PartKind::Transit) ++transit;
    }
  std::printf("nfz %d planner %s uavs %d: parse %.2f s, plan %.2f s, %zu transit legs, %zu vertices\n", n,
              planner.c_str(), uavs, std::chrono::duration<double>(t1 - t0).count(),
              std::chrono::duration<double>(t2 - t1).count(), transit, vertices);
  return 0;
}

int scaling(long max_cells, bool hard) {
  std::printf("%s\n%10s %5s %9s %10s %9s %5s %9s\n",
              hard ? "unequal shares 1..n, scattered starts" : "equal shares, starts along two edges",
              "megacells", "uavs", "time_s", "peak_MiB", "converged", "iters", "max_dev");
  for (long cells : {1000L, 10000L, 100000L, 300000L}) {
    if (cells > max_cells) break;
    for (int uavs : {1, 5, 20}) {
      std::fflush(stdout);
      const pid_t pid = fork();
      if (pid == 0) {
        const Mission m = synthetic(cells, uavs, hard);
        PlanOptions o;
        const auto t0 = std::chrono::steady_clock::now();
        const Plan p = plan(m, o);
        const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        rusage ru{};
        getrusage(RUSAGE_SELF, &ru);
        int free_cells = 0;
        for (const auto& u : p.uavs) free_cells += u.diagnostics.value("cells", 0);
        const bool converged = p.diagnostics.value("converged", true);
        const int iterations = p.diagnostics.value("iterations", 0);
        double dev = 0;
        for (const auto& u : p.uavs)
          dev = std::max(dev, std::fabs(u.share_actual - u.share_requested) * free_cells);
        std::printf("%10d %5d %9.2f %10.1f %9s %5d %9.0f\n", free_cells, uavs, t, ru.ru_maxrss / 1024.0,
                    converged ? "yes" : "no", iterations, dev);
        if (!converged) {
          std::printf("           cells - target per UAV:");
          for (const auto& u : p.uavs)
            std::printf(" %+.0f", (u.share_actual - u.share_requested) * free_cells);
          std::printf("\n");
        }
        std::fflush(stdout);
        _exit(0);
      }
      int status = 0;
      waitpid(pid, &status, 0);
    }
  }
  return 0;
}

#ifdef UAVCOVER_HAVE_GBENCH
void BM_PaperRegion(benchmark::State& state) {
  char name[64];
  std::snprintf(name, sizeof name, "/apostolidis2022/roi%02d.json", static_cast<int>(state.range(0)));
  const Mission m = parse_mission(slurp(std::string(UAVCOVER_BENCH_DATA) + name));
  for (auto _ : state) benchmark::DoNotOptimize(plan(m));
}
BENCHMARK(BM_PaperRegion)->DenseRange(1, 20)->Unit(benchmark::kMillisecond);

void BM_Synthetic(benchmark::State& state) {
  const Mission m = synthetic(state.range(0), static_cast<int>(state.range(1)));
  for (auto _ : state) benchmark::DoNotOptimize(plan(m));
}
BENCHMARK(BM_Synthetic)->Args({2000, 1})->Args({2000, 4})->Args({10000, 10})->Unit(benchmark::kMillisecond);
#endif

}  // namespace

int main(int argc, char** argv) {
  const std::string cmd = argc > 1 ? argv[1] : "paper";
  try {
    if (cmd == "paper") {
      const Mode mode = argc > 2 && std::string(argv[2]) == "coverage" ? Mode::Coverage : Mode::Strict;
      const std::string dir = argc > 3 && std::string(argv[3]) != "-"
                                  ? argv[3]
                                  : std::string(UAVCOVER_BENCH_DATA) + "/apostolidis2022";
      return paper(mode, dir, argc > 4 ? std::strtoull(argv[4], nullptr, 10) : 0);
    }
    if (cmd == "mission" && argc > 3) {  // the synthetic field as a mission file, starts left to the seed
      Mission m = synthetic(std::atol(argv[2]), std::atoi(argv[3]));
      for (auto& u : m.uavs) u.start.reset();
      std::printf("%s\n", mission_to_json(m).c_str());
      return 0;
    }
    if (cmd == "cancel") return cancel_latency();
    if (cmd == "nfz" && argc > 2)
      return nfz(std::atoi(argv[2]), argc > 3 ? argv[3] : "darp", argc > 4 ? std::atoi(argv[4]) : 3);
    if (cmd == "scaling" || cmd == "scaling-hard")
      return scaling(argc > 2 ? std::atol(argv[2]) : 100000L, cmd == "scaling-hard");
#ifdef UAVCOVER_HAVE_GBENCH
    if (cmd == "gbench") {
      --argc, ++argv;
      benchmark::Initialize(&argc, argv);
      benchmark::RunSpecifiedBenchmarks();
      return 0;
    }
#endif
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  std::fprintf(stderr,
               "usage: bench_plan paper [strict|coverage] [dir|-] [seed] | scaling|scaling-hard [max_cells] "
               "| mission CELLS UAVS | cancel | nfz N [planner] [uavs] | gbench\n");
  return 2;
}
