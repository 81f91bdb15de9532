#include "planners/milp/model.hpp"

#include <fmt/format.h>
#include <CbcEventHandler.hpp>
#include <CbcModel.hpp>
#include <CbcStrategy.hpp>
#include <CglGomory.hpp>
#include <CglProbing.hpp>
#include <ClpEventHandler.hpp>
#include <CoinPackedMatrix.hpp>
#include <CoinPackedVector.hpp>
#include <OsiClpSolverInterface.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

namespace uavcover::planners::milp {

namespace {

using Clock = std::chrono::steady_clock;

/// Per-solve state the event handler (cloned by CBC) shares with the caller.
struct Watch {
  const Context* ctx = nullptr;
  const Limits* lim = nullptr;
  Clock::time_point t0;
  Clock::time_point last_report;
  bool stopped = false;
  double first_improvement_s = -1.0;
  /// CBC's bound at its last event before a stop: after a stop has cut an LP short, CBC's own bound
  /// may rest on an unfinished node, so a stopped search reports this one
  double bound = 0.0;
  CbcModel* cbc = nullptr;
};

/// Checks for a stop inside CBC's LP solves (root LP, cut and strong-branching resolves), where no
/// CBC event fires for seconds on large models: ends the LP and sets CBC's time limit to zero so
/// that its cut, heuristic and branching loops end too.
class LpHandler final : public ClpEventHandler {
 public:
  explicit LpHandler(Watch* w) : w_(w) {}
  int event(Event e) override {
    if (e != endOfIteration || ++count_ % 16 != 0) return -1;
    if (!w_->stopped && !w_->ctx->should_stop()) return -1;
    w_->stopped = true;
    if (w_->cbc) w_->cbc->setMaximumSeconds(0.0);
    return 0;
  }
  [[nodiscard]] ClpEventHandler* clone() const override { return new LpHandler(*this); }

 private:
  Watch* w_;
  unsigned count_ = 0;
};

/// Stops CBC when the context asks (checked at every node and solution event) and reports the
/// incumbent and the bound.
class Handler final : public CbcEventHandler {
 public:
  explicit Handler(Watch* w) : w_(w) {}
  CbcAction event(CbcEvent e) override {
    if (e == solution || e == heuristicSolution)
      if (w_->first_improvement_s < 0)
        w_->first_improvement_s = std::chrono::duration<double>(Clock::now() - w_->t0).count();
    if (!w_->stopped && w_->ctx->should_stop()) w_->stopped = true;
    if (!w_->stopped) w_->bound = std::max(w_->bound, model_->getBestPossibleObjValue());
    if (w_->stopped) {
      // the root's cut and heuristic loops check the time, not the events: end them too
      model_->setMaximumSeconds(0.0);
      return stop;
    }
    const auto now = Clock::now();
    if (now - w_->last_report > std::chrono::milliseconds(100)) {
      w_->last_report = now;
      const double inc = model_->getObjValue(), bound = model_->getBestPossibleObjValue();
      const double gap = inc > 0 && inc < 1e50 ? std::max(0.0, (inc - bound) / inc) : 1.0;
      const double nodes_done = static_cast<double>(model_->getNodeCount()) /
                                static_cast<double>(std::max<long long>(1, w_->lim->max_nodes));
      const double frac = std::clamp(std::max(1.0 - gap, nodes_done), 0.0, 1.0);
      w_->ctx->report(fmt::format("{} incumbent {:.1f} bound {:.1f}", w_->lim->stage, inc, bound),
                      w_->lim->f0 + (w_->lim->f1 - w_->lim->f0) * frac);
    }
    return noAction;
  }
  [[nodiscard]] CbcEventHandler* clone() const override { return new Handler(*this); }

