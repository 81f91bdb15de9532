#include "planners/milp/model.hpp"

#include <fmt/format.h>
#include <CbcEventHandler.hpp>
#include <CbcModel.hpp>
#include <CbcStrategy.hpp>
#include <CoinPackedMatrix.hpp>
#include <CoinPackedVector.hpp>
#include <OsiClpSolverInterface.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

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
    if (w_->ctx->should_stop()) {
      w_->stopped = true;
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

struct Columns {
  int n = 0;             // nodes
  std::vector<int> arc;  // (k * n + i) * n + j -> column or -1
  std::vector<int> u;    // node -> column (waypoints only)
  int s = -1;
  std::vector<double> obj, lb, ub;
  std::vector<bool> integer;
  int add(double o, double l, double h, bool is_int) {
    obj.push_back(o);
    lb.push_back(l);
    ub.push_back(h);
    integer.push_back(is_int);
    return static_cast<int>(obj.size()) - 1;
  }
  [[nodiscard]] int x(int k, int i, int j) const {
    return arc[(static_cast<std::size_t>(k) * static_cast<std::size_t>(n) + static_cast<std::size_t>(i)) *
                   static_cast<std::size_t>(n) +
               static_cast<std::size_t>(j)];
  }
};

bool uses(int m, int k, int node) { return node >= m || node == k; }

}  // namespace

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
  const int m = in.uavs, n = in.nodes(), w = 2 * in.pairs;
  Result res;
  res.routes = start;
  res.objective = objective(in, start);
  res.from_warm_start = true;
  res.first_incumbent_s = 0.0;

  // ---- columns ----
  Columns col;
  col.n = n;
  col.arc.assign(static_cast<std::size_t>(m) * static_cast<std::size_t>(n) * static_cast<std::size_t>(n), -1);
  for (int k = 0; k < m; ++k)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        if (i == j || !uses(m, k, i) || !uses(m, k, j) || (i < m && j < m)) continue;
        col.arc[(static_cast<std::size_t>(k) * static_cast<std::size_t>(n) + static_cast<std::size_t>(i)) *
                    static_cast<std::size_t>(n) +
                static_cast<std::size_t>(j)] = col.add(in.c(i, j) / m, 0.0, 1.0, true);
      }
  // assignment variables y_pk = x_abk + x_bak (UAV k flies pair p): the same model, but branching on
  // them decides who flies what before the order (without them CBC did not prove the 8-line, 3-UAV
  // test instance in 20 s; with them in about 12 s under load)
  std::vector<int> ycol(static_cast<std::size_t>(in.pairs) * static_cast<std::size_t>(m));
  auto yidx = [m](int p, int k) {
    return static_cast<std::size_t>(p) * static_cast<std::size_t>(m) + static_cast<std::size_t>(k);
  };
  for (int p = 0; p < in.pairs; ++p)
    for (int k = 0; k < m; ++k) ycol[yidx(p, k)] = col.add(0.0, 0.0, 1.0, true);
  auto y = [&](int p, int k) { return ycol[yidx(p, k)]; };
  res.binaries = static_cast<int>(col.obj.size());
  col.u.assign(static_cast<std::size_t>(n), -1);
  for (int i = m; i < n; ++i) col.u[static_cast<std::size_t>(i)] = col.add(0.0, 1.0, w, false);
  col.s = col.add(1.0, 0.0, COIN_DBL_MAX, false);
  res.variables = static_cast<int>(col.obj.size());

  // ---- rows ----
  CoinPackedMatrix mat(false, 0, 0);
  mat.setDimensions(0, res.variables);
  std::vector<double> rlo, rhi;
  auto row = [&](const CoinPackedVector& v, double lo, double hi) {
    mat.appendRow(v);
    rlo.push_back(lo);
    rhi.push_back(hi);
  };
  // (3) every waypoint entered once
  for (int j = m; j < n; ++j) {
    CoinPackedVector v;
    for (int k = 0; k < m; ++k)
      for (int i = 0; i < n; ++i)
        if (i != j && col.x(k, i, j) >= 0) v.insert(col.x(k, i, j), 1.0);
    row(v, 1.0, 1.0);
  }
  // (4) flow conservation
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < n; ++j) {
      if (!uses(m, k, j)) continue;
      CoinPackedVector v;
      for (int i = 0; i < n; ++i) {
        if (i == j) continue;
        if (col.x(k, i, j) >= 0) v.insert(col.x(k, i, j), 1.0);
        if (col.x(k, j, i) >= 0) v.insert(col.x(k, j, i), -1.0);
      }
      row(v, 0.0, 0.0);
    }
  // (5) MTZ among the waypoints
  for (int i = m; i < n; ++i)
    for (int j = m; j < n; ++j) {
      if (i == j) continue;
      CoinPackedVector v;
      v.insert(col.u[static_cast<std::size_t>(i)], 1.0);
      v.insert(col.u[static_cast<std::size_t>(j)], -1.0);
      for (int k = 0; k < m; ++k) v.insert(col.x(k, i, j), w);
      row(v, -COIN_DBL_MAX, w - 1.0);
    }
  // (6) every UAV leaves its depot once (at most once when there are fewer pairs than UAVs)
  for (int k = 0; k < m; ++k) {
    CoinPackedVector v;
    for (int j = m; j < n; ++j) v.insert(col.x(k, k, j), 1.0);
    row(v, in.pairs >= m ? 1.0 : 0.0, 1.0);
  }
  // (7) back-and-forth along each pair, by one UAV: sum_k y_pk = 1 with y_pk = x_abk + x_bak, and UAV
  // k enters the pair from outside exactly when it flies it
  for (int p = 0; p < in.pairs; ++p) {
    const int a = m + 2 * p, b = a + 1;
    CoinPackedVector v;
    for (int k = 0; k < m; ++k) v.insert(y(p, k), 1.0);
    row(v, 1.0, 1.0);
    for (int k = 0; k < m; ++k) {
      CoinPackedVector along, enter;
      along.insert(col.x(k, a, b), 1.0);
      along.insert(col.x(k, b, a), 1.0);
      along.insert(y(p, k), -1.0);
      row(along, 0.0, 0.0);
      for (int i = 0; i < n; ++i)
        for (int j : {a, b})
          if (i != a && i != b && col.x(k, i, j) >= 0) enter.insert(col.x(k, i, j), 1.0);
      enter.insert(y(p, k), -1.0);
      row(enter, 0.0, 0.0);
    }
  }
  // (9) weighted distance of each UAV below s
  for (int k = 0; k < m; ++k) {
    CoinPackedVector v;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        if (i != j && col.x(k, i, j) >= 0) v.insert(col.x(k, i, j), in.c(i, j));
    v.insert(col.s, -in.weight[static_cast<std::size_t>(k)]);
    row(v, -COIN_DBL_MAX, 0.0);
  }
  res.rows = static_cast<int>(rlo.size());

  OsiClpSolverInterface solver;
  solver.messageHandler()->setLogLevel(0);
  solver.loadProblem(mat, col.lb.data(), col.ub.data(), col.obj.data(), rlo.data(), rhi.data());
  for (int c = 0; c < res.variables; ++c)
    if (col.integer[static_cast<std::size_t>(c)]) solver.setInteger(c);

  // ---- warm start ----
  std::vector<double> x0(static_cast<std::size_t>(res.variables), 0.0);
  double s0 = 0.0;
  for (int k = 0; k < m; ++k) {
    const auto& q = start.seq[static_cast<std::size_t>(k)];
    double d = 0.0;
    for (std::size_t t = 0; t < q.size(); ++t) {
      const int a = q[t], b = t + 1 < q.size() ? q[t + 1] : k;
      if (a == b) continue;
      x0[static_cast<std::size_t>(col.x(k, a, b))] = 1.0;
      d += in.c(a, b);
      if (a >= m) x0[static_cast<std::size_t>(col.u[static_cast<std::size_t>(a)])] = static_cast<double>(t);
    }
    s0 = std::max(s0, d / in.weight[static_cast<std::size_t>(k)]);
    for (std::size_t t = 1; t < q.size(); t += 2) x0[static_cast<std::size_t>(y((q[t] - m) / 2, k))] = 1.0;
  }
  x0[static_cast<std::size_t>(col.s)] = s0;

  CbcModel model(solver);
  model.setLogLevel(0);
  model.messageHandler()->setLogLevel(0);
  model.solver()->messageHandler()->setLogLevel(0);
  model.setRandomSeed(1234567);
  model.setUseElapsedTime(true);
  CbcStrategyDefault strategy(1, 5, 5);
  strategy.setupPreProcessing(0);
  model.setStrategy(strategy);
  // branch on who flies what first
  model.findIntegers(false);
  for (int o = 0; o < model.numberObjects(); ++o) {
    OsiObject* obj = model.modifiableObject(o);
    if (!ycol.empty() && obj->columnNumber() >= ycol.front() && obj->columnNumber() <= ycol.back())
      obj->setPriority(1);
  }
  model.setMaximumNodes(static_cast<int>(std::min<long long>(lim.max_nodes, 1 << 30)));
  double seconds = lim.max_seconds;
  if (ctx.deadline())
    seconds = std::min(seconds, std::chrono::duration<double>(*ctx.deadline() - Clock::now()).count());
  model.setMaximumSeconds(std::max(0.01, seconds));
  Watch watch;
  watch.ctx = &ctx;
  watch.lim = &lim;
  watch.t0 = t0;
  watch.last_report = t0;
  Handler handler(&watch);
  model.passInEventHandler(&handler);
  if (std::isfinite(res.objective)) model.setBestSolution(x0.data(), res.variables, res.objective, true);
  if (ctx.should_stop()) {
    res.status = "stopped";
  } else {
    model.branchAndBound();
    res.bb_nodes = model.getNodeCount();
    const double* best = model.bestSolution();
    if (best) {
      Routes r;
      r.seq.resize(static_cast<std::size_t>(m));
      for (int k = 0; k < m; ++k) {
        auto& q = r.seq[static_cast<std::size_t>(k)];
        q.push_back(k);
        int at = k;
        for (int step = 0; step <= n; ++step) {
          int next = -1;
          for (int j = 0; j < n; ++j)
            if (j != at && col.x(k, at, j) >= 0 && best[col.x(k, at, j)] > 0.5) next = j;
          if (next < 0 || next == k) break;
          q.push_back(next);
          at = next;
        }
      }
      const double o = objective(in, r);
      if (o < res.objective - 1e-9) {
        res.routes = std::move(r);
        res.objective = o;
        res.from_warm_start = false;
        res.first_incumbent_s = watch.first_improvement_s >= 0 ? watch.first_improvement_s : 0.0;
      }
    }
    res.optimal = !watch.stopped && model.isProvenOptimal();
    res.bound = std::min(model.getBestPossibleObjValue(), res.objective);
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
