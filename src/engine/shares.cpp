#include "engine/shares.hpp"

#include "geometry/geometry.hpp"

#include <fmt/format.h>

#include <boost/geometry/algorithms/point_on_surface.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "uavcover/error.hpp"

namespace uavcover::engine {

namespace {

Point rotate(Point p, double c, double s) { return {p.x() * c - p.y() * s, p.x() * s + p.y() * c}; }

/// `mp` rotated by the angle whose cosine and sine are c and s.
MultiPolygon rotated(const MultiPolygon& mp, double c, double s) {
  MultiPolygon out = mp;
  for (auto& poly : out) {
    for (auto& p : poly.outer()) p = rotate(p, c, s);
    for (auto& inner : poly.inners())
      for (auto& p : inner) p = rotate(p, c, s);
  }
  return out;
}

/// The part of `mp` with x in [x0, x1].
MultiPolygon slab(const MultiPolygon& mp, const bg::model::box<Point>& env, double x0, double x1) {
  MultiPolygon out;
  bg::intersection(mp, geometry::box_polygon(x0, env.min_corner().y() - 1.0, x1, env.max_corner().y() + 1.0),
                   out);
  return out;
}

/// Normalised shares (equal when they do not sum to a positive number).
std::vector<double> normalised(const std::vector<double>& shares) {
  std::vector<double> s(shares);
  double sum = 0;
  for (double& x : s) sum += x = std::max(0.0, x);
  if (!(sum > 0)) std::fill(s.begin(), s.end(), 1.0), sum = static_cast<double>(s.size());
  for (double& x : s) x /= sum;
  return s;
}

}  // namespace

double principal_axis(const MultiPolygon& mp) {
  // second moments of area from the rings (Boost's outer rings are clockwise, holes counter-clockwise:
  // the signed sums of all rings are the area's, with one sign)
  double a = 0, sx = 0, sy = 0, ixx = 0, iyy = 0, ixy = 0;
  auto ring = [&](const auto& r) {
    for (std::size_t k = 0; k + 1 < r.size(); ++k) {
      const double x0 = r[k].x(), y0 = r[k].y(), x1 = r[k + 1].x(), y1 = r[k + 1].y();
      const double cr = x0 * y1 - x1 * y0;
      a += cr / 2;
      sx += (x0 + x1) * cr / 6;
      sy += (y0 + y1) * cr / 6;
      iyy += (x0 * x0 + x0 * x1 + x1 * x1) * cr / 12;  // integral of x^2
      ixx += (y0 * y0 + y0 * y1 + y1 * y1) * cr / 12;  // integral of y^2
      ixy += (x0 * y1 + 2 * x0 * y0 + 2 * x1 * y1 + x1 * y0) * cr / 24;
    }
  };
  for (const auto& poly : mp) {
    ring(poly.outer());
    for (const auto& inner : poly.inners()) ring(inner);
  }
  if (std::fabs(a) < 1e-12) return 0.0;
  const double cx = sx / a, cy = sy / a;
  const double vxx = iyy / a - cx * cx, vyy = ixx / a - cy * cy, vxy = ixy / a - cx * cy;
  if (std::fabs(vxx - vyy) < 1e-12 && std::fabs(vxy) < 1e-12) return 0.0;
  return 0.5 * std::atan2(2 * vxy, vxx - vyy);
}

std::vector<Point> spread_starts(const MultiPolygon& free, const std::vector<double>& shares,
                                 std::mt19937_64& rng) {
  const std::size_t n = shares.size();
  std::vector<Point> out(n);
  if (n == 0 || free.empty()) return out;
  const std::vector<double> s = normalised(shares);
  const double theta = principal_axis(free);
  // the area in a frame whose x axis is the principal axis
  const MultiPolygon r = rotated(free, std::cos(-theta), std::sin(-theta));
  bg::model::box<Point> env;
  bg::envelope(r, env);
  const double total = bg::area(r), xmin = env.min_corner().x(), xmax = env.max_corner().x();
  // cuts[i]: the x where the area left of it is the first i shares' (bisection on the slab's area)
  std::vector<double> cuts(n + 1, xmin);
  cuts[n] = xmax;
  double acc = 0;
  for (std::size_t i = 1; i < n; ++i) {
    acc += s[i - 1];
    double lo = cuts[i - 1], hi = xmax;
    for (int it = 0; it < 40 && hi - lo > 1e-3; ++it) {
      const double mid = (lo + hi) / 2;
      (bg::area(slab(r, env, xmin - 1.0, mid)) < acc * total ? lo : hi) = mid;
    }
    cuts[i] = (lo + hi) / 2;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double w = cuts[i + 1] - cuts[i];
    // the middle half of the slab, so that neighbouring starts keep apart
    MultiPolygon mid = slab(r, env, cuts[i] + 0.25 * w, cuts[i + 1] - 0.25 * w);
    if (bg::area(mid) <= 0.0) mid = slab(r, env, cuts[i], cuts[i + 1]);
    Point p;
    bool found = false;
    if (bg::area(mid) > 0.0) {
      bg::model::box<Point> b;
      bg::envelope(mid, b);
      const double y0 = b.min_corner().y(), h = b.max_corner().y() - y0;
      std::uniform_real_distribution<double> ux(b.min_corner().x(), b.max_corner().x());
      // across the axis, the middle fifth first: starts level with each other divide a field into
      // straight bands (the thesis rectangle: 39 to 53 turns as the starts go level to staggered),
      // then the slab's whole width (shapes whose middle misses it)
      for (const double band : {0.2, 1.0}) {
        std::uniform_real_distribution<double> uy(y0 + h * (1 - band) / 2, y0 + h * (1 + band) / 2);
        for (int k = 0; k < 1000 && !found; ++k) {
          p = Point{ux(rng), uy(rng)};
          found = bg::within(p, mid);
        }
      }
      if (!found) {
        // the slab's largest piece
        const auto big = std::max_element(mid.begin(), mid.end(), [](const Polygon& x, const Polygon& y) {
          return bg::area(x) < bg::area(y);
        });
        bg::point_on_surface(*big, p);
        found = true;
      }
    }
    if (!found) bg::point_on_surface(r, p);
    out[i] = rotate(p, std::cos(theta), std::sin(theta));
  }
  return out;
}

std::vector<std::vector<PartPiece>> allocate_parts(const MultiPolygon& free, const std::vector<Point>& starts,
                                                   const std::vector<double>& shares, double snap) {
  const std::size_t U = shares.size(), P = free.size();
  std::vector<std::vector<PartPiece>> out(U);
  if (U == 0 || P == 0) return out;
  const std::vector<double> s = normalised(shares);
  std::vector<double> area(P);
  std::vector<Point> centre(P);
  double total = 0;
  for (std::size_t q = 0; q < P; ++q) {
    area[q] = bg::area(free[q]);
    total += area[q];
    bg::centroid(free[q], centre[q]);
  }
  // the axis through the parts' centroids (area-weighted principal direction); the free area's own
  // principal axis when the centroids do not spread (parts nested in each other's holes)
  double mx = 0, my = 0;
  for (std::size_t q = 0; q < P; ++q) mx += area[q] * centre[q].x(), my += area[q] * centre[q].y();
  mx /= total, my /= total;
  double vxx = 0, vyy = 0, vxy = 0;
  for (std::size_t q = 0; q < P; ++q) {
    const double dx = centre[q].x() - mx, dy = centre[q].y() - my;
    vxx += area[q] * dx * dx, vyy += area[q] * dy * dy, vxy += area[q] * dx * dy;
  }
  const double spread = (vxx + vyy) / total;
  const double theta = spread > 1e-6 ? 0.5 * std::atan2(2 * vxy, vxx - vyy) : principal_axis(free);
  const double c = std::cos(theta), sn = std::sin(theta);
  auto along = [&](Point p) { return p.x() * c + p.y() * sn; };
  std::vector<std::size_t> parts(P), uavs(U);
  std::iota(parts.begin(), parts.end(), 0);
  std::iota(uavs.begin(), uavs.end(), 0);
  std::stable_sort(parts.begin(), parts.end(),
                   [&](std::size_t a, std::size_t b) { return along(centre[a]) < along(centre[b]); });
  std::stable_sort(uavs.begin(), uavs.end(),
                   [&](std::size_t a, std::size_t b) { return along(starts[a]) < along(starts[b]); });
  // the parts laid end to end on [0, total]; each UAV in order takes the next stretch of its share
  std::vector<double> edge(P + 1, 0.0);
  for (std::size_t k = 0; k < P; ++k) edge[k + 1] = edge[k] + area[parts[k]];
  edge[P] = total;
  std::vector<double> cut(U + 1, 0.0);
  double acc = 0;
  for (std::size_t j = 0; j + 1 < U; ++j) {
    acc += s[uavs[j]] * total;
    double x = acc;
    // a cut near a part's edge moves to it: no UAV flies a sliver of a part
    for (double e : edge)
      if (std::fabs(e - acc) <= snap * total) {
        if (std::fabs(e - acc) < std::fabs(x - acc) || x == acc) x = e;
      }
    cut[j + 1] = std::max(cut[j], x);
  }
  cut[U] = total;
  for (std::size_t j = 0; j < U; ++j)
    for (std::size_t k = 0; k < P; ++k) {
      const double a = std::max(cut[j], edge[k]), b = std::min(cut[j + 1], edge[k + 1]);
      if (b - a > 1e-9 * total) out[uavs[j]].push_back({parts[k], b - a});
    }
  return out;
}

std::optional<planners::Assignment> plan_by_parts(const planners::PlannerInfo& info,
                                                  const planners::Problem& problem,
                                                  const nlohmann::json& params, const Context& ctx) {
  const std::size_t U = problem.starts.size(), P = problem.free.size();
  if (P < 2 || U < 2 || !info.supports.shares) return std::nullopt;
  const auto alloc = allocate_parts(problem.free, problem.starts, problem.shares);
  double total = 0;
  for (const auto& poly : problem.free) total += bg::area(poly);

  // per part: its UAVs and their piece areas, in UAV order
  std::vector<std::vector<std::pair<std::size_t, double>>> members(P);
  for (std::size_t i = 0; i < U; ++i)
    for (const auto& piece : alloc[i]) members[piece.part].push_back({i, piece.area_m2});
  // a UAV keeps its own start in the part nearest to it (the one it stands in, or beside)
  std::vector<std::size_t> nearest(U, 0);
  for (std::size_t i = 0; i < U; ++i) {
    double bd = std::numeric_limits<double>::infinity();
    for (std::size_t q = 0; q < P; ++q) {
      const double d = bg::distance(problem.starts[i], problem.free[q]);
      if (d < bd) bd = d, nearest[i] = q;
    }
  }

  planners::Assignment out;
  out.uavs.resize(U);
  struct Piece {
    std::size_t part;
    planners::UavAssignment a;
    double part_area;
  };
  std::vector<std::vector<Piece>> pieces(U);
  nlohmann::json parts_diag = nlohmann::json::array();
  const auto planner = info.create();
  double done = 0;
  int planned = 0;
  std::optional<InputError> first_error;
  for (std::size_t q = 0; q < P; ++q) {
    const double part_area = bg::area(problem.free[q]);
    if (members[q].empty()) {
      done += part_area;
      continue;
    }
    planners::Problem sub = problem;
    sub.free = MultiPolygon{problem.free[q]};
    sub.starts.clear();
    sub.shares.clear();
    sub.uavs.clear();
    sub.uav_footprints.clear();
    std::vector<double> sub_shares;
    for (const auto& [i, a] : members[q]) sub_shares.push_back(a / part_area);
    std::mt19937_64 rng(problem.seed ^ (0x9a27ULL + q));
    const std::vector<Point> spread = spread_starts(sub.free, sub_shares, rng);
    nlohmann::json ids = nlohmann::json::array();
    for (std::size_t k = 0; k < members[q].size(); ++k) {
      const std::size_t i = members[q][k].first;
      sub.starts.push_back(nearest[i] == q ? problem.starts[i] : spread[k]);
      sub.shares.push_back(sub_shares[k]);
      sub.uavs.push_back(problem.uavs[i]);
      sub.uav_footprints.push_back(problem.uav_footprints[i]);
      ids.push_back(problem.uavs[i].id);
    }
    const double from = done / total, span = part_area / total;
    const Context sub_ctx = ctx.with_progress(
        [&ctx, from, span](std::string_view stage, double f) { ctx.report(stage, from + span * f); });
    done += part_area;
    planners::Assignment res;
    try {
      res = planner->plan(sub, params, sub_ctx);
    } catch (const InputError& e) {
      // a part the planner cannot plan (too small or narrow for the spacing): its UAVs miss it
      if (!first_error) first_error = e;
      out.warnings.push_back(
          fmt::format("part {} of the free area ({:.0f} m^2, {:.1f} % of it) was not planned: {}", q + 1,
                      part_area, 100 * part_area / total, e.what()));
      continue;
    }
    if (res.uavs.size() != members[q].size())
      throw OperationError(fmt::format("planner \"{}\" returned {} UAVs for {}", info.name, res.uavs.size(),
                                       members[q].size()));
    ++planned;
    out.complete = out.complete && res.complete;
    for (const auto& w : res.warnings) out.warnings.push_back(fmt::format("part {}: {}", q + 1, w));
    parts_diag.push_back({{"part", q + 1},
                          {"area_m2", part_area},
                          {"uavs", ids},
                          {"shares", sub_shares},
                          {"diagnostics", res.diagnostics}});
    for (std::size_t k = 0; k < members[q].size(); ++k)
      pieces[members[q][k].first].push_back({q, std::move(res.uavs[k]), part_area});
  }
  if (planned == 0 && first_error) throw *first_error;

  for (std::size_t i = 0; i < U; ++i) {
    auto& ps = pieces[i];
    auto& ua = out.uavs[i];
    // pieces nearest first from the start, then from where the previous one ends
    Point here = problem.starts[i];
    std::vector<char> flown(ps.size(), 0);
    bool any_sorties = false, any_share = false;
    for (const auto& p : ps)
      any_sorties |= !p.a.sortie_starts.empty(), any_share |= p.a.share_actual.has_value();
    double share = 0;
    nlohmann::json diag = nlohmann::json::array();
    for (std::size_t n = 0; n < ps.size(); ++n) {
      std::size_t pick = ps.size();
      double bd = std::numeric_limits<double>::infinity();
      for (std::size_t j = 0; j < ps.size(); ++j) {
        if (flown[j]) continue;
        double d = std::numeric_limits<double>::infinity();
        for (const auto& cov : ps[j].a.coverage)
          if (!cov.empty()) d = std::min(d, bg::distance(here, cov.front()));
        if (!std::isfinite(d)) d = ps[j].a.region.empty() ? 1e300 : bg::distance(here, ps[j].a.region);
        if (pick == ps.size() || d < bd) bd = d, pick = j;
      }
      flown[pick] = 1;
      auto& p = ps[pick].a;
      const std::size_t offset = ua.coverage.size();
      if (any_sorties) {
        if (p.sortie_starts.empty() && !p.coverage.empty()) ua.sortie_starts.push_back(offset);
        for (std::size_t k : p.sortie_starts) ua.sortie_starts.push_back(offset + k);
      }
      for (auto& cov : p.coverage)
        if (!cov.empty()) here = cov.back();
      // the per-part camera flags and attitudes stay parallel to the coverage parts
      if (!p.camera_off.empty()) {
        ua.camera_off.resize(offset);
        for (std::size_t k = 0; k < p.coverage.size(); ++k)
          ua.camera_off.push_back(k < p.camera_off.size() ? std::move(p.camera_off[k])
                                                          : std::vector<std::uint8_t>{});
      }
      if (!p.attitude.empty()) {
        ua.attitude.resize(offset);
        for (std::size_t k = 0; k < p.coverage.size(); ++k)
          ua.attitude.push_back(k < p.attitude.size() ? std::move(p.attitude[k]) : Attitude{});
      }
      for (auto& cov : p.coverage) ua.coverage.push_back(std::move(cov));
      if (any_share) {
        double region_total = 0;
        for (const auto& other : pieces)
          for (const auto& op : other)
            if (op.part == ps[pick].part) region_total += bg::area(op.a.region);
        const double frac = p.share_actual     ? *p.share_actual
                            : region_total > 0 ? bg::area(p.region) / region_total
                                               : 0.0;
        share += frac * ps[pick].part_area / total;
      }
      for (auto& poly : p.region) ua.region.push_back(std::move(poly));
      diag.push_back({{"part", ps[pick].part + 1}, {"diagnostics", p.diagnostics}});
    }
    // sortie starts must begin at 0 and increase; empty coverage parts count as in the planner's
    if (!ua.sortie_starts.empty()) {
      std::sort(ua.sortie_starts.begin(), ua.sortie_starts.end());
      ua.sortie_starts.erase(std::unique(ua.sortie_starts.begin(), ua.sortie_starts.end()),
                             ua.sortie_starts.end());
      ua.sortie_starts.front() = 0;
      if (ua.sortie_starts.size() > 1 && ua.sortie_starts[1] == 0)
        ua.sortie_starts.erase(ua.sortie_starts.begin());
      std::erase_if(ua.sortie_starts, [&](std::size_t k) { return k >= ua.coverage.size(); });
    }
    if (any_share) ua.share_actual = share;
    ua.diagnostics = {{"parts", diag}};
  }
  out.diagnostics = {{"parts", parts_diag}};
  return out;
}

}  // namespace uavcover::engine