 private:
  Watch* w_;
};

/// The model handed to CBC: columns, then rows.
struct Lp {
  std::vector<double> obj, lb, ub;
  std::vector<bool> integer;
  // rows as triplets, made into one matrix at the end: appending rows to a CoinPackedMatrix one by one
  // copies it again and again (seconds, without a stop check, on a 40-pair exact model)
  std::vector<int> trow, tcol;
  std::vector<double> tval;
  std::vector<double> rlo, rhi;
  std::vector<int> first;  ///< columns CBC branches on first
  int add(double o, double l, double h, bool is_int) {
    obj.push_back(o);
    lb.push_back(l);
    ub.push_back(h);
    integer.push_back(is_int);
    return static_cast<int>(obj.size()) - 1;
  }
  void begin_rows() {}
  void row(const CoinPackedVector& v, double lo, double hi) {
    const int r = static_cast<int>(rlo.size());
    for (int e = 0; e < v.getNumElements(); ++e) {
      trow.push_back(r);
      tcol.push_back(v.getIndices()[e]);
      tval.push_back(v.getElements()[e]);
    }
    rlo.push_back(lo);
    rhi.push_back(hi);
  }
  [[nodiscard]] CoinPackedMatrix matrix() const {
    CoinPackedMatrix m(false, trow.data(), tcol.data(), tval.data(), static_cast<CoinBigIndex>(tval.size()));
    m.setDimensions(static_cast<int>(rlo.size()), static_cast<int>(obj.size()));
    return m;
  }
};

/// Arc columns x_kij (-1: no such arc).
struct Arcs {
  int n = 0;
  std::vector<int> col;
  [[nodiscard]] std::size_t at(int k, int i, int j) const {
    return (static_cast<std::size_t>(k) * static_cast<std::size_t>(n) + static_cast<std::size_t>(i)) *
               static_cast<std::size_t>(n) +
           static_cast<std::size_t>(j);
  }
  [[nodiscard]] int operator()(int k, int i, int j) const { return col[at(k, i, j)]; }
};

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Models with more binaries than this are solved without probing cuts (either formulation).
constexpr int kProbingMaxBinaries = 2000;

bool uses(int m, int k, int node) { return node >= m || node == k; }

/// The other end of the pair of waypoint `node`.
int mate(int m, int node) { return m + ((node - m) ^ 1); }

/// A built model: its columns and rows, the warm start as a column vector, and how to read routes
/// back from a CBC solution.
struct Built {
  Lp lp;
  Arcs x;
  std::vector<double> x0;
  bool contracted = false;
  int pruned = 0;  ///< arcs left out (contracted model)
};

std::size_t pk(int p, int k, int m) {
  return static_cast<std::size_t>(p) * static_cast<std::size_t>(m) + static_cast<std::size_t>(k);
}

/// Flow conservation: per UAV k and node it uses, as many arcs in as out.
void flow_rows(Lp& lp, const Arcs& x, int m) {
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < x.n; ++j) {
      if (!uses(m, k, j)) continue;
      CoinPackedVector v;
      for (int i = 0; i < x.n; ++i) {
        if (x(k, i, j) >= 0) v.insert(x(k, i, j), 1.0);
        if (x(k, j, i) >= 0) v.insert(x(k, j, i), -1.0);
      }
      lp.row(v, 0.0, 0.0);
    }
}

/// The paper's model with the assignment variables y_pk (see model.hpp).
Built build_exact(const Instance& in, const Routes& start) {
  const int m = in.uavs, n = in.nodes(), w = 2 * in.pairs;
  Built b;
  Lp& lp = b.lp;
  Arcs& x = b.x;
  x.n = n;
  x.col.assign(static_cast<std::size_t>(m) * static_cast<std::size_t>(n) * static_cast<std::size_t>(n), -1);
  for (int k = 0; k < m; ++k)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        if (i == j || !uses(m, k, i) || !uses(m, k, j) || (i < m && j < m)) continue;
        x.col[x.at(k, i, j)] = lp.add(in.c(i, j) / m, 0.0, 1.0, true);
      }
  // assignment variables y_pk = x_abk + x_bak (UAV k flies pair p): the same model, but branching on
  // them decides who flies what before the order (without them CBC did not prove the 8-line, 3-UAV
  // test instance in 20 s; with them in about 12 s under load)
  std::vector<int> ycol(static_cast<std::size_t>(in.pairs) * static_cast<std::size_t>(m));
  for (int p = 0; p < in.pairs; ++p)
    for (int k = 0; k < m; ++k) ycol[pk(p, k, m)] = lp.add(0.0, 0.0, 1.0, true);
  lp.first = ycol;
  auto y = [&](int p, int k) { return ycol[pk(p, k, m)]; };
  std::vector<int> u(static_cast<std::size_t>(n), -1);
  for (int i = m; i < n; ++i) u[static_cast<std::size_t>(i)] = lp.add(0.0, 1.0, w, false);
  const int s = lp.add(1.0, 0.0, COIN_DBL_MAX, false);

