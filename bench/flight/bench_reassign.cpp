// Reassignment and flown coverage timings (docs/flights.md): every UAV of a mission failing after a
// third and after two thirds of its coverage waypoints, the others helping with full batteries; and the
// flown coverage of every UAV's whole flight sampled at 10 Hz.
//   bench_reassign [MISSION.json ...]   (default: examples/olive-grove.json and the paper's ROI 1 with 4
//   UAVs)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "flight/coverage.hpp"
#include "flight/reassign.hpp"
#include "geodesy/local_frame.hpp"
#include "sorties/sorties.hpp"
#include "uavcover/uavcover.hpp"

using namespace uavcover;

namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

template <class F>
double best_ms(F&& f, int repeats = 5) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    best = std::min(best,
                    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

/// Each UAV's flight as a vehicle reports it: a sample every 0.1 s at its speed, at the mission altitude
/// over coverage and at its transition altitude in transit.
std::vector<flight::Track> tracks_10hz(const Plan& p) {
  const geodesy::LocalFrame frame(p.origin);
  std::vector<flight::Track> out;
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    const double step = p.mission.uavs[i].speed_mps * 0.1;
    flight::Track t{p.uavs[i].id, {}};
    for (const auto& part : p.uavs[i].parts) {
      const double alt =
          part.kind == PartKind::Coverage ? p.mission.altitude_m : p.uavs[i].transition_altitude_m;
      for (std::size_t k = 1; k < part.local.size(); ++k) {
        const Point a = part.local[k - 1], b = part.local[k];
        const double len = bg::distance(a, b);
        for (double s = 0.0; s < len; s += step) {
          const LonLat g =
              frame.to_wgs84(Point(a.x() + s / len * (b.x() - a.x()), a.y() + s / len * (b.y() - a.y())));
          t.second.push_back({g.lon, g.lat, alt});
        }
      }
    }
    out.push_back(std::move(t));
  }
  return out;
}

void run(const std::string& name, const Mission& m) {
  const Plan p = plan(m);
  std::printf("\n%s: %zu UAVs, footprint %.1f m, plan %.2f s\n", name.c_str(), p.uavs.size(),
              evaluation::footprint_for(p.mission), p.compute_time_s);
  std::printf(
      "| failed UAV | waypoints | last reached | remainder m2 | remainder ms | reassign ms | helpers' "
      "waypoints | sorties |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (std::size_t i = 0; i < p.uavs.size(); ++i) {
    const int n = static_cast<int>(sorties::coverage_waypoints(p.uavs[i]).size());
    std::vector<flight::Helper> helpers;
    for (std::size_t h = 0; h < p.uavs.size(); ++h)
      if (h != i) helpers.push_back({h, 1.0});
    for (int lr : {n / 3, (2 * n) / 3}) {
      const double rest_ms = best_ms([&] { (void)flight::remainder_area(p, i, lr); });
      flight::Reassignment r;
      const double ms = best_ms([&] { r = flight::reassign(p, i, lr, helpers); });
      int wps = 0;
      std::size_t sorties = 0;
      for (const auto& w : r.work) wps += w.waypoints, sorties += w.sorties.size();
      std::printf("| %s | %d | %d | %.0f | %.2f | %.1f | %d | %zu |\n", p.uavs[i].id.c_str(), n, lr,
                  r.area_m2, rest_ms, ms, wps, sorties);
    }
  }
  const auto tracks = tracks_10hz(p);
  std::size_t samples = 0;
  for (const auto& t : tracks) samples += t.second.size();
  flight::FlownCoverage fc;
  const double ms = best_ms([&] { fc = flight::flown_coverage(p, tracks); }, 3);
  const auto planned = evaluation::evaluate_plan(p);
  const double again_ms = best_ms([&] { fc = flight::flown_coverage(p, planned, tracks); }, 3);
  std::printf(
      "flown coverage of the whole flights at 10 Hz: %zu samples (%zu in the band), lattice %d x %d, "
      "flown PoC %.4f, planned PoC %.4f, %.0f ms (%.0f ms with the plan's evaluation given)\n",
      samples, fc.samples_in_band, fc.coverage.lattice_cols, fc.coverage.lattice_rows, fc.flown_poc,
      fc.planned_poc, ms, again_ms);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1) {
    for (int k = 1; k < argc; ++k) run(argv[k], parse_mission(slurp(argv[k])));
    return 0;
  }
  run("olive grove (examples/olive-grove.json)",
      parse_mission(slurp(UAVCOVER_SOURCE_DIR "/examples/olive-grove.json")));
  std::string roi = slurp(UAVCOVER_SOURCE_DIR "/bench/data/apostolidis2022/roi01.json");
  roi.replace(roi.find("\"uavs\": 1"), 9, "\"uavs\": 4");
  run("paper ROI 1 with 4 UAVs (bench/data/apostolidis2022/roi01.json)", parse_mission(roi));
  roi.replace(roi.find("\"spacing_m\": 40"), 15, "\"spacing_m\": 10");
  run("paper ROI 1 with 4 UAVs at a spacing of 10 m", parse_mission(roi));
  return 0;
}
