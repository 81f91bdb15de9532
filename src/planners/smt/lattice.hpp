// The SMT planner's lattice (POPCORN's capture points): nodes at the mission's spacing over the free
// area, edges to the 4 (or 8) neighbours where the segment stays clear; its division among the UAVs,
// its split into small connected subgraphs, and the stitching of the subgraphs' closed walks into
// routes (sorties) from a home point under a flight-time limit.
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "planners/planner.hpp"
#include "planners/smt/cover.hpp"

namespace uavcover::smt {

struct Lattice {
  double ds = 0.0;
  Point origin;  ///< lower-left corner of cell (0, 0); node (i, j) sits at origin + ((i + .5) ds, (j + .5)
                 ///< ds), except a node moved out of a no-fly zone (build_lattice, coverage mode)
  int cols = 0, rows = 0;
  std::vector<int> node_of_cell;         ///< rows * cols, row-major; -1: no node
  std::vector<Point> pos;                ///< per node
  std::vector<std::array<int, 2>> cell;  ///< per node: (column, row)
  std::vector<std::vector<int>> adj;     ///< per node: neighbours over clear edges (sorted)
  std::vector<std::vector<int>> adj4;    ///< the same, axis neighbours only
  [[nodiscard]] int size() const { return static_cast<int>(pos.size()); }
  /// Edge weight in millimetres (the z3 length unit).
  [[nodiscard]] int weight(int a, int b) const;
  [[nodiscard]] bool adjacent(int a, int b) const;
};

/// Strict mode: nodes inside the free area, edges within it. Coverage mode: nodes within ds/2 of the
/// free area and outside the no-fly zones, edges that do not enter a no-fly zone; a cell centred in a
/// no-fly zone whose cell holds free ground has its node moved to the zone's nearest edge, 1 m outside
/// it (dropped when no clear edge joins it to the unmoved nodes). Throws InputError
/// ("spacing_m") when the lattice would exceed `max_nodes` or has no node.
/// `check` (optional) is called once per lattice row.
Lattice build_lattice(const planners::Problem& problem, bool eight_connected, int max_nodes,
                      const std::function<void()>& check = {});

/// Divides the nodes among the UAVs: each UAV grows from the free node nearest its start, over axis
/// edges, always the UAV furthest below its share taking its frontier node nearest its seed; so every
/// part is 4-connected. Nodes no seed reaches (another component) go to the UAV with the nearest seed.
/// Then the parts are balanced towards the shares over chains of adjacent parts, each part staying
/// 4-connected with its seed (issue 26: the growth alone walled a UAV in on C and U shapes).
/// Returns the owner per node.
std::vector<int> divide(const Lattice& lat, const std::vector<Point>& starts,
                        const std::vector<double>& shares);

/// Splits `nodes` (one UAV's part) into connected subgraphs of about `size` nodes: square-ish tiles of
/// the lattice (`strips`: tiles two lattice lines wide and size / 2 long, along the nodes' longer
/// extent, whose cycles turn only at their ends), each tile's part split into its connected components.
std::vector<std::vector<int>> split(const Lattice& lat, const std::vector<int>& nodes, int size,
                                    bool strips = false);

/// The subgraph of `nodes` with the lattice's edges between them (local numbers follow `nodes`).
Subgraph subgraph(const Lattice& lat, const std::vector<int>& nodes);

/// A closed walk over lattice node ids (the step back to the first node implicit).
using Walk = std::vector<int>;

struct Route {
  /// in flight order from `entry` to the exit: a closed walk flown open (flight_order), or, for a piece
  /// of a walk too long for one route (split_route), an open path
  Walk walk;
  int entry = 0;        ///< the route's first node (its node nearest home, unless a piece)
  double time_s = 0;    ///< modelled flight time home -> entry -> walk -> exit -> home
  double length_m = 0;  ///< the same flight's length
  int turns = 0;        ///< the turns the time model charges (path_cost)
  int walks = 0;        ///< subgraph walks stitched into it
};

/// A closed walk in flight order: rotated to start at `entry` and turned so that its last node (the
/// exit, a lattice neighbour of the entry) is the nearer of the entry's two neighbours on it to `home`.
/// The route flies it as an open path, entry to exit: the closing step back to the entry is the leg
/// home instead.
Walk flight_order(const Lattice& lat, const Walk& walk, int entry, Point home);

/// Flight time in seconds (eq. 15, with turns) and length of a flight from `home` over an open path of
/// lattice nodes and back: home -> path[0] -> ... -> path.back() -> home; `leg(a, b)` returns the
/// transit polyline between two points (around no-fly zones). Turns: every vertex of the path's
/// polyline (collinear ones dropped), as the engine counts a sortie's turns (sorties.cpp), plus the
/// bends of the two legs around no-fly zones, so that both the engine's sortie time and the flight's
/// geometric turns are within `time_s`.
struct RouteCost {
  double time_s = 0, length_m = 0;
  int turns = 0;
};
using LegFn = std::function<std::vector<Point>(Point, Point)>;
RouteCost path_cost(const Lattice& lat, const Walk& path, Point home, const Uav& uav, const LegFn& leg);

/// path_cost of a closed walk flown from `entry` in flight_order.
RouteCost route_cost(const Lattice& lat, const Walk& walk, int entry, Point home, const Uav& uav,
                     const LegFn& leg);

/// Cuts a route whose flight exceeds `max_time_s` into consecutive pieces of its path, each flown from
/// home and back within the limit (greedy: each piece as long as the limit allows; nodes an earlier
/// piece visited are not flown again at a piece's ends). Throws InputError
/// ("planner_params.max_flight_time_s") when one node alone cannot be reached and left within it.
std::vector<Route> split_route(const Lattice& lat, const Route& route, Point home, const Uav& uav,
                               double max_time_s, const LegFn& leg);

/// Tree stitching: starting from the walk nearest `home`, grows a route by splicing in adjacent walks
/// (a zero-cost exchange of two parallel edges where there is one, else a detour over one lattice
/// edge), nearest to home first, while the route's flight time stays within `max_time_s`; then starts
/// the next route at the nearest walk left. A walk that alone exceeds the limit is cut into pieces
/// (split_route; `split` counts such walks), so every route is within the limit.
std::vector<Route> stitch(const Lattice& lat, const std::vector<Walk>& walks, Point home, const Uav& uav,
                          double max_time_s, const LegFn& leg, int* split,
                          const std::function<void()>& check = {});

/// The polyline of a walk from its first node (`closed`: back to it; else to its last node),
/// collinear vertices dropped.
std::vector<Point> walk_polyline(const Lattice& lat, const Walk& walk, bool closed = true);

}  // namespace uavcover::smt
