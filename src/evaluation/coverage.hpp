// Coverage simulation (Apostolidis et al. 2022 §3): sample the free area on a lattice, sweep a
// square footprint of width w along every straight leg (w/2 beyond each end), count scans.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "uavcover/context.hpp"
#include "uavcover/geometry.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::evaluation {

struct CoverageOptions {
  double footprint_m = 0.0;  ///< w; required (> 0)
  /// Heterogeneous cameras: one w per flight (that UAV's own footprint); empty: footprint_m for all.
  std::vector<double> uav_footprint_m;
  double lattice_m = 0.0;  ///< sample spacing; 0 = adaptive (about 0.25-4 m^2 per sample)
  std::size_t max_samples = 20'000'000;
  bool count_transit = false;        ///< transit legs scan too
  const Context* context = nullptr;  ///< checked for stops (throws Cancelled / TimeLimitReached)
  /// Footprints that change along the legs (terrain, docs/photogrammetry.md): the widths of the `pieces`
  /// equal pieces of UAV `uav`'s leg a-b (a part of kind `kind`), each swept as its own rectangle (the
  /// leg's ends extended by half their width). Empty: footprint_m everywhere.
  std::function<std::vector<double>(std::size_t uav, PartKind kind, Point a, Point b, std::size_t pieces)>
      widths;
  double piece_m = 2.0;  ///< length of the pieces when `widths` is set
  /// Oblique parts (docs/patterns.md "Obliques"): a coverage part whose attitude has a gimbal pitch other
  /// than -90 sweeps the tilted camera's trapezoid (photo::oblique_footprint) at `altitude_m` (the part's
  /// own altitude_m when it has one), facing the part's heading_deg (per vertex; empty: along the track),
  /// with these fields of view. hfov_deg 0: no camera, every part sweeps the nadir square.
  double hfov_deg = 0.0;
  double vfov_deg = 0.0;
  double altitude_m = 0.0;
};

struct CoverageStats {
  double poc = 0.0;   ///< share of samples scanned >= 1 time
  double pooc = 0.0;  ///< share of samples scanned >= 2 times
  int max_scans = 0;
  std::vector<double> histogram;  ///< normalised: histogram[k] = share of samples scanned k times
  int turns = 0;                  ///< waypoints of the coverage loops, start counted twice (paper)
  double length_m = 0.0;          ///< all legs flown (coverage + transit)
  double area_m2 = 0.0;           ///< free area
  double turns_per_1000m2 = 0.0;
  double length_per_1000m2 = 0.0;  ///< metres per 1000 m^2
};

struct UavCoverage {
  CoverageStats stats;       ///< coverage by this UAV's legs alone (shares of the whole free area)
  double area_share = 0.0;   ///< share of the scanned samples this UAV scans (shared ones split equally)
  double footprint_m = 0.0;  ///< the w its legs were swept with
};

/// The samples one oblique direction sees (all UAVs' parts with that heading and pitch).
struct DirectionCoverage {
  double heading_deg = 0.0;  ///< where the camera faces (the parts' first vertex's heading)
  double gimbal_pitch_deg = 0.0;
  double poc = 0.0;  ///< share of the free area's samples inside at least one of its footprints
  int parts = 0;     ///< coverage parts swept with it
};

struct CoverageResult {
  /// With oblique parts: the share of samples the nadir parts see (gimbal -90 or none), and per
  /// oblique direction its own PoC (in order of first appearance). Without: empty.
  std::optional<double> nadir_poc;
  std::vector<DirectionCoverage> oblique;
  double lattice_m = 0.0;
  std::size_t samples = 0;
  CoverageStats total;
  std::vector<UavCoverage> uavs;
  // scan counts on the lattice, for heatmaps: row-major, -1 outside the free area
  Point lattice_origin;  ///< local position of sample (0,0)
  int lattice_cols = 0, lattice_rows = 0;
  std::vector<int> scans;
};

/// One UAV's flight as parts (coverage/transit polylines in local metres).
using Flight = std::vector<PathPart>;

CoverageResult evaluate_coverage(const MultiPolygon& free, const std::vector<Flight>& flights,
                                 const CoverageOptions& options);

}  // namespace uavcover::evaluation
