// One subproblem of the SMT planner (POPCORN, Shah et al. 2020): a closed walk that visits every node
// of a small connected lattice subgraph, found with z3 and shortened by tightening a pseudo-Boolean
// length bound until z3 proves no shorter walk exists or the subproblem's budget runs out.
//
// Encoding: per edge two Booleans (used once, used twice; twice implies once), per node an even
// degree in {2, 4, 6, 8} (three ordered Booleans), connectivity by lazy subtour cuts (every
// component of a model that is not the whole subgraph gets "at least one edge leaves it"), and
// sum(weight * use) <= bound. A Hamiltonian cycle is the case where every degree is 2; nodes of
// degree 4 and doubled edges are revisits, needed where no Hamiltonian cycle exists (odd node
// counts on the bipartite 4-connected lattice, dead ends).
//
// Optional turn penalty (beyond POPCORN): per pair of edges meeting at a node at an angle (not straight
// on), a Boolean implied by both edges being used, each weighted by the penalty in the objective
// sum(weight * use) + penalty * sum(turning pairs used) <= bound. Where every node has degree 2 (a
// Hamiltonian cycle) the pairs are exactly the walk's turns; at a revisited node they over-count.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <vector>

namespace uavcover::smt {

/// A connected subgraph in local node numbers 0..n-1.
struct Subgraph {
  int n = 0;
  std::vector<std::array<int, 2>> edges;  ///< undirected, a != b
  std::vector<int> weight;                ///< per edge, > 0 (the planner uses millimetres)
  /// (node, edge, edge): two edges meeting at the node at an angle other than 180 degrees, edge indices
  /// ascending; empty: no geometry known (the turn penalty then has nothing to weigh)
  std::vector<std::array<int, 3>> turns;
};

struct CoverOptions {
  int bound_offset = 1;  ///< each tightening asks for a walk shorter by this many shortest edges
  /// wall-clock safety net of the subproblem (all its z3 checks); a search it ends depends on the machine
  double timeout_s = 2.0;
  unsigned rlimit = 0;  ///< z3 resource limit (rlimit) per check (0: none); deterministic, unlike time
  /// z3 resource units (rlimit) for all checks of the subproblem together (0: none); deterministic
  unsigned long long resource_budget = 0;
  unsigned seed = 0;         ///< z3 random seeds
  int max_cut_rounds = 200;  ///< subtour-cut rounds per bound before giving up on that bound
  int turn_penalty = 0;  ///< objective cost of one turning pair of used edges (weight units); 0: length only
};

struct CoverResult {
  std::vector<int> walk;        ///< closed walk: walk[0] .. walk.back(), then back to walk[0]
  long long first_length = -1;  ///< length of the first connected z3 model (-1: none)
  long long length = 0;         ///< length of `walk`
  int models = 0;               ///< connected models found (each tightening that succeeded, plus the first)
  int checks = 0;               ///< z3 check() calls
  int cuts = 0;                 ///< subtour cuts added
  bool optimal = false;   ///< z3 proved the bound below `length` unsatisfiable (or it is the lower bound)
  bool fallback = false;  ///< no z3 model in budget: the doubled spanning tree walk
  std::vector<long long> lengths;     ///< length of every connected model, in the order found
  int turns = 0;                      ///< turning pairs (Subgraph::turns) among the edges `walk` uses
  long long objective = 0;            ///< length + turn_penalty * turns of `walk`
  std::vector<long long> objectives;  ///< objective of every connected model, in the order found
  unsigned long long resources = 0;   ///< z3 resource units (rlimit count) spent by the checks
  bool budget_out = false;  ///< the resource budget (or a check's rlimit) ended the search: deterministic
  bool timed_out = false;   ///< `timeout_s` ended the search: the result depends on the machine's load
};

/// Interrupts running z3 checks from another thread (a stop request, the plan's deadline).
class Interrupter {
 public:
  /// Interrupts every registered check now and every later one at once.
  void interrupt_all();
  [[nodiscard]] bool interrupted() const noexcept { return stopped_.load(); }
  // used by solve_cover: a z3 context (opaque here so that z3's header stays in cover.cpp)
  void add(void* z3_context);
  void remove(void* z3_context);

 private:
  std::mutex mutex_;
  std::vector<void*> active_;
  std::atomic<bool> stopped_{false};
};

/// Lower bound of any closed walk covering the subgraph: n shortest edges (n >= 3), 2 (n == 2), 0.
long long length_lower_bound(const Subgraph& g);

/// The closed walk around a depth-first spanning tree (every tree edge twice): always valid.
std::vector<int> tree_walk(const Subgraph& g);

/// Length of a closed walk (the edge back to walk[0] included); -1 if two consecutive nodes are not
/// joined by an edge of g.
long long walk_length(const Subgraph& g, const std::vector<int>& walk);

/// Turning pairs of g (Subgraph::turns) among the edges a closed walk uses (-1: a step is no edge).
int walk_turn_pairs(const Subgraph& g, const std::vector<int>& walk);

/// The best closed walk found within the options' budget; never fails on a connected subgraph
/// (falls back to tree_walk). `interrupter` may be null.
CoverResult solve_cover(const Subgraph& g, const CoverOptions& options, Interrupter* interrupter);

}  // namespace uavcover::smt
