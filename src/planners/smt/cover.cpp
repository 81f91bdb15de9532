#include "planners/smt/cover.hpp"

#include <z3++.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <limits>
#include <numeric>

namespace uavcover::smt {

void Interrupter::interrupt_all() {
  std::lock_guard lock(mutex_);
  stopped_.store(true);
  for (void* c : active_) static_cast<z3::context*>(c)->interrupt();
}

void Interrupter::add(void* z3_context) {
  std::lock_guard lock(mutex_);
  active_.push_back(z3_context);
  if (stopped_.load()) static_cast<z3::context*>(z3_context)->interrupt();
}

void Interrupter::remove(void* z3_context) {
  std::lock_guard lock(mutex_);
  active_.erase(std::remove(active_.begin(), active_.end(), z3_context), active_.end());
}

namespace {

/// Incident edges per node, in edge order.
std::vector<std::vector<int>> incidence(const Subgraph& g) {
  std::vector<std::vector<int>> inc(static_cast<std::size_t>(g.n));
  for (std::size_t e = 0; e < g.edges.size(); ++e) {
    inc[static_cast<std::size_t>(g.edges[e][0])].push_back(static_cast<int>(e));
    inc[static_cast<std::size_t>(g.edges[e][1])].push_back(static_cast<int>(e));
  }
  return inc;
}

int other(const Subgraph& g, int e, int v) {
  const auto& ed = g.edges[static_cast<std::size_t>(e)];
  return ed[0] == v ? ed[1] : ed[0];
}

/// Connected components over edges with use[e] > 0; returns the label per node and the count.
int components(const Subgraph& g, const std::vector<std::vector<int>>& inc, const std::vector<int>& use,
               std::vector<int>& label) {
  label.assign(static_cast<std::size_t>(g.n), -1);
  int count = 0;
  std::vector<int> stack;
  for (int s = 0; s < g.n; ++s) {
    if (label[static_cast<std::size_t>(s)] >= 0) continue;
    label[static_cast<std::size_t>(s)] = count;
    stack.push_back(s);
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (int e : inc[static_cast<std::size_t>(v)]) {
        if (use[static_cast<std::size_t>(e)] == 0) continue;
        const int w = other(g, e, v);
        if (label[static_cast<std::size_t>(w)] < 0) {
          label[static_cast<std::size_t>(w)] = count;
          stack.push_back(w);
        }
      }
    }
    ++count;
  }
  return count;
}

/// Euler circuit (Hierholzer) of the multigraph with use[e] copies of edge e, from node 0. Every
/// degree is even and the used edges connect all nodes.
std::vector<int> euler_walk(const Subgraph& g, const std::vector<std::vector<int>>& inc,
                            std::vector<int> use) {
  std::vector<std::size_t> next(static_cast<std::size_t>(g.n), 0);
  std::vector<int> stack{0}, circuit;
  while (!stack.empty()) {
    const int v = stack.back();
    auto& k = next[static_cast<std::size_t>(v)];
    const auto& edges = inc[static_cast<std::size_t>(v)];
    while (k < edges.size() && use[static_cast<std::size_t>(edges[k])] == 0) ++k;
    if (k == edges.size()) {
      circuit.push_back(v);
      stack.pop_back();
    } else {
      const int e = edges[k];
      --use[static_cast<std::size_t>(e)];
      stack.push_back(other(g, e, v));
    }
  }
  std::reverse(circuit.begin(), circuit.end());
  if (circuit.size() > 1) circuit.pop_back();  // closed: the last node repeats the first
  return circuit;
}

/// Copies of each edge a closed walk uses (empty for a walk of fewer than two nodes, or when a step is
/// no edge of g).
std::vector<int> walk_uses(const Subgraph& g, const std::vector<int>& walk) {
  if (walk.size() <= 1) return {};
  std::vector<int> use(g.edges.size(), 0);
  for (std::size_t k = 0; k < walk.size(); ++k) {
    const int a = walk[k], b = walk[(k + 1) % walk.size()];
    const auto it = std::find_if(g.edges.begin(), g.edges.end(), [&](const std::array<int, 2>& e) {
      return (e[0] == a && e[1] == b) || (e[0] == b && e[1] == a);
    });
    if (it == g.edges.end()) return {};
    ++use[static_cast<std::size_t>(it - g.edges.begin())];
  }
  return use;
}

long long used_length(const Subgraph& g, const std::vector<int>& use) {
  long long total = 0;
  for (std::size_t e = 0; e < use.size(); ++e) total += static_cast<long long>(use[e]) * g.weight[e];
  return total;
}

/// The subgraph of g's lightest edges (same nodes; turning pairs renumbered).
Subgraph lightest_edges(const Subgraph& g) {
  Subgraph out;
  out.n = g.n;
  if (g.weight.empty()) return out;
  const int w = *std::min_element(g.weight.begin(), g.weight.end());
  std::vector<int> index(g.edges.size(), -1);
  for (std::size_t e = 0; e < g.edges.size(); ++e)
    if (g.weight[e] == w) {
      index[e] = static_cast<int>(out.edges.size());
      out.edges.push_back(g.edges[e]);
      out.weight.push_back(w);
    }
  for (const auto& t : g.turns) {
    const int a = index[static_cast<std::size_t>(t[1])], b = index[static_cast<std::size_t>(t[2])];
    if (a >= 0 && b >= 0) out.turns.push_back({t[0], a, b});
  }
  return out;
}

bool connected(const Subgraph& g) {
  std::vector<int> label;
  return components(g, incidence(g), std::vector<int>(g.edges.size(), 1), label) == 1;
}

int turn_pairs(const Subgraph& g, const std::vector<int>& use) {
  if (use.empty()) return 0;
  return static_cast<int>(std::count_if(g.turns.begin(), g.turns.end(), [&](const std::array<int, 3>& t) {
    return use[static_cast<std::size_t>(t[1])] > 0 && use[static_cast<std::size_t>(t[2])] > 0;
  }));
}

}  // namespace

