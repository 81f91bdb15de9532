#include "planners/darp/division.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <queue>
#include <random>

namespace uavcover::darp {

namespace {

constexpr double kConnVariation = 0.01;  // C_i range [1 - v, 1 + v] (Kapoutsis et al.)
constexpr double kAim = 1.0;             // the waves stop at this normalised deviation
constexpr int kStagnation = 20;          // ... or after this many evaluations without a better division
constexpr int kRebalanceRounds = 40;     // flow rounds of the border balance after the waves
/// The single-cell transfer search (transfer_search) runs on grids up to this many cells, for at most
/// this many cell visits.
constexpr int kTransferMaxCells = 5000;
constexpr double kTransferWork = 2e7;
/// Grids up to this many cell evaluations per iteration (cells x participants) run the classic DARP
/// iterations first; larger ones, and classic divisions off their shares, are balanced by waves.
constexpr double kClassicMaxWork = 1e5;
/// Absolute tolerance of the classic iterations' own stopping rule (cells).
double classic_tolerance(int cells) { return std::max(2.0, 0.01 * cells); }

struct Graph {
  int n = 0;
  int cols = 0;
  std::vector<int> cell;               // grid index of each node
  std::vector<std::array<int, 4>> nb;  // by direction: 0 right, 1 up, 2 left, 3 down; -1 none
};

Graph build_graph(const grid::Grid& g, const std::vector<int>& cells, std::vector<int>& lid) {
  Graph G;
  G.n = static_cast<int>(cells.size());
  G.cols = g.cols;
  G.cell = cells;
  lid.assign(static_cast<std::size_t>(g.rows) * g.cols, -1);
  for (int i = 0; i < G.n; ++i) lid[cells[i]] = i;
  G.nb.assign(G.n, {-1, -1, -1, -1});
  for (int i = 0; i < G.n; ++i) {
    const int k = cells[i];
    if ((g.link[k] & 1) && lid[k + 1] >= 0) G.nb[i][0] = lid[k + 1], G.nb[lid[k + 1]][2] = i;
    if ((g.link[k] & 2) && lid[k + g.cols] >= 0) G.nb[i][1] = lid[k + g.cols], G.nb[lid[k + g.cols]][3] = i;
  }
  return G;
}

/// Geodesic distances (octile metric over links: diagonal steps of sqrt 2 through a free corner).
std::vector<double> geodesic(const Graph& G, int src) {
  std::vector<double> d(G.n, std::numeric_limits<double>::infinity());
  using QE = std::pair<double, int>;
  std::priority_queue<QE, std::vector<QE>, std::greater<>> pq;
  d[src] = 0;
  pq.push({0, src});
  constexpr double diag = std::numbers::sqrt2;
  while (!pq.empty()) {
    const double du = pq.top().first;  // not a structured binding: clang 14 cannot capture one
    const int u = pq.top().second;
    pq.pop();
    if (du > d[u]) continue;
    auto relax = [&](int v, double w) {
      if (v >= 0 && du + w < d[v]) {
        d[v] = du + w;
        pq.push({d[v], v});
      }
    };
    for (int dir = 0; dir < 4; ++dir) relax(G.nb[u][dir], 1.0);
    for (int dir = 0; dir < 4; ++dir) {
      const int d2 = (dir + 1) % 4;
      int v = -1;
      if (G.nb[u][dir] >= 0) v = G.nb[G.nb[u][dir]][d2];
      if (v < 0 && G.nb[u][d2] >= 0) v = G.nb[G.nb[u][d2]][dir];
      relax(v, diag);
    }
  }
  return d;
}

/// Multi-source BFS (unit steps) from the cells where `src` is true.
void bfs(const Graph& G, const std::vector<int>& sources, std::vector<int>& dist, std::vector<int>& queue) {
  dist.assign(G.n, std::numeric_limits<int>::max());
  queue.clear();
  for (int s : sources) {
    dist[s] = 0;
    queue.push_back(s);
  }
  for (std::size_t h = 0; h < queue.size(); ++h) {
    const int u = queue[h];
    for (int v : G.nb[u])
      if (v >= 0 && dist[v] == std::numeric_limits<int>::max()) {
        dist[v] = dist[u] + 1;
        queue.push_back(v);
      }
  }
}

/// Marks the cells of participant i connected to its start; returns their count.
int main_piece(const Graph& G, const std::vector<int>& owner, int i, int start, std::vector<int>& mark,
               int stamp, std::vector<int>& stack) {
  int count = 0;
  stack.clear();
  stack.push_back(start);
  mark[start] = stamp;
  while (!stack.empty()) {
    const int u = stack.back();
    stack.pop_back();
    ++count;
    for (int v : G.nb[u])
      if (v >= 0 && mark[v] != stamp && owner[v] == i) {
        mark[v] = stamp;
        stack.push_back(v);
      }
  }
  return count;
}

/// Makes every region connected: cells cut off from their owner's start are handed to an
/// adjacent region (multi-source BFS from the kept cells).
void repair(const Graph& G, std::vector<int>& owner, const std::vector<int>& starts) {
  std::vector<int> mark(G.n, -1), stack;
  for (std::size_t i = 0; i < starts.size(); ++i)
    main_piece(G, owner, static_cast<int>(i), starts[i], mark, static_cast<int>(i), stack);
  std::vector<int> queue;
  for (int u = 0; u < G.n; ++u) {
    if (mark[u] == owner[u])
      queue.push_back(u);
    else
      owner[u] = -1;
  }
  for (std::size_t h = 0; h < queue.size(); ++h) {
    const int u = queue[h];
    for (int v : G.nb[u])
      if (v >= 0 && owner[v] < 0) {
        owner[v] = owner[u];
        queue.push_back(v);
      }
  }
}

/// Moves boundary cells along chains of neighbouring regions, from over- to under-allocated ones,
/// keeping every region connected and its start; stops when all are within `tol` or no move helps.
void polish(const Graph& G, std::vector<int>& owner, const std::vector<int>& st,
            const std::vector<double>& targets, const std::vector<std::vector<double>>& D, double tol,
            int max_moves) {
  const int n = G.n, P = static_cast<int>(st.size());
  std::vector<int> counts(P, 0);
  for (int x = 0; x < n; ++x) ++counts[owner[x]];
  std::vector<char> is_start(n, 0);
  for (int s : st) is_start[s] = 1;
  std::vector<int> mark(n, -1), stack;
  int stamp = 0;
  // deterministic work budget (cell visits) so that huge grids stay fast
  double work = 0;
  const double budget = 1e9;
  // can cell x leave region a without disconnecting it?
  auto removable = [&](int x, int a) {
    if (is_start[x]) return false;
    work += counts[a];
    owner[x] = -2;
    ++stamp;
    const int c = main_piece(G, owner, a, st[a], mark, stamp, stack);
    owner[x] = a;
    return c == counts[a] - 1;
  };
  // Hands cell x of region a, with everything its removal cuts off from a's start, to region b when
  // no start cell is among them and the squared deviation from the targets drops by more than eps.
  auto hand_over_cut = [&](int x, int a, int b, double eps) {
    work += n;
    owner[x] = -2;
    ++stamp;
    main_piece(G, owner, a, st[a], mark, stamp, stack);
    owner[x] = a;
    std::vector<int> cut;
    for (int y = 0; y < n; ++y)
      if (owner[y] == a && mark[y] != stamp) {
        if (is_start[y]) return false;
        cut.push_back(y);
      }
    const double m = static_cast<double>(cut.size());
    const double before = std::pow(counts[a] - targets[a], 2) + std::pow(counts[b] - targets[b], 2);
    const double after = std::pow(counts[a] - m - targets[a], 2) + std::pow(counts[b] + m - targets[b], 2);
    if (!(after + eps < before)) return false;
    for (int y : cut) owner[y] = b;
    counts[a] -= static_cast<int>(m);
    counts[b] += static_cast<int>(m);
    return true;
  };
  for (int move = 0; move < max_moves && work < budget; ++move) {
    work += n;
    std::vector<int> order(P);
    for (int i = 0; i < P; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return counts[a] - targets[a] > counts[b] - targets[b]; });
    double worst = 0;
    for (int i = 0; i < P; ++i) worst = std::max(worst, std::fabs(counts[i] - targets[i]));
    if (worst <= tol) return;
    // region adjacency
    std::vector<std::vector<char>> adj(P, std::vector<char>(P, 0));
    for (int x = 0; x < n; ++x)
      for (int v : G.nb[x])
        if (v >= 0 && owner[v] != owner[x]) adj[owner[x]][owner[v]] = 1;
    bool moved = false;
    for (int donor : order) {
      if (counts[donor] - targets[donor] <= 0.5) break;
      // BFS over regions to the nearest under-allocated one
      std::vector<int> prev(P, -1);
      std::vector<int> q{donor};
      prev[donor] = donor;
      int recv = -1;
      for (std::size_t h = 0; h < q.size() && recv < 0; ++h)
        for (int j = 0; j < P; ++j)
          if (adj[q[h]][j] && prev[j] < 0) {
            prev[j] = q[h];
            if (counts[j] - targets[j] < -0.5) {
              recv = j;
              break;
            }
            q.push_back(j);
          }
      if (recv < 0) continue;
      std::vector<int> chain{recv};
      while (chain.back() != donor) chain.push_back(prev[chain.back()]);
      std::reverse(chain.begin(), chain.end());  // donor ... recv
      // move one cell along every link of the chain, from the receiving end backwards
      bool ok = true;
      for (std::size_t k = chain.size() - 1; k > 0 && ok; --k) {
        const int a = chain[k - 1], b = chain[k];
        work += n;
        std::vector<int> cand;
        for (int x = 0; x < n; ++x) {
          if (owner[x] != a) continue;
          for (int v : G.nb[x])
            if (v >= 0 && owner[v] == b) {
              cand.push_back(x);
              break;
            }
        }
        std::stable_sort(cand.begin(), cand.end(), [&](int x, int y) { return D[b][x] < D[b][y]; });
        ok = false;
        for (std::size_t c = 0; c < cand.size() && c < 24 && !ok; ++c) {
          const int x = cand[c];
          if (is_start[x]) continue;
          if (removable(x, a)) {
            owner[x] = b;
            --counts[a];
            ++counts[b];
            ok = true;
          } else if (chain.size() == 2) {
            // x is a cut cell of a: hand over x with everything it cuts off from a's start, when
            // that brings both regions closer to their targets
            ok = hand_over_cut(x, a, b, 0.0);
          }
        }
      }
      if (ok) {
        moved = true;
        break;
      }
    }
    if (!moved) {
      // pull: an under-allocated region takes a boundary cell (with what it cuts off) from a
      // neighbour when that lowers the total squared deviation
      std::vector<int> recvs(order.rbegin(), order.rend());
      for (int b : recvs) {
        if (counts[b] - targets[b] >= -0.5 || work > budget) break;
        work += n;
        std::vector<int> cand;
        for (int x = 0; x < n; ++x) {
          if (owner[x] == b || is_start[x]) continue;
          for (int v : G.nb[x])
            if (v >= 0 && owner[v] == b) {
              cand.push_back(x);
              break;
            }
        }
        std::stable_sort(cand.begin(), cand.end(), [&](int x, int y) { return D[b][x] < D[b][y]; });
        for (std::size_t c = 0; c < cand.size() && c < 48 && !moved; ++c) {
          const int x = cand[c], a = owner[x];
          moved = hand_over_cut(x, a, b, 1e-9);
        }
        if (moved) break;
      }
    }
    if (!moved) return;
  }
}

/// Additively weighted partition grown by waves: every start sends out a wave at time -w_i; a wave
/// spreads over links only, reaching cell x at the time |x - s_i| - w_i (straight-line distance from
/// its start, in cells), or later when it has to go around an obstacle, and a cell goes to the first
/// wave that reaches it. Each cell is thus 4-adjacent to a cell its owner held earlier: every region
/// is connected and holds its start, whatever the weights. Straight-line times make the borders
/// hyperbolas, so a region's size changes smoothly with the weights (the octile or link metric has
/// flat bisectors: whole areas change hands at once). A bucket queue of width 1/16 cell orders the
/// cells; a time earlier than the current bucket (a wave coming round an obstacle) is the current one.
class Waves {
 public:
  explicit Waves(const Graph& G, std::vector<float> px, std::vector<float> py)
      : G_(G), px_(std::move(px)), py_(std::move(py)) {}