  lp.begin_rows();
  // (3) every waypoint entered once
  for (int j = m; j < n; ++j) {
    CoinPackedVector v;
    for (int k = 0; k < m; ++k)
      for (int i = 0; i < n; ++i)
        if (i != j && x(k, i, j) >= 0) v.insert(x(k, i, j), 1.0);
    lp.row(v, 1.0, 1.0);
  }
  // (4) flow conservation
  flow_rows(lp, x, m);
  // (5) MTZ among the waypoints
  for (int i = m; i < n; ++i)
    for (int j = m; j < n; ++j) {
      if (i == j) continue;
      CoinPackedVector v;
      v.insert(u[static_cast<std::size_t>(i)], 1.0);
      v.insert(u[static_cast<std::size_t>(j)], -1.0);
      for (int k = 0; k < m; ++k) v.insert(x(k, i, j), w);
      lp.row(v, -COIN_DBL_MAX, w - 1.0);
    }
  // (6) every UAV leaves its depot once (at most once when there are fewer pairs than UAVs)
  for (int k = 0; k < m; ++k) {
    CoinPackedVector v;
    for (int j = m; j < n; ++j) v.insert(x(k, k, j), 1.0);
    lp.row(v, in.pairs >= m ? 1.0 : 0.0, 1.0);
  }
  // (7) back-and-forth along each pair, by one UAV: sum_k y_pk = 1 with y_pk = x_abk + x_bak, and UAV
  // k enters the pair from outside exactly when it flies it
  for (int p = 0; p < in.pairs; ++p) {
    const int a = m + 2 * p, bb = a + 1;
    CoinPackedVector v;
    for (int k = 0; k < m; ++k) v.insert(y(p, k), 1.0);
    lp.row(v, 1.0, 1.0);
    for (int k = 0; k < m; ++k) {
      CoinPackedVector along, enter;
      along.insert(x(k, a, bb), 1.0);
      along.insert(x(k, bb, a), 1.0);
      along.insert(y(p, k), -1.0);
      lp.row(along, 0.0, 0.0);
      for (int i = 0; i < n; ++i)
        for (int j : {a, bb})
          if (i != a && i != bb && x(k, i, j) >= 0) enter.insert(x(k, i, j), 1.0);
      enter.insert(y(p, k), -1.0);
      lp.row(enter, 0.0, 0.0);
    }
  }
  // (9) weighted distance of each UAV below s
  for (int k = 0; k < m; ++k) {
    CoinPackedVector v;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        if (i != j && x(k, i, j) >= 0) v.insert(x(k, i, j), in.c(i, j));
    v.insert(s, -in.weight[static_cast<std::size_t>(k)]);
    lp.row(v, -COIN_DBL_MAX, 0.0);
  }

  // warm start
  b.x0.assign(lp.obj.size(), 0.0);
  double s0 = 0.0;
  for (int k = 0; k < m; ++k) {
    const auto& q = start.seq[static_cast<std::size_t>(k)];
    double d = 0.0;
    for (std::size_t t = 0; t < q.size(); ++t) {
      const int a = q[t], c = t + 1 < q.size() ? q[t + 1] : k;
      if (a == c) continue;
      b.x0[static_cast<std::size_t>(x(k, a, c))] = 1.0;
      d += in.c(a, c);
      if (a >= m) b.x0[static_cast<std::size_t>(u[static_cast<std::size_t>(a)])] = static_cast<double>(t);
    }
    s0 = std::max(s0, d / in.weight[static_cast<std::size_t>(k)]);
    for (std::size_t t = 1; t < q.size(); t += 2) b.x0[static_cast<std::size_t>(y((q[t] - m) / 2, k))] = 1.0;
  }
  b.x0[static_cast<std::size_t>(s)] = s0;
  return b;
}

