// Method::Polynomial (Mondinelli 2025 §4.1): per axis one polynomial of degree P = 2m + 1 per segment
// between consecutive waypoints, in s = (t - t0) / T on [0, 1]. Each segment is the Hermite polynomial of
// the positions and the first m derivatives at its two waypoints; those derivatives at the interior
// waypoints are the unknowns, and derivatives m + 1 .. 2m continuous there are as many equations (a
// block-tridiagonal system, m x m blocks); the first m derivatives are 0 at both ends (rest). So the
// trajectory is C^(P-1) at every waypoint and passes through each (the interpolating spline of degree
// P; for P = 5 the one of least integrated squared jerk). Durations start at length / v_mean. Scaling
// every duration by the worst factor k a segment needs meets every bound at once (scaling time by k
// divides v by k and a by k^2); usually much shorter is stretching only the segments whose polynomial
// breaks a bound, with their neighbours, round after round, then shrinking back those with room to
// spare: the shorter of the two is kept.
#include "trajectory/polynomial.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "trajectory/vec3.hpp"
#include "uavcover/error.hpp"

namespace uavcover::trajectory::detail {
namespace {

using Coeffs = std::array<double, kMaxOrder + 1>;

constexpr int kSamples = 24;           // per segment, before the golden-section refinement of each peak
constexpr int kRefine = 40;            // golden-section steps: the peak's place to 1e-9 of the segment
constexpr int kLocalRounds = 40;       // most rounds of stretching the segments that break a bound
constexpr double kMaxStep = 2.0;       // most a duration grows in one round
constexpr int kShrinkRounds = 6;       // rounds of shrinking the stretched segments with room to spare
constexpr double kShrinkBelow = 0.98;  // ... those whose worst share of a bound is below this
constexpr double kShrinkStep = 0.85;   // ... by at most this factor a round
constexpr double kMinSegmentS = 0.05;  // shortest initial duration (a leg of millimetres)
constexpr double kTol = 1e-9;          // relative slack of "holds"

/// j! / (j - d)!
double falling(int j, int d) {
  double r = 1;
  for (int i = 0; i < d; ++i) r *= j - i;
  return r;
}

/// The d-th derivative in s of sum c_j s^j (j <= P) at s.
double poly_d(const Coeffs& c, int P, int d, double s) {
  double r = 0;
  for (int j = P; j >= d; --j) r = r * s + c[static_cast<std::size_t>(j)] * falling(j, d);
  return r;
}

/// Solves A X = B in place (A n x n, B n x k, row-major) by Gaussian elimination with partial pivoting.
void solve_dense(std::vector<double> A, int n, std::vector<double>& B, int k) {
  auto a = [&](int r, int c) -> double& { return A[static_cast<std::size_t>(r * n + c)]; };
  auto b = [&](int r, int c) -> double& { return B[static_cast<std::size_t>(r * k + c)]; };
  for (int col = 0; col < n; ++col) {
    int piv = col;
    for (int r = col + 1; r < n; ++r)
      if (std::abs(a(r, col)) > std::abs(a(piv, col))) piv = r;
    if (!(std::abs(a(piv, col)) > 0)) throw std::logic_error("trajectory: singular polynomial system");
    for (int c = 0; c < n; ++c) std::swap(a(col, c), a(piv, c));
    for (int c = 0; c < k; ++c) std::swap(b(col, c), b(piv, c));
    for (int r = col + 1; r < n; ++r) {
      const double f = a(r, col) / a(col, col);
      if (f == 0) continue;
      for (int c = col; c < n; ++c) a(r, c) -= f * a(col, c);
      for (int c = 0; c < k; ++c) b(r, c) -= f * b(col, c);
    }
  }
  for (int r = n - 1; r >= 0; --r)
    for (int c = 0; c < k; ++c) {
      double v = b(r, c);
      for (int j = r + 1; j < n; ++j) v -= a(r, j) * b(j, c);
      b(r, c) = v / a(r, r);
    }
}

/// The Hermite basis of degree P on [0, 1]: c = H q for the data q = (p(0), p'(0) .. p^(m)(0), p(1),
/// p'(1) .. p^(m)(1)) (derivatives in s), and the rows giving derivative d at s = 0 and s = 1 from q.
struct Hermite {
  int P = 0, m = 0;
  std::vector<double> H;                    // (P + 1) x (P + 1)
  std::vector<std::vector<double>> G0, G1;  // [d][i]: d-th derivative at 0 / at 1 per datum i