  /// owner[x] (participant) for weights w; counts per participant and sens[i * P + j], the number of
  /// cells region i takes from region j when w_i - w_j grows by one (estimated along their border).
  void run(const std::vector<int>& st, const std::vector<double>& w, std::vector<int>& owner,
           std::vector<int>& counts, std::vector<double>& sens) {
    const int n = G_.n, P = static_cast<int>(st.size());
    constexpr double width = 1.0 / 16;
    constexpr int live = 20;  // a push lands at most 1 cell (16 buckets) ahead
    owner.assign(n, -1);
    best_.assign(n, std::numeric_limits<double>::infinity());
    best_owner_.assign(n, -1);
    buckets_.resize(live);
    for (auto& b : buckets_) b.clear();
    pinned_.assign(n, 0);
    for (int s : st) pinned_[s] = 1;
    std::vector<int> order(P);
    for (int i = 0; i < P; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return w[a] > w[b]; });
    const double base = -w[order[0]];
    auto bucket_of = [&](double key) { return static_cast<long>(std::floor((key - base) / width)); };
    auto dist = [&](int x, int y) {
      const double dx = px_[x] - px_[y], dy = py_[x] - py_[y];
      return std::sqrt(dx * dx + dy * dy);
    };
    anchor_.assign(n, -1);
    anchor_time_.assign(n, 0.0);
    std::size_t next_src = 0;
    long pending = 0;
    std::vector<Entry> work;
    for (long b = 0; next_src < order.size() || pending > 0; ++b) {
      if (pending == 0) b = std::max(b, bucket_of(-w[order[next_src]]));  // jump over empty time
      auto& bucket = buckets_[static_cast<std::size_t>(b % live)];
      while (next_src < order.size() && bucket_of(-w[order[next_src]]) <= b) {
        const int i = order[next_src++];
        bucket.push_back({-w[i], st[i], i});
        anchor_[st[i]] = st[i];
        anchor_time_[st[i]] = -w[i];
        best_[st[i]] = -w[i];
        best_owner_[st[i]] = i;
        ++pending;
      }
      while (!bucket.empty()) {  // cells claimed in this bucket may claim more in it
        work.swap(bucket);
        for (const Entry& e : work) {
          --pending;
          const int v = e.v;
          // settled, or superseded by a better entry (pushed later, never in a later bucket)
          if (owner[v] >= 0 || e.key != best_[v] || e.o != best_owner_[v]) continue;
          owner[v] = e.o;
          for (int u : G_.nb[v]) {
            if (u < 0 || owner[u] >= 0 || pinned_[u]) continue;
            // straight on from v's anchor, unless that heads back toward it (the wave bends round an
            // obstacle or another region): then v anchors the cells behind it
            int a = anchor_[v];
            double t = dist(u, a) + anchor_time_[a];
            if (t < e.key) a = v, t = e.key + 1.0;
            if (best_owner_[u] >= 0 && !(t < best_[u] || (t == best_[u] && e.o < best_owner_[u]))) continue;
            best_[u] = t;
            best_owner_[u] = e.o;
            anchor_[u] = a;
            buckets_[static_cast<std::size_t>(std::max(b, bucket_of(t)) % live)].push_back({t, u, e.o});
            ++pending;
          }
          anchor_time_[v] = e.key;
        }
        work.clear();
      }
    }
    counts.assign(P, 0);
    sens.assign(static_cast<std::size_t>(P) * P, 0.0);
    for (int x = 0; x < n; ++x) {
      const int a = owner[x];
      ++counts[a];
      for (int dir = 0; dir < 2; ++dir) {  // right and up: each link once
        const int y = G_.nb[x][dir];
        if (y < 0 || owner[y] == a) continue;
        const int b = owner[y];
        // the border moves by dw / |u_a - u_b| along its normal (u: unit directions from the starts);
        // one link stands for 1 / (|n_x| + |n_y|) of border length
        const double mx = 0.5 * (px_[x] + px_[y]), my = 0.5 * (py_[x] + py_[y]);
        double ax = mx - px_[st[a]], ay = my - py_[st[a]], bx = mx - px_[st[b]], by = my - py_[st[b]];
        const double la = std::max(1e-9, std::hypot(ax, ay)), lb = std::max(1e-9, std::hypot(bx, by));
        const double gx = ax / la - bx / lb, gy = ay / la - by / lb;
        const double g = std::max(0.25, std::hypot(gx, gy));
        const double nsum = g > 0.25 ? (std::fabs(gx) + std::fabs(gy)) / g : 1.0;
        const double c = 1.0 / (g * std::max(1.0, nsum));
        sens[static_cast<std::size_t>(a) * P + b] += c;
        sens[static_cast<std::size_t>(b) * P + a] += c;
      }
    }
  }