long long length_lower_bound(const Subgraph& g) {
  if (g.n <= 1 || g.weight.empty()) return 0;
  const long long w = *std::min_element(g.weight.begin(), g.weight.end());
  long long steps = g.n == 2 ? 2 : g.n;
  // equal weights on a bipartite graph (the 4-connected lattice): a closed walk alternates the two
  // colours, so it has an even number of steps, at least twice the larger colour class
  const bool uniform = std::all_of(g.weight.begin(), g.weight.end(), [&](int x) { return x == w; });
  if (uniform) {
    const auto inc = incidence(g);
    std::vector<int> colour(static_cast<std::size_t>(g.n), -1);
    long long count[2] = {0, 0};
    bool bipartite = true;
    for (int s = 0; s < g.n && bipartite; ++s) {
      if (colour[static_cast<std::size_t>(s)] >= 0) continue;
      colour[static_cast<std::size_t>(s)] = 0;
      std::vector<int> stack{s};
      while (!stack.empty() && bipartite) {
        const int v = stack.back();
        stack.pop_back();
        ++count[colour[static_cast<std::size_t>(v)]];
        for (int e : inc[static_cast<std::size_t>(v)]) {
          const int u = other(g, e, v);
          if (colour[static_cast<std::size_t>(u)] < 0) {
            colour[static_cast<std::size_t>(u)] = 1 - colour[static_cast<std::size_t>(v)];
            stack.push_back(u);
          } else if (colour[static_cast<std::size_t>(u)] == colour[static_cast<std::size_t>(v)]) {
            bipartite = false;
          }
        }
      }
    }
    if (bipartite) steps = std::max(steps, 2 * std::max(count[0], count[1]));
  }
  return steps * w;
}

std::vector<int> tree_walk(const Subgraph& g) {
  if (g.n <= 0) return {};
  const auto inc = incidence(g);
  std::vector<char> seen(static_cast<std::size_t>(g.n), 0);
  std::vector<int> walk;
  // iterative DFS that records the node on entry and again after returning from each child
  std::vector<std::pair<int, std::size_t>> stack{{0, 0}};
  seen[0] = 1;
  walk.push_back(0);
  while (!stack.empty()) {
    auto& [v, k] = stack.back();
    const auto& edges = inc[static_cast<std::size_t>(v)];
    bool descended = false;
    while (k < edges.size()) {
      const int w = other(g, edges[k++], v);
      if (seen[static_cast<std::size_t>(w)]) continue;
      seen[static_cast<std::size_t>(w)] = 1;
      walk.push_back(w);
      stack.emplace_back(w, 0);
      descended = true;
      break;
    }
    if (!descended) {
      stack.pop_back();
      if (!stack.empty()) walk.push_back(stack.back().first);
    }
  }
  if (walk.size() > 1) walk.pop_back();  // back at node 0: the closing edge is implicit
  return walk;
}

