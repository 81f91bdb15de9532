// Flown coverage (issue 12, docs/flights.md): the UAVs' flown tracks through the same coverage
// simulation as the plan's evaluation (src/evaluation/), counting only what was flown in the coverage
// band, against the plan's own paths; with the coverage overlay picture for the map.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "evaluation/evaluate.hpp"
#include "uavcover/artifact.hpp"
#include "uavcover/context.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::flight {

/// A track sample within this many metres of the mission altitude is in the coverage band (it scans).
inline constexpr double kCoverageBandM = 5.0;
/// Track samples accepted over all tracks (about 55 UAV-hours at 10 Hz).
inline constexpr std::size_t kMaxTrackSamples = 2'000'000;

/// One UAV's flown track: its id and samples [lon, lat, metres above take-off] in time order, as
/// Flight::tracks() gives them.
using Track = std::pair<std::string, std::vector<std::array<double, 3>>>;

struct FlownCoverage {
  double flown_poc = 0.0;           ///< share of the free area's lattice samples scanned by the tracks
  double planned_poc = 0.0;         ///< the same for the plan's own paths (what plan.json reports)
  double flown_pooc = 0.0;          ///< share scanned at least twice by the tracks
  std::size_t samples_in_band = 0;  ///< track samples that scanned
  std::size_t samples_out_of_band = 0;
  evaluation::GeoBounds bounds;  ///< the WGS84 box the overlay spans
  Artifact overlay;              ///< "coverage.png": the flown scans per lattice sample, transparent outside
  evaluation::CoverageResult coverage;  ///< the flown lattice (scan counts) itself
};

/// Flown coverage of `tracks`: each UAV's samples in the coverage band (altitude within kCoverageBandM
/// of plan.mission.altitude_m) form polylines, broken where the track leaves the band, and the
/// evaluator sweeps that UAV's footprint along them (the width the plan's evaluation gave it: its own
/// camera's, uavs[i].camera, else the mission's) over the free area, on the same lattice as the
/// plan's evaluation. Samples are joined in order; straight runs are simplified (0.25 m) first.
/// InputError naming "tracks[i].uav" (not a UAV of the plan), "tracks[i].samples[k]" (not a finite
/// position) or "tracks" (more than kMaxTrackSamples). ctx: stops (Cancelled).
FlownCoverage flown_coverage(const Plan& plan, const std::vector<Track>& tracks, const Context& ctx = {});

/// The same with the plan's evaluation (evaluation::evaluate_plan(plan)) computed once by the caller,
/// for a flight that updates its flown coverage as the tracks grow (bench_reassign: 390 -> 334 ms on
/// the olive grove, 264 -> 160 ms on the paper's ROI 1).
FlownCoverage flown_coverage(const Plan& plan, const evaluation::Evaluation& planned,
                             const std::vector<Track>& tracks, const Context& ctx = {});

}  // namespace uavcover::flight