 private:
  struct Entry {
    double key;
    int v;
    int o;  ///< the wave's participant
  };

  const Graph& G_;
  std::vector<float> px_, py_;       ///< cell column and row
  std::vector<double> best_;         ///< earliest time a wave reaches the cell, so far
  std::vector<int> best_owner_;      ///< that wave
  std::vector<int> anchor_;          ///< the cell the wave reached u from in a straight line
  std::vector<double> anchor_time_;  ///< time the wave reached each settled cell
  std::vector<char> pinned_;
  std::vector<std::vector<Entry>> buckets_;
};

/// Largest deviation from the targets, each in units of its own tolerance (<= 1: converged).
double normalised_deviation(const std::vector<int>& counts, const std::vector<double>& targets) {
  double worst = 0;
  for (std::size_t i = 0; i < counts.size(); ++i)
    worst = std::max(worst, std::fabs(counts[i] - targets[i]) / tolerance(targets[i]));
  return worst;
}

struct Balanced {
  std::vector<int> owner;
  double deviation = std::numeric_limits<double>::infinity();  ///< normalised_deviation of owner
  int iterations = 0;
};

/// Solves the augmented system [A | b] in place (Gaussian elimination, partial pivoting; the solution is
/// left in the last column). Boost uBLAS's lu.hpp does not compile as C++20 (allocator::construct).
bool solve(std::vector<std::vector<double>>& A) {
  const int m = static_cast<int>(A.size());
  for (int c = 0; c < m; ++c) {
    int piv = c;
    for (int r = c + 1; r < m; ++r)
      if (std::fabs(A[r][c]) > std::fabs(A[piv][c])) piv = r;
    if (!(std::fabs(A[piv][c]) > 1e-12)) return false;
    std::swap(A[c], A[piv]);
    for (int r = 0; r < m; ++r) {
      if (r == c || A[r][c] == 0) continue;
      const double f = A[r][c] / A[c][c];
      for (int k = c; k <= m; ++k) A[r][k] -= f * A[c][k];
    }
  }
  for (int r = 0; r < m; ++r) A[r][m] /= A[r][r];
  return true;
}