/// One node per pair and orientation (see model.hpp): node M + 2p + o enters pair p at waypoint
/// M + 2p + o and leaves it at the other end.
Built build_contracted(const Instance& in, const Routes& start) {
  const int m = in.uavs, n = in.nodes(), P = in.pairs;
  Built b;
  b.contracted = true;
  Lp& lp = b.lp;
  Arcs& x = b.x;
  x.n = n;
  x.col.assign(static_cast<std::size_t>(m) * static_cast<std::size_t>(n) * static_cast<std::size_t>(n), -1);
  // arc i -> j: from the depot or the exit of i's pair to the depot or the entry of j's
  auto cost = [&](int i, int j) { return in.c(i < m ? i : mate(m, i), j); };
  auto inner = [&](int p) { return in.c(m + 2 * p, m + 2 * p + 1); };
  // Arcs that cannot be in a solution better than the warm start are left out. A route of UAV k over
  // arc i -> j has transits of at least T: the shortest path from its depot to i's entry, the arc, the
  // shortest path from j's exit home (paths in the full graph with the pairs' legs at no cost, a
  // relaxation), and legs of at least those of i and j (all legs when k is the only UAV). The total
  // distance is at least T, all legs and the other UAVs' shortest trips out and back. Objective (8)
  // is at least d_k / w_k + total / M.
  const double incumbent = back_and_forth(in, start) ? objective(in, start) : kInf;
  std::vector<double> sp(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), 0.0);
  auto dist = [&](int i, int j) -> double& {
    return sp[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)];
  };
  double legs = 0.0;
  for (int p = 0; p < P; ++p) legs += inner(p);
  if (std::isfinite(incumbent)) {
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) dist(i, j) = i == j || (i >= m && j == mate(m, i)) ? 0.0 : in.c(i, j);
    for (int v = 0; v < n; ++v)  // Floyd-Warshall
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) dist(i, j) = std::min(dist(i, j), dist(i, v) + dist(v, j));
  }
  // each UAV's least transit out of and back to its depot (when every UAV must fly)
  std::vector<double> home(static_cast<std::size_t>(m), 0.0);
  for (int k = 0; k < m && P >= m && std::isfinite(incumbent); ++k) {
    double out = kInf, back = kInf;
    for (int j = m; j < n; ++j) out = std::min(out, in.c(k, j)), back = std::min(back, in.c(j, k));
    home[static_cast<std::size_t>(k)] = out + back;
  }
  const double all_home = std::accumulate(home.begin(), home.end(), 0.0);
  auto useful = [&](int k, int i, int j) {
    if (!std::isfinite(incumbent)) return true;
    double t = cost(i, j), own = 0.0;
    if (i >= m) t += dist(k, i), own += inner((i - m) / 2);
    if (j >= m) t += dist(mate(m, j), k), own += inner((j - m) / 2);
    const double dk = t + (m == 1 ? legs : own);
    const double total = t + legs + all_home - home[static_cast<std::size_t>(k)];
    const double lower = dk / in.weight[static_cast<std::size_t>(k)] + total / m;
    return lower <= incumbent * (1.0 + 1e-9) + 1e-9;
  };
  for (int k = 0; k < m; ++k)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        if (i == j || !uses(m, k, i) || !uses(m, k, j) || (i < m && j < m)) continue;
        if (i >= m && j >= m && (i - m) / 2 == (j - m) / 2) continue;  // the two orientations of one pair
        if (!useful(k, i, j)) {
          ++b.pruned;
          continue;
        }
        x.col[x.at(k, i, j)] = lp.add(cost(i, j) / m, 0.0, 1.0, true);
      }
  // y_pk: UAV k flies pair p; the pair's own legs are a constant on it
  std::vector<int> ycol(static_cast<std::size_t>(P) * static_cast<std::size_t>(m));
  for (int p = 0; p < P; ++p)
    for (int k = 0; k < m; ++k) ycol[pk(p, k, m)] = lp.add(inner(p) / m, 0.0, 1.0, true);
  lp.first = ycol;
  auto y = [&](int p, int k) { return ycol[pk(p, k, m)]; };
  // MTZ position of each pair within its UAV's route, 1..P
  std::vector<int> u(static_cast<std::size_t>(P));
  for (int p = 0; p < P; ++p) u[static_cast<std::size_t>(p)] = lp.add(0.0, 1.0, std::max(1, P), false);
  const int s = lp.add(1.0, 0.0, COIN_DBL_MAX, false);

  lp.begin_rows();
  // every pair flown once, by one UAV; UAV k enters pair p (in either orientation) exactly when y_pk
  for (int p = 0; p < P; ++p) {
    CoinPackedVector v;
    for (int k = 0; k < m; ++k) v.insert(y(p, k), 1.0);
    lp.row(v, 1.0, 1.0);
    for (int k = 0; k < m; ++k) {
      CoinPackedVector enter;
      for (int j : {m + 2 * p, m + 2 * p + 1})
        for (int i = 0; i < n; ++i)
          if (x(k, i, j) >= 0) enter.insert(x(k, i, j), 1.0);
      enter.insert(y(p, k), -1.0);
      lp.row(enter, 0.0, 0.0);
    }
  }
  // flow conservation per UAV and node
  flow_rows(lp, x, m);
  // (6) every UAV leaves its depot once (at most once when there are fewer pairs than UAVs)
  for (int k = 0; k < m; ++k) {
    CoinPackedVector v;
    for (int j = m; j < n; ++j)
      if (x(k, k, j) >= 0) v.insert(x(k, k, j), 1.0);
    lp.row(v, P >= m ? 1.0 : 0.0, 1.0);
  }
  // MTZ among the pairs, lifted (Desrochers and Laporte 1991):
  //   u_p - u_q + P X_pq + (P - 2) X_qp <= P - 1,  X_pq = sum over UAVs and orientations of p -> q
  for (int p = 0; p < P; ++p)
    for (int q = 0; q < P; ++q) {
      if (p == q) continue;
      CoinPackedVector v;
      v.insert(u[static_cast<std::size_t>(p)], 1.0);
      v.insert(u[static_cast<std::size_t>(q)], -1.0);
      for (int k = 0; k < m; ++k)
        for (int op = 0; op < 2; ++op)
          for (int oq = 0; oq < 2; ++oq) {
            const int i = m + 2 * p + op, j = m + 2 * q + oq;
            if (x(k, i, j) >= 0) v.insert(x(k, i, j), P);
            if (P > 2 && x(k, j, i) >= 0) v.insert(x(k, j, i), P - 2);
          }
      lp.row(v, -COIN_DBL_MAX, P - 1.0);
    }
  // (9) weighted distance of each UAV below s
  for (int k = 0; k < m; ++k) {
    CoinPackedVector v;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        if (x(k, i, j) >= 0) v.insert(x(k, i, j), cost(i, j));
    for (int p = 0; p < P; ++p) v.insert(y(p, k), inner(p));
    v.insert(s, -in.weight[static_cast<std::size_t>(k)]);
    lp.row(v, -COIN_DBL_MAX, 0.0);
  }

  // warm start: the entries of the pairs in flight order
  b.x0.assign(lp.obj.size(), 0.0);
  double s0 = 0.0;
  for (int k = 0; k < m && std::isfinite(incumbent); ++k) {
    const auto& q = start.seq[static_cast<std::size_t>(k)];
    double d = 0.0;
    int here = k, pos = 0;
    for (std::size_t t = 1; t < q.size(); t += 2) {
      const int e = q[t], p = (e - m) / 2;
      if (x(k, here, e) < 0) return b.x0.clear(), b;  // not expected: the start's arcs are never left out
      b.x0[static_cast<std::size_t>(x(k, here, e))] = 1.0;
      b.x0[static_cast<std::size_t>(y(p, k))] = 1.0;
      b.x0[static_cast<std::size_t>(u[static_cast<std::size_t>(p)])] = ++pos;
      d += cost(here, e) + inner(p);
      here = e;
    }
    if (here != k) {
      if (x(k, here, k) < 0) return b.x0.clear(), b;
      b.x0[static_cast<std::size_t>(x(k, here, k))] = 1.0;
      d += cost(here, k);
    }
    s0 = std::max(s0, d / in.weight[static_cast<std::size_t>(k)]);
  }
  b.x0[static_cast<std::size_t>(s)] = s0;
  return b;
}

