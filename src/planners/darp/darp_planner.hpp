// The DARP stage (paper Apostolidis et al. 2022 §2; thesis Mondinelli 2025 §3.1):
// grid placement optimisation -> DARP division -> STC paths with fewest turns.
// Everything here works in the local ENU frame (metres).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "planners/darp/placement.hpp"
#include "uavcover/context.hpp"
#include "uavcover/geometry.hpp"
#include "uavcover/mission.hpp"

namespace uavcover::darp {

/// The grid actually used (mega-cells of size 2*ds).
struct GridInfo {
  double cell_m = 0.0;  ///< mega-cell size dn = 2*ds
  double rotation_deg = 0.0;
  Point origin;  ///< local ENU position of mega-cell (0,0)'s lower-left corner
  int rows = 0, cols = 0;
  std::vector<int> owner;  ///< rows*cols; -1 blocked, else UAV index
};

/// The planner's own parameters (mission field planner_params).
struct Options {
  int max_iterations = 4000;         ///< per DARP attempt
  int placement_evaluations = 1500;  ///< grid placement budget (annealing steps in total)
  bool optimise_placement = true;
  bool extend_legs = true;  ///< lengthen U-turns at the region's edge toward the boundary (extend.hpp)
  bool shift_legs = true;   ///< move legs along the region's outer edge outward (LegExtender::shift)
  /// Try every spanning-tree orientation and keep the loop with the fewest turns (the paper's Fig. 8-9);
  /// false: one orientation (planner_params.min_turn_orientation).
  bool min_turn_orientation = true;
  /// The placement objective (planner_params.objective): false ("uavcover") maximises J plus the
  /// coverage estimate minus the length term (grid::Weights); true ("paper") maximises the paper's J
  /// alone (eq. 7, with the authors' disconnected-grid penalty): coverage_weight = length_weight = 0,
  /// and the search's best is kept without the coverage re-ranking.
  bool paper_objective = false;
  /// The weights a, b, c of J = a J1 + b J2 - c J3 (planner_params.j_weight_a, _b, _c), both objectives.
  double j_weight_a = grid::Weights{}.a;
  double j_weight_b = grid::Weights{}.b;
  double j_weight_c = grid::Weights{}.c;
  /// Every placement the search evaluates (grid::PlacementOptions::on_evaluation); empty: none.
  std::function<void(double, double, double, const grid::Score&)> on_placement_evaluation;
};

struct Input {
  MultiPolygon free;             ///< area minus no-fly zones (corrected)
  MultiPolygon no_fly;           ///< union of no-fly zones, including holes of the area
  std::vector<Point> starts;     ///< one per UAV (may lie outside the area)
  std::vector<double> shares;    ///< one per UAV, sum 1
  std::vector<std::string> ids;  ///< one per UAV, for warnings
  double ds = 0.0;               ///< scanning density; mega-cells are 2*ds
  /// One per UAV (or empty): the footprint width of a UAV's own camera, 0 for the mission's. The legs
  /// shifted along the edges keep such a UAV's swath meeting its inner lane's (issue 26).
  std::vector<double> own_footprint_m;
  Mode mode = Mode::Strict;
  std::uint64_t seed = 0;
};

struct UavResult {
  /// Closed coverage loops (last == first) of turning waypoints, in flight order; one per
  /// connected region the UAV flies. Each loop starts at its region's cell nearest the entry.
  std::vector<std::vector<Point>> loops;
  int cells = 0;               ///< mega-cells assigned
  double share_actual = 0.0;   ///< cells / all free cells
  MultiPolygon cells_outline;  ///< the mega-cells assigned, as polygons (they may reach past the area)
};

struct Output {
  grid::Placement placement;
  GridInfo grid;
  std::vector<UavResult> uavs;
  std::vector<std::string> warnings;
  bool converged = true;
  int iterations = 0;
  bool stopped_early = false;  ///< the time limit cut the search short (best result so far)
};

/// Runs the whole DARP pipeline. Deterministic for a given input (seed included).
/// Throws InputError when no free cell exists at this spacing.
///
/// Output::grid: mega-cell (r, c) has its lower-left corner at
///   origin + R(rotation_deg) * (c * cell_m, r * cell_m)   (local ENU metres, R = rotation CCW),
/// owner is row-major. Output::placement holds the paper's J = a J1 + b J2 - c J3 (by default 0.68,
/// 0.32, 0.25; -0.5 when the free grid has more components than the free space) of the chosen placement;
/// the search itself maximises J plus a swept-footprint coverage estimate minus a path-length term (see
/// grid/grid.hpp, grid::Weights), or J alone with Options::paper_objective. Warnings: starts outside
/// the free grid, DARP not meeting the share tolerance (2 % of each UAV's own share, at least one cell;
/// converged = false, best connected division used), UAVs without cells, shares that a split free
/// space cannot honour.
/// Progress goes to ctx; a stop request throws Cancelled; when the time is up the placement search
/// and the division end early with their best result so far (stopped_early).
Output run(const Input& input, const Options& options, const Context& ctx);

/// The warning for a grid with too few cells for the shares (`target`: each UAV's share in cells): the
/// best division in whole cells misses a share by more than DARP's 2 % of it. Says by how much, and what
/// to change: a finer spacing (about the one giving 25 cells to the smallest share; `ds` the spacing,
/// `free_area_m2` the free area), or a planner that divides continuously. Nothing when the grid is fine
/// enough or there is one UAV.
std::optional<std::string> coarse_grid_warning(const std::vector<double>& target, double ds,
                                               double free_area_m2);

}  // namespace uavcover::darp