/// Solves L x = rhs for the Laplacian L of the symmetric P x P weights W (row-major), the last
/// participant's x held at 0 (L is singular); false when L is (a region without neighbours).
bool solve_laplacian(const std::vector<double>& W, const std::vector<double>& rhs, std::vector<double>& x) {
  const int P = static_cast<int>(rhs.size()), m = P - 1;
  std::vector<std::vector<double>> L(m, std::vector<double>(m + 1, 0.0));  // [L | rhs]
  for (int i = 0; i < m; ++i) {
    L[i][m] = rhs[i];
    double diag = 1e-6;
    for (int j = 0; j < P; ++j) {
      const double b = W[static_cast<std::size_t>(i) * P + j];
      diag += b;
      if (j < m && j != i) L[i][j] = -b;
    }
    L[i][i] = diag;
  }
  if (!solve(L)) return false;
  x.assign(P, 0.0);
  for (int i = 0; i < m; ++i) x[i] = L[i][m];
  return true;
}

/// Tunes the waves' weights until every region is within its tolerance (or the iterations run out), by
/// damped Newton steps: the Jacobian of the counts is the Laplacian of the regions' border sensitivities
/// (Waves::run). Each step is halved until the squared normalised error drops.
Balanced balance_waves(const Graph& G, const std::vector<int>& st, const std::vector<double>& targets,
                       int max_iter, const std::function<bool()>& stop_early,
                       const std::function<void(double)>& progress) {
  const int P = static_cast<int>(st.size());
  Balanced out;
  std::vector<float> px(G.n), py(G.n);
  for (int x = 0; x < G.n; ++x)
    px[x] = static_cast<float>(G.cell[x] % G.cols), py[x] = static_cast<float>(G.cell[x] / G.cols);
  Waves waves(G, std::move(px), std::move(py));
  std::vector<double> w(P, 0.0), sens, trial_sens;
  std::vector<int> owner, counts, trial_owner, trial_counts;
  for (int i = 0; i < P; ++i) w[i] = std::sqrt(targets[i] / std::numbers::pi);  // radius of a disc
  auto error = [&](const std::vector<int>& c) {
    double e = 0;
    for (int i = 0; i < P; ++i) e += std::pow((c[i] - targets[i]) / tolerance(targets[i]), 2);
    return e;
  };
  int last_gain = 0;  // the evaluation that last improved the best division
  auto evaluate = [&](const std::vector<double>& wt, std::vector<int>& o, std::vector<int>& c,
                      std::vector<double>& b) {
    ++out.iterations;
    if (progress) progress(static_cast<double>(out.iterations) / max_iter);
    waves.run(st, wt, o, c, b);
    const double dev = normalised_deviation(c, targets);
    if (dev < out.deviation) {
      out.deviation = dev;
      out.owner = o;
      last_gain = out.iterations;
    }
  };
  evaluate(w, owner, counts, sens);
  double err = error(counts);
  std::vector<double> wt(P), step(P);
  while (out.deviation > kAim && out.iterations < max_iter && out.iterations - last_gain < kStagnation &&
         !(stop_early && stop_early())) {
    // Newton step: L step = targets - counts
    std::vector<double> rhs(P);
    for (int i = 0; i < P; ++i) rhs[i] = targets[i] - counts[i];
    if (!solve_laplacian(sens, rhs, step)) break;  // a region without neighbours: nothing to trade
    double tau = 1.0;
    for (int halvings = 0; halvings < 8 && out.iterations < max_iter; ++halvings, tau *= 0.5) {
      if (halvings > 0 && stop_early && stop_early()) break;
      for (int i = 0; i < P; ++i) wt[i] = w[i] + tau * step[i];
      evaluate(wt, trial_owner, trial_counts, trial_sens);
      const double e = error(trial_counts);
      if (e < err || halvings == 7) {  // no descent at all: take the smallest step and go on
        w.swap(wt);
        owner.swap(trial_owner);
        counts.swap(trial_counts);
        sens.swap(trial_sens);
        err = e;
        break;
      }
      if (out.deviation <= kAim) break;
    }
  }
  return out;
}