/// Routes from CBC's solution vector.
Routes decode(const Instance& in, const Built& b, const double* sol) {
  const int m = in.uavs, n = in.nodes();
  Routes r;
  r.seq.resize(static_cast<std::size_t>(m));
  for (int k = 0; k < m; ++k) {
    auto& q = r.seq[static_cast<std::size_t>(k)];
    q.push_back(k);
    int at = k;
    for (int step = 0; step <= n; ++step) {
      int next = -1;
      for (int j = 0; j < n; ++j)
        if (j != at && b.x(k, at, j) >= 0 && sol[b.x(k, at, j)] > 0.5) next = j;
      if (next < 0 || next == k) break;
      q.push_back(next);
      if (b.contracted) q.push_back(mate(m, next));
      at = next;
    }
  }
  return r;
}

}  // namespace

bool back_and_forth(const Instance& in, const Routes& r) {
  const int m = in.uavs;
  if (static_cast<int>(r.seq.size()) != m) return false;
  for (const auto& q : r.seq) {
    if (q.size() % 2 != 1) return false;
    for (std::size_t t = 1; t + 1 < q.size(); t += 2)
      if (q[t] < m || q[t] >= in.nodes() || q[t + 1] != mate(m, q[t])) return false;
  }
  return true;
}

double objective(const Instance& in, const Routes& r) {
  const int m = in.uavs;
  if (static_cast<int>(r.seq.size()) != m) return std::numeric_limits<double>::infinity();
  std::vector<int> seen(static_cast<std::size_t>(in.nodes()), 0);
  double s = 0.0, total = 0.0;
  for (int k = 0; k < m; ++k) {
    const auto& q = r.seq[static_cast<std::size_t>(k)];
    if (q.empty() || q.front() != k) return std::numeric_limits<double>::infinity();
    double d = 0.0;
    for (std::size_t t = 0; t < q.size(); ++t) {
      const int a = q[t], b = t + 1 < q.size() ? q[t + 1] : k;
      if (t > 0) {
        if (a < m) return std::numeric_limits<double>::infinity();
        ++seen[static_cast<std::size_t>(a)];
      }
      if (a != b) d += in.c(a, b);
    }
    s = std::max(s, d / in.weight[static_cast<std::size_t>(k)]);
    total += d;
  }
  for (int i = m; i < in.nodes(); ++i)
    if (seen[static_cast<std::size_t>(i)] != 1) return std::numeric_limits<double>::infinity();
  return s + total / m;
}