  explicit Hermite(int order) : P(order), m((order - 1) / 2) {
    const int n = P + 1;
    std::vector<double> M(static_cast<std::size_t>(n * n), 0.0);
    for (int k = 0; k <= m; ++k) {
      M[static_cast<std::size_t>(k * n + k)] = falling(k, k);
      for (int j = k; j <= P; ++j) M[static_cast<std::size_t>((m + 1 + k) * n + j)] = falling(j, k);
    }
    H.assign(static_cast<std::size_t>(n * n), 0.0);
    for (int i = 0; i < n; ++i) H[static_cast<std::size_t>(i * n + i)] = 1.0;
    solve_dense(M, n, H, n);
    G0.assign(static_cast<std::size_t>(P + 1), std::vector<double>(static_cast<std::size_t>(n), 0.0));
    G1 = G0;
    for (int d = 0; d <= P; ++d)
      for (int i = 0; i < n; ++i) {
        G0[static_cast<std::size_t>(d)][static_cast<std::size_t>(i)] =
            falling(d, d) * H[static_cast<std::size_t>(d * n + i)];
        double g = 0;
        for (int j = d; j <= P; ++j) g += falling(j, d) * H[static_cast<std::size_t>(j * n + i)];
        G1[static_cast<std::size_t>(d)][static_cast<std::size_t>(i)] = g;
      }
  }
};

/// The segments through `w` with durations `T`: the spline of degree P, at rest at both ends.
std::vector<PolySegment> solve_spline(const Hermite& h, const std::vector<Vec3>& w,
                                      const std::vector<double>& T) {
  const int m = h.m, n = h.P + 1;
  const std::size_t N = T.size();
  // u[j][k * 3 + axis]: the (k + 1)-th time derivative at waypoint j; 0 at both ends
  std::vector<std::vector<double>> u(N + 1, std::vector<double>(static_cast<std::size_t>(m * 3), 0.0));
  if (N >= 2) {
    const std::size_t ni = N - 1;  // interior waypoints 1 .. N - 1
    const auto mm = static_cast<std::size_t>(m * m), m3 = static_cast<std::size_t>(m * 3);
    std::vector<std::vector<double>> A(ni, std::vector<double>(mm)), B = A, C = A;
    std::vector<std::vector<double>> r(ni, std::vector<double>(m3));
    for (std::size_t i = 0; i < ni; ++i) {
      const std::size_t j = i + 1;
      const double Ta = T[j - 1], Tb = T[j], Tm = (Ta + Tb) / 2;
      for (int e = 0; e < m; ++e) {
        const auto d = static_cast<std::size_t>(m + 1 + e);
        const double rs = std::pow(Tm, static_cast<double>(d));  // the equation in units of Tm
        const auto& g1 = h.G1[d];
        const auto& g0 = h.G0[d];
        for (int k = 1; k <= m; ++k) {
          const double pa = std::pow(Ta, static_cast<double>(k) - static_cast<double>(d)) * rs;
          const double pb = std::pow(Tb, static_cast<double>(k) - static_cast<double>(d)) * rs;
          const auto at = static_cast<std::size_t>(e * m + k - 1);
          A[i][at] = g1[static_cast<std::size_t>(k)] * pa;
          B[i][at] = g1[static_cast<std::size_t>(m + 1 + k)] * pa - g0[static_cast<std::size_t>(k)] * pb;
          C[i][at] = -g0[static_cast<std::size_t>(m + 1 + k)] * pb;
        }
        const double ia = rs / std::pow(Ta, static_cast<double>(d)),
                     ib = rs / std::pow(Tb, static_cast<double>(d));
        for (std::size_t ax = 0; ax < 3; ++ax)
          r[i][static_cast<std::size_t>(e * 3) + ax] =
              -(ia * (g1[0] * w[j - 1][ax] + g1[static_cast<std::size_t>(m + 1)] * w[j][ax]) -
                ib * (g0[0] * w[j][ax] + g0[static_cast<std::size_t>(m + 1)] * w[j + 1][ax]));
      }
    }
    // block Thomas: X[i] = Bp[i]^-1 [C[i] | rp[i]], then back substitution
    std::vector<std::vector<double>> X(ni);
    std::vector<double> Bp = B[0], rp = r[0];
    const int cols = m + 3;
    for (std::size_t i = 0;; ++i) {
      std::vector<double> rhs(static_cast<std::size_t>(m * cols));
      for (int row = 0; row < m; ++row) {
        for (int c = 0; c < m; ++c)
          rhs[static_cast<std::size_t>(row * cols + c)] = C[i][static_cast<std::size_t>(row * m + c)];
        for (int c = 0; c < 3; ++c)
          rhs[static_cast<std::size_t>(row * cols + m + c)] = rp[static_cast<std::size_t>(row * 3 + c)];
      }
      solve_dense(Bp, m, rhs, cols);
      X[i] = std::move(rhs);
      if (i + 1 == ni) break;
      // Bp' = B[i+1] - A[i+1] X_C, rp' = r[i+1] - A[i+1] X_r
      Bp = B[i + 1];
      rp = r[i + 1];
      for (int row = 0; row < m; ++row)
        for (int q = 0; q < m; ++q) {
          const double a = A[i + 1][static_cast<std::size_t>(row * m + q)];
          for (int c = 0; c < m; ++c)
            Bp[static_cast<std::size_t>(row * m + c)] -= a * X[i][static_cast<std::size_t>(q * cols + c)];
          for (int c = 0; c < 3; ++c)
            rp[static_cast<std::size_t>(row * 3 + c)] -= a * X[i][static_cast<std::size_t>(q * cols + m + c)];
        }
    }
    for (std::size_t i = ni; i-- > 0;) {
      auto& ui = u[i + 1];
      const auto& next = u[i + 2];
      for (int row = 0; row < m; ++row)
        for (int c = 0; c < 3; ++c) {
          double v = X[i][static_cast<std::size_t>(row * cols + m + c)];
          for (int q = 0; q < m; ++q)
            v -= X[i][static_cast<std::size_t>(row * cols + q)] * next[static_cast<std::size_t>(q * 3 + c)];
          ui[static_cast<std::size_t>(row * 3 + c)] = v;
        }
    }
  }
  std::vector<PolySegment> out(N);
  double t = 0;
  for (std::size_t i = 0; i < N; ++i) {
    PolySegment& g = out[i];
    g.t0 = t;
    g.duration = T[i];
    g.length = norm(sub(w[i + 1], w[i]));
    t += T[i];
    for (std::size_t ax = 0; ax < 3; ++ax) {
      std::vector<double> q(static_cast<std::size_t>(n), 0.0);
      q[0] = w[i][ax];
      q[static_cast<std::size_t>(m + 1)] = w[i + 1][ax];
      for (int k = 1; k <= m; ++k) {
        const double tk = std::pow(T[i], k);
        q[static_cast<std::size_t>(k)] = tk * u[i][static_cast<std::size_t>((k - 1) * 3) + ax];
        q[static_cast<std::size_t>(m + 1 + k)] = tk * u[i + 1][static_cast<std::size_t>((k - 1) * 3) + ax];
      }
      for (int j = 0; j < n; ++j) {
        double c = 0;
        for (int l = 0; l < n; ++l)
          c += h.H[static_cast<std::size_t>(j * n + l)] * q[static_cast<std::size_t>(l)];
        g.c[ax][static_cast<std::size_t>(j)] = c;
      }
    }
  }
  return out;
}

/// The d-th time derivative of segment g at s (per axis).
Vec3 deriv(const PolySegment& g, int P, int d, double s) {
  const double f = 1.0 / std::pow(g.duration, d);
  return {poly_d(g.c[0], P, d, s) * f, poly_d(g.c[1], P, d, s) * f, poly_d(g.c[2], P, d, s) * f};
}

/// The largest value of f on [0, 1]: sampled, then each local maximum from `floor` up refined by
/// golden section.
double peak(const std::function<double(double)>& f, double floor = -1e300) {
  std::array<double, kSamples + 1> v{};
  for (int i = 0; i <= kSamples; ++i) v[static_cast<std::size_t>(i)] = f(static_cast<double>(i) / kSamples);
  double best = *std::max_element(v.begin(), v.end());
  constexpr double g = 0.6180339887498949;
  for (int i = 0; i <= kSamples; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if ((i > 0 && v[k] < v[k - 1]) || (i < kSamples && v[k] < v[k + 1]) || v[k] < floor) continue;
    double lo = std::max(0.0, (i - 1.0) / kSamples), hi = std::min(1.0, (i + 1.0) / kSamples);
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = f(x1), f2 = f(x2);
    for (int it = 0; it < kRefine; ++it) {
      if (f1 < f2) {
        lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = f(x2);
      } else {
        hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = f(x1);
      }
    }
    best = std::max({best, f1, f2});
  }
  return best;
}

/// The stretch that would bring g within the bounds alone (v scales as 1/k, a as 1/k^2; below 1 a
/// shrink would keep them): from the worst
/// share of a bound its velocity and its acceleration reach (|v| over v_max, a component over v_max or
/// over v_min; the same for a). Peaks sampled below `refine_from` of a bound are not refined (a polynomial
/// of degree <= 7 hardly rises that much between two of kSamples samples; the report refines all).
double factor(const PolySegment& g, int P, const LimitReport& b, double refine_from = 0.9) {
  auto share = [](const Vec3& x, double lo, double hi) {
    double r = norm(x) / hi;
    for (const double c : x) r = std::max({r, c / hi, c / lo});
    return r;
  };
  const double rv = peak([&](double s) { return share(deriv(g, P, 1, s), b.v_min, b.v_max); }, refine_from);
  const double ra = peak([&](double s) { return share(deriv(g, P, 2, s), b.a_min, b.a_max); }, refine_from);
  return std::max(rv, std::sqrt(ra));
}

/// The report's extremes (every component, |v|, |a|, |jerk|, each peak refined), the stretched
/// segments and whether every bound holds.
void extremes(const std::vector<PolySegment>& segments, const std::vector<double>& T,
              const std::vector<double>& T0, int P, LimitReport& rep) {
  rep.v_lo = rep.a_lo = 1e300;
  rep.v_hi = rep.a_hi = -1e300;
  rep.speed_max = rep.accel_max = rep.jerk_max = 0;
  rep.stretched = 0;
  for (std::size_t i = 0; i < T.size(); ++i) {
    const PolySegment& g = segments[i];
    if (T[i] > T0[i] * (1 + 1e-6)) ++rep.stretched;
    auto top = [&](int d, double sign) {  // sign 1: the largest component, -1: the smallest
      return sign * peak([&](double s) {
               const Vec3 x = deriv(g, P, d, s);
               return std::max({sign * x[0], sign * x[1], sign * x[2]});
             });
    };
    rep.v_hi = std::max(rep.v_hi, top(1, 1));
    rep.v_lo = std::min(rep.v_lo, top(1, -1));
    rep.a_hi = std::max(rep.a_hi, top(2, 1));
    rep.a_lo = std::min(rep.a_lo, top(2, -1));
    rep.speed_max = std::max(rep.speed_max, peak([&](double s) { return norm(deriv(g, P, 1, s)); }));
    rep.accel_max = std::max(rep.accel_max, peak([&](double s) { return norm(deriv(g, P, 2, s)); }));
    rep.jerk_max = std::max(rep.jerk_max, peak([&](double s) { return norm(deriv(g, P, 3, s)); }));
  }
  const double up = 1 + kTol;
  rep.hold = rep.v_hi <= rep.v_max * up && rep.speed_max <= rep.v_max * up && rep.v_lo >= rep.v_min * up &&
             rep.a_hi <= rep.a_max * up && rep.accel_max <= rep.a_max * up && rep.a_lo >= rep.a_min * up;
}

}  // namespace

LimitReport polynomial_bounds(const Limits& limits, const Options& options) {
  if (options.order < kMinOrder || options.order > kMaxOrder || options.order % 2 == 0)
    throw InputError("order", fmt::format("must be 3, 5 or 7 (an odd degree: as many conditions at the ends "
                                          "as the waypoints' continuity leaves), got {}",
                                          options.order));
  LimitReport b;
  b.v_max = limits.v_max;
  b.a_max = limits.a_max;
  b.v_min = std::isnan(options.v_min) ? -limits.v_max : options.v_min;
  b.a_min = std::isnan(options.a_min) ? -limits.a_max : options.a_min;
  if (!std::isfinite(b.v_min) || b.v_min > b.v_max)
    throw InputError("v_min",
                     fmt::format("{} m/s is above v_max {} m/s: no velocity meets both", b.v_min, b.v_max));
  if (!(b.v_min < 0))
    throw InputError("v_min",
                     fmt::format("must be negative, got {} m/s: the flight returns home, so it flies "
                                 "every axis both ways (the thesis: v_min -5 m/s, v_max 5 m/s)",
                                 b.v_min));
  if (!std::isfinite(b.a_min) || b.a_min > b.a_max)
    throw InputError("a_min", fmt::format("{} m/s^2 is above a_max {} m/s^2: no acceleration meets both",
                                          b.a_min, b.a_max));
  if (!(b.a_min < 0))
    throw InputError("a_min", fmt::format("must be negative, got {} m/s^2: stopping needs a negative "
                                          "acceleration on every axis flown",
                                          b.a_min));
  if (!std::isfinite(options.v_mean) || options.v_mean < 0 || options.v_mean > limits.v_max)
    throw InputError("v_mean", fmt::format("must be in (0, v_max = {} m/s] (0 = v_max), got {}", limits.v_max,
                                           options.v_mean));
  return b;
}

PolyTrajectory polynomial(const std::vector<Vec3>& w, const Limits& limits, const Options& options) {
  PolyTrajectory out;
  LimitReport& rep = out.report;
  rep = polynomial_bounds(limits, options);
  const int P = options.order;
  const Hermite h(P);
  const double v_mean = options.v_mean > 0 ? options.v_mean : limits.v_max;
  const std::size_t n = w.size() - 1;
  std::vector<double> T0(n);
  for (std::size_t i = 0; i < n; ++i) T0[i] = std::max(norm(sub(w[i + 1], w[i])) / v_mean, kMinSegmentS);
  auto total = [](const std::vector<double>& d) {
    double s = 0;
    for (const double x : d) s += x;
    return s;
  };
  // the segments of durations d and each one's stretch factor; true when every bound holds
  std::vector<double> f(n);
  auto solve = [&](const std::vector<double>& d) {
    out.segments = solve_spline(h, w, d);
    ++rep.iterations;
    double worst = 0;
    for (std::size_t i = 0; i < n; ++i) worst = std::max(worst, f[i] = factor(out.segments[i], P, rep));
    return worst;
  };
  // always within the bounds: every duration by the worst factor of the mean-speed allocation
  const double worst0 = solve(T0);
  std::vector<double> best = T0;
  if (worst0 > 1 + kTol) {
    for (auto& t : best) t *= worst0 * (1 + kTol);
    // usually much shorter: stretch only where a bound breaks, a segment with its two neighbours (a
    // corner's polynomial is shaped by both legs; alone, a stretched segment can make its short neighbour
    // swing out), by twice the excess (fewer rounds), at most kMaxStep a round; given up once it takes
    // longer than the uniform stretch
    std::vector<double> T = T0;
    for (int round = 0; round < kLocalRounds; ++round) {
      std::vector<double> g(n, 1.0);
      for (std::size_t i = 0; i < n; ++i)
        if (f[i] > 1 + kTol)
          for (std::size_t j = i == 0 ? 0 : i - 1; j <= std::min(i + 1, n - 1); ++j)
            g[j] = std::max(g[j], std::min(2 * f[i] - 1, kMaxStep));
      for (std::size_t i = 0; i < n; ++i) T[i] *= g[i];
      if (total(T) >= total(best)) break;
      if (solve(T) <= 1 + kTol) {
        best = T;
        break;
      }
    }
    // the stretched segments with room to spare shrink back towards length / v_mean, each round kept only
    // while every bound still holds
    bool holds = solve(best) <= 1 + kTol;  // (the uniform stretch does by construction, to rounding)
    for (int round = 0; holds && round < kShrinkRounds; ++round) {
      T = best;
      bool any = false;
      for (std::size_t i = 0; i < n; ++i)
        if (f[i] < kShrinkBelow && T[i] > T0[i]) {
          T[i] = std::max(T0[i], T[i] * std::max(f[i], kShrinkStep));
          any = true;
        }
      holds = any && solve(T) <= 1 + kTol;
      if (holds) best = T;
    }
  }
  out.segments = solve_spline(h, w, best);
  std::vector<double>& T = best;
  extremes(out.segments, T, T0, P, rep);
  if (!rep.hold) {
    // a peak the rounds' sampling missed: every duration by the exact worst factor
    double worst = 1;
    for (const auto& g : out.segments) worst = std::max(worst, factor(g, P, rep, -1e300));
    for (auto& t : T) t *= worst * (1 + kTol);
    out.segments = solve_spline(h, w, T);
    ++rep.iterations;
    extremes(out.segments, T, T0, P, rep);
  }
  if (!rep.hold) {
    const double up = 1 + kTol;
    const char* broken = rep.v_hi > rep.v_max * up || rep.speed_max > rep.v_max * up   ? "v_max"
                         : rep.v_lo < rep.v_min * up                                   ? "v_min"
                         : rep.a_hi > rep.a_max * up || rep.accel_max > rep.a_max * up ? "a_max"
                                                                                       : "a_min";
    throw InputError(broken, fmt::format("the polynomial trajectory cannot keep it: after {} solves the "
                                         "velocity spans [{}, {}] m/s (|v| <= {}), the acceleration [{}, {}] "
                                         "m/s^2 (|a| <= {})",
                                         rep.iterations, rep.v_lo, rep.v_hi, rep.speed_max, rep.a_lo,
                                         rep.a_hi, rep.accel_max));
  }
  return out;
}

Sample polynomial_at(const std::vector<PolySegment>& segments, int order, double t) {
  Sample s;
  const double end = segments.back().t0 + segments.back().duration;
  t = std::clamp(t, 0.0, end);
  s.t = t;
  auto it = std::upper_bound(segments.begin(), segments.end(), t,
                             [](double x, const PolySegment& g) { return x < g.t0; });
  const std::size_t k = it == segments.begin() ? 0 : static_cast<std::size_t>(it - segments.begin()) - 1;
  const PolySegment& g = segments[k];
  const double x = std::clamp((t - g.t0) / g.duration, 0.0, 1.0);
  s.p = deriv(g, order, 0, x);
  s.v = deriv(g, order, 1, x);
  s.a = deriv(g, order, 2, x);
  s.piece = static_cast<int>(k);
  return s;
}

}  // namespace uavcover::trajectory::detail