/// Moves border cells from regions over their targets to regions under them, as a flow on the graph
/// of adjacent regions (potentials phi from L phi = counts - targets, L the Laplacian weighted by the
/// border links; region a hands w_ab (phi_a - phi_b) cells to b), for up to `rounds` rounds or until
/// every region is within its tolerance. Each region keeps a spanning tree rooted at its start; only a
/// leaf of it changes hands, and it hangs below the neighbour it joins, so every region stays connected
/// and keeps its start. O(cells) memory and time per round.
void rebalance(const Graph& G, std::vector<int>& owner, const std::vector<int>& st,
               const std::vector<double>& targets, int rounds, const std::function<bool()>& stop_early) {
  const int n = G.n, P = static_cast<int>(st.size());
  std::vector<int> parent(n, -1), kids(n, 0), depth(n, 0), counts(P, 0), queue;
  std::vector<char> is_start(n, 0);
  for (int s : st) is_start[s] = 1;
  for (int x = 0; x < n; ++x) ++counts[owner[x]];
  for (int round = 0; round < rounds && normalised_deviation(counts, targets) > 1.0; ++round) {
    if (stop_early && stop_early()) return;
    // spanning trees: BFS from every start inside its own region
    std::fill(parent.begin(), parent.end(), -1);
    std::fill(kids.begin(), kids.end(), 0);
    queue.assign(st.begin(), st.end());
    for (int s : st) parent[s] = s, depth[s] = 0;
    for (std::size_t h = 0; h < queue.size(); ++h) {
      const int u = queue[h];
      for (int v : G.nb[u])
        if (v >= 0 && parent[v] < 0 && owner[v] == owner[u]) {
          parent[v] = u, depth[v] = depth[u] + 1, ++kids[u];
          queue.push_back(v);
        }
    }
    // hangs x's children below other cells of x's region that are no deeper than x (so not below x);
    // true when x ends up a leaf. Depth grows along every tree edge, before and after.
    auto free_leaf = [&](int x) {
      for (int c : G.nb[x]) {
        if (kids[x] == 0) break;
        if (c < 0 || parent[c] != x || owner[c] != owner[x]) continue;
        for (int z : G.nb[c])
          if (z >= 0 && z != x && owner[z] == owner[x] && depth[z] <= depth[x]) {
            parent[c] = z, ++kids[z], --kids[x], depth[c] = depth[z] + 1;
            break;
          }
      }
      return kids[x] == 0;
    };
    // border links per pair of regions, and the cells along each border
    std::vector<double> links(static_cast<std::size_t>(P) * P, 0.0);
    std::vector<std::vector<int>> border(static_cast<std::size_t>(P) * P);
    for (int x = 0; x < n; ++x)
      for (int v : G.nb[x])
        if (v >= 0 && owner[v] != owner[x]) {
          const std::size_t ab = static_cast<std::size_t>(owner[x]) * P + owner[v];
          links[ab] += 1;
          if (border[ab].empty() || border[ab].back() != x) border[ab].push_back(x);
        }
    std::vector<double> excess(P), phi;
    for (int i = 0; i < P; ++i) excess[i] = counts[i] - targets[i];
    if (!solve_laplacian(links, excess, phi)) return;
    // highest potential first: a region receives its inflow before it hands on its outflow
    std::vector<int> order(P);
    for (int i = 0; i < P; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return phi[a] > phi[b]; });
    int moved = 0;
    for (int a : order)
      for (int b : order) {
        const std::size_t ab = static_cast<std::size_t>(a) * P + b;
        int want = static_cast<int>(std::lround(links[ab] * (phi[a] - phi[b])));
        if (a == b || want <= 0) continue;
        // b grows into a from their border, breadth first, taking leaves of a's tree only
        std::vector<int> q = border[ab], deferred;
        for (bool progress = true; want > 0 && progress;) {
          progress = false;
          for (std::size_t h = 0; h < q.size() && want > 0; ++h) {
            const int x = q[h];
            if (owner[x] != a) continue;
            int y = -1;
            for (int v : G.nb[x])
              if (v >= 0 && owner[v] == b) y = v;
            if (y < 0) continue;
            if (is_start[x] || (kids[x] > 0 && !free_leaf(x))) {
              deferred.push_back(x);
              continue;
            }
            --kids[parent[x]];
            owner[x] = b, parent[x] = y, ++kids[y], depth[x] = depth[y] + 1;
            --counts[a], ++counts[b], --want, ++moved;
            progress = true;
            for (int v : G.nb[x])
              if (v >= 0 && owner[v] == a) q.push_back(v);
          }
          q.swap(deferred);
          deferred.clear();
        }
      }
    if (moved == 0) return;
  }
}