Result solve(const Instance& in, const Routes& start, const Limits& lim, const Context& ctx) {
  const auto t0 = Clock::now();
  Result res;
  res.routes = start;
  res.objective = back_and_forth(in, start) ? objective(in, start) : std::numeric_limits<double>::infinity();
  res.from_warm_start = true;
  res.first_incumbent_s = 0.0;
  const bool contracted = lim.model == Formulation::Contracted;
  res.model = contracted ? "contracted" : "exact";

  Built b = contracted ? build_contracted(in, start) : build_exact(in, start);
  Lp& lp = b.lp;
  res.variables = static_cast<int>(lp.obj.size());
  res.binaries = static_cast<int>(std::count(lp.integer.begin(), lp.integer.end(), true));
  res.rows = static_cast<int>(lp.rlo.size());
  res.pruned_arcs = b.pruned;

  OsiClpSolverInterface solver;
  solver.messageHandler()->setLogLevel(0);
  solver.loadProblem(lp.matrix(), lp.lb.data(), lp.ub.data(), lp.obj.data(), lp.rlo.data(), lp.rhi.data());
  for (int c = 0; c < res.variables; ++c)
    if (lp.integer[static_cast<std::size_t>(c)]) solver.setInteger(c);

  Watch watch;
  watch.ctx = &ctx;
  watch.lim = &lim;
  watch.t0 = t0;
  watch.last_report = t0;
  LpHandler lp_handler(&watch);
  solver.getModelPtr()->passInEventHandler(&lp_handler);

  CbcModel model(solver);
  watch.cbc = &model;
  model.setLogLevel(0);
  model.messageHandler()->setLogLevel(0);
  model.solver()->messageHandler()->setLogLevel(0);
  model.setRandomSeed(1234567);
  model.setUseElapsedTime(true);
  CbcStrategyDefault strategy(1, 5, 5);
  strategy.setupPreProcessing(0);
  // contracted model: no Gomory cuts (the strategy adds none when a generator of the kind exists;
  // -100 = never called). Measured in bench_milp: the pentagon 1.2 s CPU with them, 0.25 s without;
  // 200 segments with the defaults 10.3 s with, 1.9 s without (gap 1.3 % and 2.0 %)
  CglGomory gomory;
  if (contracted) model.addCutGenerator(&gomory, -100, "Gomory");
  // large models (contracted or exact): no probing either. Its root pass runs without any callback, so
  // a stop waited for it: 0.8-1.1 s on a 40-pair, 3-UAV contracted model under load, 0.28-0.35 s
  // without it
  CglProbing probing;
  if (res.binaries > kProbingMaxBinaries) model.addCutGenerator(&probing, -100, "Probing");
  model.setStrategy(strategy);
  // branch on who flies what first
  model.findIntegers(false);
  for (int o = 0; o < model.numberObjects(); ++o) {
    OsiObject* obj = model.modifiableObject(o);
    if (!lp.first.empty() && obj->columnNumber() >= lp.first.front() &&
        obj->columnNumber() <= lp.first.back())
      obj->setPriority(1);
  }
  model.setMaximumNodes(static_cast<int>(std::min<long long>(lim.max_nodes, 1 << 30)));
  double seconds = lim.max_seconds;
  if (ctx.deadline())
    seconds = std::min(seconds, std::chrono::duration<double>(*ctx.deadline() - Clock::now()).count());
  model.setMaximumSeconds(std::max(0.01, seconds));
  Handler handler(&watch);
  model.passInEventHandler(&handler);
  if (std::isfinite(res.objective) && !b.x0.empty())
    model.setBestSolution(b.x0.data(), res.variables, res.objective, true);
  if (ctx.should_stop()) {
    res.status = "stopped";
  } else {
    model.branchAndBound();
    res.bb_nodes = model.getNodeCount();
    if (const double* best = model.bestSolution()) {
      Routes r = decode(in, b, best);
      const double o = back_and_forth(in, r) ? objective(in, r) : std::numeric_limits<double>::infinity();
      if (o < res.objective - 1e-9) {
        res.routes = std::move(r);
        res.objective = o;
        res.from_warm_start = false;
        res.first_incumbent_s = watch.first_improvement_s >= 0 ? watch.first_improvement_s : 0.0;
      }
    }
    res.optimal = !watch.stopped && model.isProvenOptimal() && std::isfinite(res.objective);
    res.bound = std::min(watch.stopped ? watch.bound : model.getBestPossibleObjValue(), res.objective);
    res.status = watch.stopped                   ? "stopped"
                 : res.optimal                   ? "optimal"
                 : model.isSecondsLimitReached() ? "time_limit"
                 : model.isNodeLimitReached()    ? "node_limit"
                                                 : "stopped";
  }
  if (res.optimal) res.bound = std::max(res.bound, res.objective * (1.0 - 1e-9));
  res.gap = res.objective > 0 ? std::max(0.0, (res.objective - res.bound) / res.objective) : 0.0;
  res.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return res;
}

}  // namespace uavcover::planners::milp
