// The task-assignment MILP of Hong et al. 2021 §3.2–3.3, solved with COIN-OR CBC: binaries x_ijk
// (UAV k flies the edge i -> j), MTZ order variables u_i, the longest weighted distance s.
//   (3) every waypoint is entered once        (4) flow conservation per node and UAV
//   (5) MTZ: no subtours among the waypoints  (6) every UAV leaves its own depot once
//   (7) the two ends of each line segment are flown one after the other (back-and-forth)
//   (9) sum_ij c_ij x_ijk / w_k <= s          (8) minimise s + (1/M) sum_ijk c_ij x_ijk
// Nodes 0..M-1 are the depots (UAV k starts and ends at depot k, and never touches another UAV's
// depot: the paper's depot penalty, enforced exactly); node M + 2p and M + 2p + 1 are the two ends of
// pair p.
//
// The contracted model (Formulation::Contracted) has the same optimum with one node per pair and
// orientation instead of one per waypoint: node M + 2p + o is pair p entered at its end M + 2p + o and
// left at the other end, and exactly one of the two is visited. The pair's own edge becomes a constant
// on the assignment y_pk, constraint (7) disappears (a visit is a whole back-and-forth pass by
// construction), MTZ orders the P pairs instead of the 2P waypoints (with the Desrochers–Laporte
// lifting), and arcs between the two orientations of one pair do not exist.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "uavcover/context.hpp"

namespace uavcover::planners::milp {

struct Instance {
  int uavs = 0;   ///< M
  int pairs = 0;  ///< waypoint pairs (line segments or blocks of them)
  /// Edge costs c_ij, (M + 2 pairs)^2 row-major; the diagonal is unused.
  std::vector<double> cost;
  /// Per UAV the weight w_k of its distance in (9) (share * M: 1 for equal shares).
  std::vector<double> weight;
  [[nodiscard]] int nodes() const { return uavs + 2 * pairs; }
  [[nodiscard]] double c(int i, int j) const {
    return cost[static_cast<std::size_t>(i) * static_cast<std::size_t>(nodes()) +
                static_cast<std::size_t>(j)];
  }
};

/// A solution: per UAV its node sequence, depot first (the return to the depot is implied).
struct Routes {
  std::vector<std::vector<int>> seq;
};

/// Objective (8) of a solution (infinity when it is not feasible).
double objective(const Instance& in, const Routes& r);

/// Whether every route flies whole pairs: after the depot, each entered waypoint is followed by the
/// other end of its pair (constraint (7)).
bool back_and_forth(const Instance& in, const Routes& r);

enum class Formulation { Exact, Contracted };

struct Limits {
  Formulation model = Formulation::Exact;
  long long max_nodes = 100000;  ///< branch-and-bound nodes (a deterministic budget)
  double max_seconds = 60.0;     ///< CBC's time limit (the context's budget is applied on top)
  std::string stage = "milp";    ///< progress stage prefix
  double f0 = 0.0, f1 = 1.0;     ///< progress fraction range of this solve
};

struct Result {
  Routes routes;
  double objective = 0.0;  ///< of `routes`
  double bound = 0.0;      ///< best lower bound CBC proved
  double gap = 0.0;        ///< (objective - bound) / objective
  bool optimal = false;    ///< proven optimal
  bool from_warm_start = false;
  std::string status;  ///< optimal, node_limit, time_limit, stopped
  std::string model;   ///< exact or contracted
  int variables = 0, binaries = 0, rows = 0;
  int pruned_arcs = 0;  ///< contracted model: arcs left out as worse than the warm start
  long long bb_nodes = 0;
  double seconds = 0.0;
  double first_incumbent_s = -1.0;  ///< when CBC first had a solution (the warm start counts at 0)
};

/// Solves `in` with the formulation `lim.model` from the feasible warm start `start` (required: it is also
/// what is returned when CBC finds nothing better in its limits). Returns with status "stopped" when the
/// context asks to stop (a stop request or its deadline); the caller decides whether that is an error.
Result solve(const Instance& in, const Routes& start, const Limits& lim, const Context& ctx);

}  // namespace uavcover::planners::milp