/// Transfers for the small grids that the waves and the flow leave off their shares (issue 26: a
/// five-pointed star at 18 cells stayed 3 / 8 / 7 for 6 / 6 / 6). A move hands a cell x of region a to an
/// adjacent region b, together with the pieces of a that x alone holds to the rest (the components of a
/// without x other than the one that stays: the one with a's start, or the largest when the start is
/// movable), so a stays connected and non-empty and a dead-end branch can change hands at once (on the
/// star, a UAV's start cell and its one neighbour hang on a single link). A fixed start cell never moves
/// (`movable[a]`: the start only marks where a UAV from outside the area enters, and may go with its
/// cell). Simulated annealing on the sum of squared deviations from the targets, seeded, so the search
/// leaves local optima (5 / 6 / 7 on the star; single cells reach only 83 divisions from its 3 / 8 / 7,
/// none of them 6 / 6 / 6): a random cell and a random foreign neighbour; a move that adds d to the sum is
/// taken with probability exp(-d / T), T falling linearly to 0 over the budget. Ends when every count is
/// within one cell of its target, or after `work` cell visits; keeps the closest division seen
/// (normalised deviation, then the sum).
void transfer_search(const Graph& G, std::vector<int>& owner, const std::vector<int>& st,
                     const std::vector<char>& movable, const std::vector<double>& targets, double work,
                     std::uint64_t seed, const std::function<bool()>& stop_early) {
  constexpr double kT0 = 4.0;  // squared cells: a move away from balance adds 2 to 2 + 2 x the gap
  const int n = G.n, P = static_cast<int>(st.size());
  std::vector<char> fixed(n, 0);
  std::vector<int> fixed_start(P, -1);
  for (int a = 0; a < P; ++a)
    if (static_cast<std::size_t>(a) >= movable.size() || !movable[a])
      fixed[st[a]] = 1, fixed_start[a] = st[a];
  std::vector<int> counts(P, 0), seen(n, -1), piece(n, -1), moved;
  for (int x = 0; x < n; ++x) ++counts[owner[x]];
  auto squares = [&] {
    double q = 0;
    for (int a = 0; a < P; ++a) q += (counts[a] - targets[a]) * (counts[a] - targets[a]);
    return q;
  };
  // every count within one cell of its target: nothing closer exists
  auto exact = [&] {
    for (int a = 0; a < P; ++a)
      if (std::fabs(counts[a] - targets[a]) >= 1.0) return false;
    return true;
  };
  std::vector<int> best = owner;
  double best_dev = normalised_deviation(counts, targets), best_sq = squares();
  int stamp = 0;
  // the cells that go with x out of region a: x and every component of a without x but the one that stays
  std::vector<std::vector<int>> pieces;
  auto going = [&](int a, int x) {
    ++stamp;
    seen[x] = stamp;
    pieces.clear();
    for (int s : G.nb[x]) {
      if (s < 0 || owner[s] != a || seen[s] == stamp) continue;
      pieces.emplace_back(1, s);
      seen[s] = stamp;
      auto& q = pieces.back();
      for (std::size_t h = 0; h < q.size(); ++h)
        for (int v : G.nb[q[h]])
          if (v >= 0 && seen[v] != stamp && owner[v] == a) seen[v] = stamp, q.push_back(v);
      for (int c : q) piece[c] = static_cast<int>(pieces.size()) - 1;
      work -= static_cast<double>(q.size());
    }
    moved.assign(1, x);
    if (pieces.empty()) return false;  // x is all of a
    std::size_t stay = 0;
    if (fixed_start[a] >= 0) {
      stay = static_cast<std::size_t>(piece[fixed_start[a]]);
    } else {
      for (std::size_t k = 1; k < pieces.size(); ++k)
        if (pieces[k].size() > pieces[stay].size()) stay = k;
    }
    for (std::size_t k = 0; k < pieces.size(); ++k)
      if (k != stay) moved.insert(moved.end(), pieces[k].begin(), pieces[k].end());
    return true;
  };
  std::mt19937_64 rng(seed ^ 0x7f4a7c15f39cc060ULL);
  std::uniform_int_distribution<int> cell(0, n - 1), side(0, 3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double budget = work;
  for (long step = 0; work > 0 && !exact(); ++step) {
    if ((step & 1023) == 0 && stop_early && stop_early()) break;
    work -= 1;
    const int x = cell(rng), v = G.nb[x][side(rng)];
    if (v < 0 || fixed[x] || owner[v] == owner[x]) continue;
    const int a = owner[x], b = owner[v];
    if (!going(a, x)) continue;
    // change of the sum of (count - target)^2 when k cells go from a to b
    const double k = static_cast<double>(moved.size()), da = counts[a] - targets[a],
                 db = counts[b] - targets[b];
    const double delta = (db + k) * (db + k) - db * db + (da - k) * (da - k) - da * da;
    const double T = kT0 * std::max(0.0, work) / budget;
    if (delta > 0 && !(T > 0 && unit(rng) < std::exp(-delta / T))) continue;
    for (int c : moved) owner[c] = b;
    counts[a] -= static_cast<int>(moved.size());
    counts[b] += static_cast<int>(moved.size());
    const double dev = normalised_deviation(counts, targets), sq = squares();
    if (dev < best_dev || (dev == best_dev && sq < best_sq)) best_dev = dev, best_sq = sq, best = owner;
  }
  owner = std::move(best);
}

/// Counts, deviation and convergence of out.owner.
void finish(DivisionResult& out, const std::vector<double>& targets) {
  std::fill(out.counts.begin(), out.counts.end(), 0);
  for (int o : out.owner) ++out.counts[o];
  out.max_deviation = 0;
  for (std::size_t i = 0; i < targets.size(); ++i)
    out.max_deviation = std::max(out.max_deviation, std::fabs(out.counts[i] - targets[i]));
  out.converged = normalised_deviation(out.counts, targets) <= 1.0;
}

/// Keeps in `a` the division closer to the targets (normalised deviation; `a` on ties), `b` being a
/// later attempt on the same cells: iterations add up, and the later attempt's stop flag counts.
void keep_closer(DivisionResult& a, DivisionResult&& b, const std::vector<double>& targets) {
  const int iterations = a.iterations + b.iterations;
  const bool stopped = b.stopped;
  if (normalised_deviation(b.counts, targets) < normalised_deviation(a.counts, targets)) a = std::move(b);
  a.iterations = iterations;
  a.stopped = stopped;
}

/// The DARP iterations of Kapoutsis et al. (multiplicative correction of the evaluation matrices,
/// connectivity matrices), then the boundary polish; for grids of up to kClassicMaxWork.
void classic(const Graph& G, const DivisionInput& in, const std::vector<int>& st, DivisionResult& out,
             const std::function<void(double)>& progress) {
  const int n = G.n;
  const int P = static_cast<int>(st.size());
  // geodesic distances from each start
  std::vector<std::vector<double>> D(P);
  for (int i = 0; i < P; ++i) {
    D[i] = geodesic(G, st[i]);
    for (double& v : D[i]) v += 1.0;  // keep the start's evaluation positive
  }

  const double final_tol = classic_tolerance(n);
  std::mt19937_64 rng(in.seed ^ 0xda3e39cb94b95bdbULL);
  std::uniform_real_distribution<double> u01(0.0, 1.0);

  std::vector<int> best_owner;
  double best_dev = std::numeric_limits<double>::infinity();
  std::vector<int> owner(n), cand(n), counts(P), mark(n, -1), stack, dist_r, dist_q, queue, piece_r, piece_q;
  std::vector<double> M(static_cast<std::size_t>(P) * n);
  const int attempts = std::max(1, in.attempts);
  // large grids: cap the iterations so that one division stays within ~1e9 cell evaluations
  // (deterministic; the boundary polish below finishes the balance)
  const double per_iter = static_cast<double>(n) * P;
  const int max_iter = static_cast<int>(
      std::min<double>(std::max(1, in.max_iterations), std::max(50.0, 2e8 / (per_iter * attempts))));
  const long total_iters = static_cast<long>(attempts) * max_iter;
  int stamp = 0;

  bool stopped = false;
  for (int attempt = 0; attempt < attempts && !out.converged && !stopped; ++attempt) {
    const double tol = std::max(1.0, final_tol * (attempt + 1) / attempts);
    const double rand_level = 0.002 * (attempt + 1);
    for (int i = 0; i < P; ++i)
      for (int x = 0; x < n; ++x)
        M[static_cast<std::size_t>(x) * P + i] = D[i][x] * (1.0 + rand_level * (u01(rng) - 0.5));
    std::vector<double> lm(P, 0.0), step(P, 0.02);
    std::vector<int> last_sign(P, 0);
    int last_gain = 0;

    for (int it = 0; it < max_iter; ++it) {
      if (!best_owner.empty() && in.stop_early && in.stop_early()) {
        stopped = true;
        break;
      }
      ++out.iterations;
      if (progress) progress(static_cast<double>(out.iterations) / total_iters);
      // assignment: argmin over the corrected evaluation matrices
      std::vector<double> m(P);
      for (int i = 0; i < P; ++i) m[i] = std::exp(lm[i]);
      for (int x = 0; x < n; ++x) {
        int bi = 0;
        const double* Mx = M.data() + static_cast<std::size_t>(x) * P;  // x-major: one cache line
        double bv = m[0] * Mx[0];
        for (int i = 1; i < P; ++i) {
          const double v = m[i] * Mx[i];
          if (v < bv) bv = v, bi = i;
        }
        owner[x] = bi;
      }
      for (int i = 0; i < P; ++i) owner[st[i]] = i;
      std::fill(counts.begin(), counts.end(), 0);
      for (int x = 0; x < n; ++x) ++counts[owner[x]];

      // connectivity
      std::vector<char> disconnected(P, 0);
      bool any_disc = false;
      for (int i = 0; i < P; ++i) {
        ++stamp;
        const int c = main_piece(G, owner, i, st[i], mark, stamp, stack);
        if (c < counts[i]) {
          disconnected[i] = 1;
          any_disc = true;
          piece_r.clear();
          piece_q.clear();
          for (int x = 0; x < n; ++x) {
            if (owner[x] != i) continue;
            (mark[x] == stamp ? piece_r : piece_q).push_back(x);
          }
          // connectivity matrix C_i = d(main piece) - d(other pieces), scaled to [1 - v, 1 + v]
          bfs(G, piece_r, dist_r, queue);
          bfs(G, piece_q, dist_q, queue);
          double lo = std::numeric_limits<double>::infinity(), hi = -lo;
          for (int x = 0; x < n; ++x) {
            const double c2 = static_cast<double>(dist_r[x]) - dist_q[x];
            lo = std::min(lo, c2), hi = std::max(hi, c2);
          }
          if (hi > lo) {
            double* Mi = M.data() + i;
            for (int x = 0; x < n; ++x) {
              const double c2 = static_cast<double>(dist_r[x]) - dist_q[x];
              Mi[static_cast<std::size_t>(x) * P] *=
                  (c2 - lo) * (2 * kConnVariation / (hi - lo)) + (1 - kConnVariation);
            }
          }
        }
      }

      // the best connected division so far (disconnected pieces handed to neighbours)
      cand = owner;
      if (any_disc) repair(G, cand, st);
      std::vector<int> cc(P, 0);
      for (int x = 0; x < n; ++x) ++cc[cand[x]];
      double dev = 0;
      for (int i = 0; i < P; ++i) dev = std::max(dev, std::fabs(cc[i] - in.targets[i]));
      if (dev < best_dev) {
        best_dev = dev;
        best_owner = cand;
        last_gain = it;
      }
      if (it - last_gain > std::max(std::min(400, max_iter / 2), max_iter / 8))
        break;  // stagnating: next attempt
      if (dev <= tol) {
        out.converged = dev <= final_tol;
        break;
      }

      // multiplicative correction toward the share (sign-adaptive step per participant)
      for (int i = 0; i < P; ++i) {
        const double err = cc[i] - in.targets[i];  // as repaired: what the UAV would fly
        const int sign = err > 0.5 ? 1 : (err < -0.5 ? -1 : 0);
        if (sign != 0 && last_sign[i] != 0 && sign != last_sign[i])
          step[i] = std::max(1e-6, step[i] * 0.5);
        else if (sign != 0)
          step[i] = std::min(0.1, step[i] * 1.15);
        if (sign != 0) last_sign[i] = sign;
        if (std::fabs(err) > 4 * tol) {
          // coarse phase: damped Newton step (a region's size goes roughly with m^-2)
          lm[i] += std::clamp(0.25 * std::log((cc[i] + 1.0) / (in.targets[i] + 1.0)), -0.05, 0.05);
        } else {
          const double scale = std::max(1.0, 0.05 * in.targets[i]);
          lm[i] += step[i] * std::clamp(err / scale, -1.0, 1.0);
        }
      }
    }
  }

  out.owner = best_owner;
  if (best_dev > final_tol) polish(G, out.owner, st, in.targets, D, final_tol, 4 * n);
  out.stopped = stopped;
  finish(out, in.targets);
}

}  // namespace

