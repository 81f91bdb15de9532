// Flown coverage: tracks in the coverage band -> polylines in the plan's frame -> the evaluator's
// coverage simulation on the plan's lattice -> PoC and the overlay picture.
#include "flight/coverage.hpp"

#include <fmt/format.h>

#include <cmath>

#include "geodesy/local_frame.hpp"
#include "render/render.hpp"
#include "uavcover/error.hpp"

namespace uavcover::flight {

namespace {

/// Straight runs of a track sampled at 5-10 Hz become one leg each (Douglas-Peucker), so the evaluator
/// sweeps legs, not thousands of sample-to-sample steps.
constexpr double kSimplifyM = 0.25;

void check_tracks(const Plan& plan, const std::vector<Track>& tracks) {
  std::size_t total = 0;
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    const auto& [uav, samples] = tracks[i];
    bool known = false;
    for (const auto& up : plan.uavs) known = known || up.id == uav;
    if (!known)
      throw InputError(fmt::format("tracks[{}].uav", i), fmt::format("\"{}\" is no UAV of the plan", uav));
    total += samples.size();
    if (total > kMaxTrackSamples)
      throw InputError("tracks", fmt::format("more than {} samples in all", kMaxTrackSamples));
    for (std::size_t k = 0; k < samples.size(); ++k) {
      const auto& s = samples[k];
      if (!std::isfinite(s[0]) || !std::isfinite(s[1]) || !std::isfinite(s[2]) || std::abs(s[0]) > 180.0 ||
          std::abs(s[1]) > 90.0)
        throw InputError(
            fmt::format("tracks[{}].samples[{}]", i, k),
            "must be [lon, lat, altitude] with finite numbers, lon in [-180, 180], lat in [-90, 90]");
    }
  }
}

}  // namespace

FlownCoverage flown_coverage(const Plan& plan, const std::vector<Track>& tracks, const Context& ctx) {
  evaluation::EvaluateOptions options;
  options.coverage.context = &ctx;
  return flown_coverage(plan, evaluation::evaluate_plan(plan, options), tracks, ctx);
}

FlownCoverage flown_coverage(const Plan& plan, const evaluation::Evaluation& planned,
                             const std::vector<Track>& tracks, const Context& ctx) {
  check_tracks(plan, tracks);
  const geodesy::LocalFrame frame(plan.origin);
  const double altitude = plan.mission.altitude_m;
  FlownCoverage out;

  // each track's runs in the coverage band, as the evaluator's coverage parts, swept with the footprint
  // the plan's evaluation gave that UAV (its own camera's, else the mission's)
  std::vector<evaluation::Flight> flights;
  std::vector<double> widths;
  for (const auto& [uav, samples] : tracks) {
    ctx.check();
    double w = planned.footprint_m;
    for (std::size_t i = 0; i < plan.uavs.size() && i < planned.coverage.uavs.size(); ++i)
      if (plan.uavs[i].id == uav) w = planned.coverage.uavs[i].footprint_m;
    widths.push_back(w);
    evaluation::Flight flight;
    Polyline run;
    auto close_run = [&] {
      if (run.empty()) return;
      Polyline simple;
      bg::simplify(run, simple, kSimplifyM);
      flight.push_back({PartKind::Coverage, std::vector<Point>(simple.begin(), simple.end()), {}});
      run.clear();
    };
    for (const auto& s : samples) {
      if (std::abs(s[2] - altitude) <= kCoverageBandM) {
        ++out.samples_in_band;
        run.push_back(frame.to_local({s[0], s[1]}));
      } else {
        ++out.samples_out_of_band;
        close_run();
      }
    }
    close_run();
    flights.push_back(std::move(flight));
  }

  // the plan's lattice for the tracks: the same free area, footprints and options
  out.planned_poc = planned.coverage.total.poc;
  evaluation::CoverageOptions co;
  co.context = &ctx;
  co.footprint_m = planned.footprint_m;
  co.uav_footprint_m = std::move(widths);
  out.coverage = evaluation::evaluate_coverage(planned.free, flights, co);
  out.flown_poc = out.coverage.total.poc;
  out.flown_pooc = out.coverage.total.pooc;
  out.bounds = evaluation::lattice_bounds(out.coverage, frame);
  out.overlay = render::heatmap_overlay_png(out.coverage, "coverage.png");
  return out;
}

}  // namespace uavcover::flight
