#include "planners/darp/placement.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace uavcover::grid {

namespace {

struct Candidate {
  double sx = 0, sy = 0, th = 0;
  Score s;
};

constexpr double kPlacementWork = 2e7;
constexpr long kMinLargeEvaluations = 64;

double wrap(double v, double period) {
  v = std::fmod(v, period);
  return v < 0 ? v + period : v;
}

}  // namespace

PlacementResult optimise_placement(const Prepared& prep, const PlacementOptions& opt,
                                   const std::function<void(double)>& progress) {
  const double dn = 2 * prep.ds;
  long evals = 0;
  long budget = std::max(1, opt.evaluations);
  bool stopped = false;  // stop_early() said so: the budget ends here
  auto evaluate = [&](double sx, double sy, double th) {
    ++evals;
    if (evals % 8 == 0 && progress) progress(std::min(1.0, static_cast<double>(evals) / budget));
    // before every evaluation (a clock read): at 1M mega-cells one evaluation is a pass over the whole
    // grid (~60 ms of CPU), and checking every 8th let a time limit overshoot by half a second or more
    if (evals > 1 && !stopped && opt.stop_early && opt.stop_early()) stopped = true, budget = evals;
    Candidate c{sx, sy, th, score(prep, rasterize(prep, sx, sy, th), opt.weights)};
    if (opt.on_evaluation) opt.on_evaluation(sx, sy, th, c.s);
    return c;
  };
  // better: higher J, then more free cells, then the earlier candidate (deterministic)
  auto better = [](const Candidate& a, const Candidate& b) {
    if (a.s.key != b.s.key) return a.s.key > b.s.key;
    return a.s.free_cells > b.s.free_cells;
  };

  // pool of the best distinct candidates for the final re-ranking
  std::vector<Candidate> pool;
  const std::size_t pool_size = static_cast<std::size_t>(std::max(1, opt.rerank));
  auto offer = [&](const Candidate& c) {
    for (auto& p : pool) {
      // the same grid seen twice (equal cell count and coverage) counts once
      if (p.s.free_cells == c.s.free_cells && p.s.coverage == c.s.coverage &&
          p.s.components == c.s.components) {
        if (better(c, p)) p = c;
        return;
      }
    }
    if (pool.size() < pool_size) {
      pool.push_back(c);
    } else {
      auto worst = std::min_element(pool.begin(), pool.end(),
                                    [&](const Candidate& a, const Candidate& b) { return better(b, a); });
      if (better(c, *worst)) *worst = c;
    }
  };
  Candidate best = evaluate(0, 0, 0);
  offer(best);
  // large grids: at most about kPlacementWork cell rasterisations in all (a placement's J and coverage
  // terms change little on a grid of many cells, and one evaluation costs a pass over all of them)
  if (best.s.free_cells > 0)
    budget = std::min(
        budget, std::max<long>(kMinLargeEvaluations, static_cast<long>(kPlacementWork / best.s.free_cells)));
  if (opt.optimise && budget > 1) {
    std::mt19937_64 rng(opt.seed ^ 0x9e3779b97f4a7c15ULL);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::normal_distribution<double> gauss(0.0, 1.0);

    // coarse pre-scan: about 35 % of the budget on a regular (theta, sx, sy) lattice
    const long scan_budget = std::max<long>(1, static_cast<long>(0.35 * budget));
    int ns = 1, nt = 1;
    while (true) {  // grow the lattice keeping ~ 4 theta steps per shift step squared
      const int nt2 = std::max(1, static_cast<int>(std::lround(4.5 * (ns + 1) * 1.0)));
      if (static_cast<long>(nt2) * (ns + 1) * (ns + 1) > scan_budget) break;
      ++ns;
      nt = nt2;
    }
    while (static_cast<long>(nt + 1) * ns * ns <= scan_budget) ++nt;
    std::vector<Candidate> scanned;
    scanned.reserve(static_cast<std::size_t>(nt) * ns * ns);
    for (int t = 0; t < nt && !stopped; ++t)
      for (int i = 0; i < ns && !stopped; ++i)
        for (int j = 0; j < ns && !stopped; ++j) {
          Candidate c = evaluate(dn * i / ns, dn * j / ns, 90.0 * t / nt);
          if (better(c, best)) best = c;
          offer(c);
          scanned.push_back(c);
        }
    std::stable_sort(scanned.begin(), scanned.end(), better);
    // restart points: the best pre-scan candidates with distinct rotations
    std::vector<Candidate> starts;
    const std::size_t restarts = 3;
    for (const auto& c : scanned) {
      bool distinct = true;
      for (const auto& s : starts) {
        const double d = std::fabs(s.th - c.th);
        if (std::min(d, 90.0 - d) < 45.0 / nt + 1e-9) distinct = false;
      }
      if (distinct) starts.push_back(c);
      if (starts.size() == restarts) break;
    }
    if (starts.empty()) starts.push_back(best);

    const long left = budget - evals;
    const long per = std::max<long>(1, left / static_cast<long>(starts.size()));
    const double theta_step = 90.0 / nt, shift_step = dn / ns;
    for (const auto& s0 : starts) {
      Candidate cur = s0;
      for (long k = 0; k < per && evals < budget; ++k) {
        const double f = static_cast<double>(k) / per;  // annealing progress
        const double T = 0.01 * std::pow(1e-3, f);      // temperature on J (J in [0, 1))
        const double scale = 1.0 - 0.9 * f;
        double sx = cur.sx, sy = cur.sy, th = cur.th;
        const double pick = u01(rng);
        if (pick < 0.4) {
          th += gauss(rng) * theta_step * scale;
        } else if (pick < 0.8) {
          sx += gauss(rng) * shift_step * scale;
          sy += gauss(rng) * shift_step * scale;
        } else {
          th += gauss(rng) * theta_step * scale * 0.5;
          sx += gauss(rng) * shift_step * scale * 0.5;
          sy += gauss(rng) * shift_step * scale * 0.5;
        }
        Candidate next = evaluate(wrap(sx, dn), wrap(sy, dn), wrap(th, 90.0));
        const double delta = next.s.key - cur.s.key;  // maximisation: accept improvements always
        offer(next);
        if (delta >= 0 || u01(rng) < std::exp(delta / T)) cur = next;
        if (better(cur, best)) best = cur;
      }
    }
  }
  PlacementResult out;
  // the re-ranking costs two passes over the grid per candidate (2 s of 24 at 1M mega-cells on a loaded
  // machine): a time limit ends it too, keeping the best re-ranked so far (the search's best when none)
  if (!stopped && opt.rerank > 1 && pool.size() > 1) {
    std::stable_sort(pool.begin(), pool.end(), better);
    double best_key = -std::numeric_limits<double>::infinity();
    for (const auto& c : pool) {
      if (opt.stop_early && opt.stop_early()) break;
      const double cov = coverage_proxy(prep, rasterize(prep, c.sx, c.sy, c.th));
      const double key = c.s.key + opt.weights.coverage_weight * (cov - c.s.coverage);
      if (key > best_key + 1e-12) best_key = key, best = c, out.coverage = cov;
    }
  }
  out.grid = rasterize(prep, best.sx, best.sy, best.th);
  out.placement.shift_x_m = best.sx;
  out.placement.shift_y_m = best.sy;
  out.placement.rotation_deg = best.th;
  out.placement.J = best.s.J;
  out.placement.J1 = best.s.J1;
  out.placement.J2 = best.s.J2;
  out.placement.J3 = best.s.J3;
  out.placement.evaluations = evals;
  if (progress) progress(1.0);
  return out;
}

}  // namespace uavcover::grid