double tolerance(double target) { return std::max(1.0, 0.02 * target); }

DivisionResult divide(const grid::Grid& g, const DivisionInput& in,
                      const std::function<void(double)>& progress) {
  DivisionResult out;
  std::vector<int> lid;
  const Graph G = build_graph(g, in.cells, lid);
  const int n = G.n;
  const int P = static_cast<int>(in.starts.size());
  std::vector<int> st(P);
  for (int i = 0; i < P; ++i) st[i] = lid[in.starts[i]];
  out.owner.assign(n, 0);
  out.counts.assign(P, 0);
  if (P == 0 || n == 0) return out;
  if (P == 1) {
    out.counts[0] = n;
    out.converged = true;
    out.max_deviation = std::fabs(n - in.targets[0]);
    return out;
  }

  const bool classic_first = static_cast<double>(n) * P <= kClassicMaxWork;
  if (classic_first) {
    classic(G, in, st, out, progress);
    if (out.converged || out.stopped) return out;
  }
  // waves: each iteration is one pass over the cells, whatever the number of participants
  const int max_iter =
      static_cast<int>(std::min<double>(std::max(1, in.max_iterations), std::max(100.0, 2e8 / n)));
  Balanced b = balance_waves(G, st, in.targets, max_iter, in.stop_early, progress);
  DivisionResult waves;
  waves.owner = std::move(b.owner);
  waves.counts.assign(P, 0);
  waves.iterations = b.iterations;
  finish(waves, in.targets);
  if (!waves.converged) {
    rebalance(G, waves.owner, st, in.targets, kRebalanceRounds, in.stop_early);
    finish(waves, in.targets);
  }
  if (classic_first) {
    keep_closer(out, std::move(waves), in.targets);
  } else {
    out = std::move(waves);
    if (!out.converged && !(in.stop_early && in.stop_early())) {
      // the waves' weights can stall on unequal shares (bench/results/darp-scale.md): the classic
      // iterations (capped at ~2e8 cell evaluations) get their turn, and the closer division is kept
      DivisionResult c;
      c.owner.assign(n, 0);
      c.counts.assign(P, 0);
      classic(G, in, st, c, progress);
      keep_closer(out, std::move(c), in.targets);
    }
  }
  if (!out.converged && n <= kTransferMaxCells && !(in.stop_early && in.stop_early())) {
    transfer_search(G, out.owner, st, in.movable, in.targets, kTransferWork, in.seed, in.stop_early);
    finish(out, in.targets);
  }
  return out;
}

}  // namespace uavcover::darp