long long walk_length(const Subgraph& g, const std::vector<int>& walk) {
  const std::vector<int> use = walk_uses(g, walk);
  if (use.empty() && walk.size() > 1) return -1;
  return used_length(g, use);
}

int walk_turn_pairs(const Subgraph& g, const std::vector<int>& walk) {
  const std::vector<int> use = walk_uses(g, walk);
  if (use.empty() && walk.size() > 1) return -1;
  return turn_pairs(g, use);
}

CoverResult solve_cover(const Subgraph& g, const CoverOptions& options, Interrupter* interrupter) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  CoverResult out;
  const long long penalty = std::max(0, options.turn_penalty);
  out.walk = tree_walk(g);
  out.length = walk_length(g, out.walk);
  out.turns = walk_turn_pairs(g, out.walk);
  out.objective = out.length + penalty * out.turns;
  out.fallback = true;
  const long long lower = length_lower_bound(g);
  // edges of several weights (the 8-connected lattice): solve on the lightest edges alone first (the
  // 4-connected tile, where z3 proves optimality quickly), if they connect every node, and start from
  // that walk; it is often at the lower bound already
  if (const Subgraph light = lightest_edges(g); light.edges.size() < g.edges.size() && connected(light)) {
    const CoverResult inner = solve_cover(light, options, interrupter);
    out.checks += inner.checks;
    out.cuts += inner.cuts;
    out.resources += inner.resources;  // the tile's budget is shared by both searches
    out.timed_out = inner.timed_out;
    const long long objective = inner.length + penalty * walk_turn_pairs(g, inner.walk);
    if (!inner.fallback && objective < out.objective) {
      out.walk = inner.walk;
      out.length = inner.length;
      out.turns = walk_turn_pairs(g, inner.walk);
      out.objective = objective;
      out.fallback = false;
      out.first_length = out.length;
      out.lengths.push_back(out.length);
      out.objectives.push_back(out.objective);
    }
  }
  // a connected cover of nodes that are not all on one line turns somewhere: at least one turning pair
  const long long lower_objective = lower + (g.turns.empty() ? 0 : penalty);
  if (g.n <= 1 || out.objective <= lower_objective) {  // one node, or the walk so far is optimal
    if (out.fallback) {
      out.fallback = false;
      out.first_length = out.length;
      out.lengths.push_back(out.length);
      out.objectives.push_back(out.objective);
    }
    out.optimal = true;
    return out;
  }
  const auto inc = incidence(g);
  const long long unit = *std::min_element(g.weight.begin(), g.weight.end());

  // z3 throws once its context is interrupted (a stop, the deadline): the best walk so far stands
  try {
    z3::context c;
    struct Registration {
      Interrupter* i;
      z3::context* c;
      Registration(Interrupter* in, z3::context* ctx) : i(in), c(ctx) {
        if (i) i->add(c);
      }
      ~Registration() {
        if (i) i->remove(c);
      }
      Registration(const Registration&) = delete;
      Registration& operator=(const Registration&) = delete;
    } registration(interrupter, &c);

    z3::solver s(c, "QF_FD");  // Booleans and pseudo-Boolean sums: the SAT core
    std::vector<z3::expr> once, twice;
    for (std::size_t e = 0; e < g.edges.size(); ++e) {
      once.push_back(c.bool_const(("a" + std::to_string(e)).c_str()));
      twice.push_back(c.bool_const(("b" + std::to_string(e)).c_str()));
      s.add(z3::implies(twice.back(), once.back()));
    }
    for (int v = 0; v < g.n; ++v) {
      // deg(v) = sum(once + twice) = 2 + 2 * (p1 + p2 + p3), written with positive coefficients:
      // sum(once + twice) + 2 * (!p1 + !p2 + !p3) = 8, and p3 -> p2 -> p1 against symmetric models
      z3::expr_vector terms(c);
      std::vector<int> coeffs;
      for (int e : inc[static_cast<std::size_t>(v)]) {
        terms.push_back(once[static_cast<std::size_t>(e)]);
        terms.push_back(twice[static_cast<std::size_t>(e)]);
        coeffs.insert(coeffs.end(), {1, 1});
      }
      const std::string base = "p" + std::to_string(v) + "_";
      const z3::expr p1 = c.bool_const((base + "1").c_str()), p2 = c.bool_const((base + "2").c_str()),
                     p3 = c.bool_const((base + "3").c_str());
      s.add(z3::implies(p3, p2));
      s.add(z3::implies(p2, p1));
      for (const auto& p : {p1, p2, p3}) {
        terms.push_back(!p);
        coeffs.push_back(2);
      }
      s.add(z3::pbeq(terms, coeffs.data(), 8));
    }
    z3::expr_vector length_terms(c);
    std::vector<int> length_coeffs;
    for (std::size_t e = 0; e < g.edges.size(); ++e) {
      length_terms.push_back(once[e]);
      length_terms.push_back(twice[e]);
      length_coeffs.insert(length_coeffs.end(), {g.weight[e], g.weight[e]});
    }
    // the objective: the length plus, with a turn penalty, a Boolean per turning pair that both of its
    // edges imply (the solver keeps it false otherwise, the bound pushing it down)
    z3::expr_vector objective_terms(c);  // a copy of an expr_vector would share its contents
    for (const z3::expr& term : length_terms) objective_terms.push_back(term);
    std::vector<int> objective_coeffs = length_coeffs;
    if (penalty > 0)
      for (std::size_t t = 0; t < g.turns.size(); ++t) {
        const z3::expr turn = c.bool_const(("t" + std::to_string(t)).c_str());
        s.add(!once[static_cast<std::size_t>(g.turns[t][1])] ||
              !once[static_cast<std::size_t>(g.turns[t][2])] || turn);
        objective_terms.push_back(turn);
        objective_coeffs.push_back(static_cast<int>(penalty));
      }

    // the subtours a lattice model falls into first, cut up front: an edge walked there and back, and the
    // 3- and 4-cycles (a lattice cell's square); each set must be left at least twice
    auto cut = [&](const std::vector<int>& set) {
      if (static_cast<int>(set.size()) >= g.n) return;
      z3::expr_vector leaving(c);
      std::vector<int> ones;
      for (std::size_t e = 0; e < g.edges.size(); ++e) {
        const bool a = std::find(set.begin(), set.end(), g.edges[e][0]) != set.end();
        const bool b = std::find(set.begin(), set.end(), g.edges[e][1]) != set.end();
        if (a == b) continue;
        leaving.push_back(once[e]);
        leaving.push_back(twice[e]);
        ones.insert(ones.end(), {1, 1});
      }
      s.add(z3::pbge(leaving, ones.data(), 2));
      ++out.cuts;
    };
    std::vector<std::vector<char>> joined(static_cast<std::size_t>(g.n),
                                          std::vector<char>(static_cast<std::size_t>(g.n), 0));
    for (const auto& e : g.edges) {
      joined[static_cast<std::size_t>(e[0])][static_cast<std::size_t>(e[1])] = 1;
      joined[static_cast<std::size_t>(e[1])][static_cast<std::size_t>(e[0])] = 1;
    }
    auto j = [&](int a, int b) {
      return joined[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)] != 0;
    };
    for (const auto& e : g.edges) cut({e[0], e[1]});
    for (int a = 0; a < g.n; ++a)
      for (int b = a + 1; b < g.n; ++b) {
        if (!j(a, b)) continue;
        for (int d = a + 1; d < g.n; ++d) {
          if (d == b || !j(a, d)) continue;
          if (d > b && j(b, d)) cut({a, b, d});  // a triangle (diagonal edges)
          for (int x = a + 1; x < g.n; ++x)      // a square a-b-x-d, a its smallest node, b < d
            if (b < d && x != b && x != d && j(b, x) && j(d, x)) cut({a, b, x, d});
        }
      }

    // the resource budget left for this context's checks (z3's rlimit count is cumulative per context)
    const unsigned long long spent_before = out.resources;
    auto spent = [&] {
      const z3::stats st = s.statistics();
      for (unsigned i = 0; i < st.size(); ++i)
        if (st.key(i) == "rlimit count")
          return static_cast<unsigned long long>(st.is_uint(i) ? st.uint_value(i) : st.double_value(i));
      return 0ULL;
    };

    std::vector<int> use(g.edges.size(), 0), label;
    // One bound: check, cut the model's subtours, check again until a connected model (1), unsat (0) or
    // no answer in the budget (-1). The bound and the cuts stay in the solver's current scope.
    // `length_only`: bound the length alone (the probe for a Hamiltonian cycle), else the objective
    auto attempt = [&](long long bound, bool length_only) {
      const auto& terms = length_only ? length_terms : objective_terms;
      const auto& coeffs = length_only ? length_coeffs : objective_coeffs;
      s.add(z3::pble(terms, coeffs.data(),
                     static_cast<int>(std::min<long long>(bound, std::numeric_limits<int>::max()))));
      for (int round = 0; round < options.max_cut_rounds; ++round) {
        if (interrupter && interrupter->interrupted()) return -1;
        // the deterministic budget first: a check gets the smaller of its own rlimit and what is left
        unsigned long long limit = options.rlimit > 0 ? options.rlimit : 0ULL;
        if (options.resource_budget > 0) {
          if (out.resources >= options.resource_budget) {
            out.budget_out = true;
            return -1;
          }
          const unsigned long long left = options.resource_budget - out.resources;
          limit = limit > 0 ? std::min(limit, left) : left;
        }
        limit = std::min<unsigned long long>(limit, std::numeric_limits<unsigned>::max());
        const double left = options.timeout_s - std::chrono::duration<double>(Clock::now() - t0).count();
        if (left <= 0.0) {
          out.timed_out = true;
          return -1;
        }
        z3::params p(c);
        p.set("timeout", static_cast<unsigned>(std::max(1.0, std::min(left * 1000.0, 4.0e9))));
        if (limit > 0) p.set("rlimit", static_cast<unsigned>(limit));
        p.set("random_seed", options.seed);
        s.set(p);
        ++out.checks;
        z3::check_result r = z3::unknown;
        try {
          r = s.check();
        } catch (const z3::exception&) {  // interrupted or out of resources
          r = z3::unknown;
        }
        out.resources = spent_before + spent();
        if (r == z3::unsat) return 0;
        if (r != z3::sat) {
          // which budget ended the check: the wall clock (load-dependent), or else the resources
          const double after = options.timeout_s - std::chrono::duration<double>(Clock::now() - t0).count();
          if (interrupter && interrupter->interrupted()) return -1;
          if (after <= 0.0 || s.reason_unknown().find("timeout") != std::string::npos)
            out.timed_out = true;
          else
            out.budget_out = true;
          return -1;
        }
        const z3::model m = s.get_model();
        for (std::size_t e = 0; e < g.edges.size(); ++e)
          use[e] = (m.eval(once[e], true).is_true() ? 1 : 0) + (m.eval(twice[e], true).is_true() ? 1 : 0);
        const int count = components(g, inc, use, label);
        if (count == 1) return 1;
        for (int k = 0; k < count; ++k) {  // a closed walk leaves every proper subset at least twice
          std::vector<int> set;
          for (int v = 0; v < g.n; ++v)
            if (label[static_cast<std::size_t>(v)] == k) set.push_back(v);
          cut(set);
        }
      }
      return -1;
    };
    // a model replaces the best walk when its objective is lower (the probe's may not be)
    auto take = [&] {
      const long long len = used_length(g, use);
      const int turns = turn_pairs(g, use);
      const long long objective = len + penalty * turns;
      if (out.first_length < 0) out.first_length = len;
      if (!out.fallback && objective >= out.objective) return false;
      out.lengths.push_back(len);
      out.objectives.push_back(objective);
      ++out.models;
      out.walk = euler_walk(g, inc, use);
      out.length = len;
      out.turns = turns;
      out.objective = objective;
      out.fallback = false;
      return true;
    };
    // each tightening asks for an objective lower by (bound_offset - 1) shortest edges and then some:
    // with bound_offset 1, any better walk
    const long long step = static_cast<long long>(options.bound_offset - 1) * unit + 1;
    long long bound = out.objective - step;  // the tree walk is known: ask for better
    bool probed = false;
    while (bound >= lower_objective) {
      const int r = attempt(bound, false);
      if (r == 0) out.optimal = true;
      if (r != 1) break;
      take();
      if (out.objective <= lower_objective) {
        out.optimal = true;
        break;
      }
      if (!probed) {
        // once: ask for the length's lower bound itself (a Hamiltonian cycle on most lattice tiles) in a
        // scope of its own; without a turn penalty that is optimal, with one tightening goes on from the
        // better of the two models; if there is none, from the first model
        probed = true;
        s.push();
        const int at_lower = attempt(lower, true);
        if (at_lower == 1) take();
        s.pop();
        if (at_lower == 1 && penalty == 0) {
          out.optimal = true;
          break;
        }
        if (at_lower < 0) break;
      }
      bound = out.objective - step;
    }
    if (bound < lower_objective && !out.fallback) out.optimal = true;
  } catch (const z3::exception&) {
  }
  if (out.fallback && out.optimal) out.fallback = false;  // z3 proved nothing beats the tree walk
  return out;
}

}  // namespace uavcover::smt
