#include "sorties/sorties.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <string>

#include "evaluation/cost.hpp"
#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "uavcover/error.hpp"
#include "waypoints/vertical.hpp"

namespace uavcover::sorties {

namespace {

constexpr double kSamePlaceM = 1e-6;  // as the engine: closer points need no transit leg
constexpr double kEps = 1e-9;

double reserve_of(const Plan& plan, const Options& o) {
  const double r = o.reserve ? *o.reserve : plan.mission.battery_reserve;
  if (!std::isfinite(r) || r < 0.0 || r > 0.9) throw InputError("battery_reserve", "must be in [0, 0.9]");
  return r;
}

/// sorties::vertical_min() at given transition altitudes (the cutter resolves them once per UAV).
double vertical_min_at(const Plan& plan, std::size_t index, const Sortie& s,
                       const waypoints::AltitudeOptions& altitudes) {
  return waypoints::vertical_time_s(plan, index, waypoints::mission_items(plan, index, s.parts, altitudes)) /
         60.0;
}

}  // namespace

double resume_backoff_m(const Plan& plan, std::size_t index) {
  const Mission& m = plan.mission;
  if (m.resume_backoff_m) return *m.resume_backoff_m;
  const Uav& u = m.uavs.at(index);
  if (u.camera_geometry && u.camera_geometry->trigger_distance_m > 0)
    return u.camera_geometry->trigger_distance_m;
  return m.trigger_distance_m.value_or(0.0);
}

namespace {

/// The no-fly zones' router in the plan's local frame (as the engine routes transit legs).
struct Geo {
  geodesy::LocalFrame frame;
  std::unique_ptr<geometry::Router> owned;
  const geometry::Router& router;
  explicit Geo(const Plan& plan)
      : frame(plan.origin),
        owned(std::make_unique<geometry::Router>(
            geometry::unite(geometry::to_local(plan.mission.no_fly_zones, frame)))),
        router(*owned) {}
  /// With the engine's router (the no-fly zones in the plan's frame): nothing is built again.
  Geo(const Plan& plan, const geometry::Router& r) : frame(plan.origin), router(r) {}
};

/// One UAV's coverage laid out for cutting. Lengths that time a sortie are air distances (issue 32:
/// eq. 15 with each leg at its ground speed in the mission's wind; without wind, the lengths).
struct Layout {
  const Plan& plan;
  std::size_t index;
  const UavPlan& up;
  const Uav& uav;
  const Geo& geo;
  Point start;
  std::vector<WaypointRef> wp;
  std::vector<std::size_t> wp_cov;  ///< waypoint -> index into cov_parts
  std::vector<std::size_t> cov_parts;
  std::vector<double> cum;  ///< air distance along the plan from waypoint 0
  std::size_t lead_end = 0, trail_begin = 0;
  double lead_len = 0.0, trail_len = 0.0;
  double backoff_m = 0.0;  ///< resume_backoff_m (issue 31): a later sortie starts this far back
  /// the transition altitudes of the whole flight's climbs and descents (issue 32)
  waypoints::AltitudeOptions altitudes;

  double air(Point a, Point b) const {
    return evaluation::air_distance_m(a, b, uav.speed_mps, plan.mission.wind);
  }
  double air(const std::vector<Point>& line) const {
    return evaluation::air_length_m(line, uav.speed_mps, plan.mission.wind);
  }

  Layout(const Plan& p, std::size_t i, const Geo& g)
      : plan(p), index(i), up(p.uavs.at(i)), uav(p.mission.uavs.at(i)), geo(g) {
    start = geo.frame.to_local(uav.start_resolved);
    for (std::size_t pi = 0; pi < up.parts.size(); ++pi) {
      const auto& part = up.parts[pi];
      if (part.kind != PartKind::Coverage || part.local.empty()) continue;
      if (part.wgs84.size() != part.local.size())
        throw InputError(fmt::format("uavs[{}].parts[{}]", i, pi), "local and WGS84 vertices differ");
      const std::size_t j = cov_parts.size();
      for (std::size_t k = 0; k < part.local.size(); ++k) {
        double c = 0.0;
        if (!wp.empty()) {
          const WaypointRef prev = wp.back();
          if (prev.part == pi) {
            c = cum.back() + air(up.parts[pi].local[k - 1], part.local[k]);
          } else {
            c = cum.back();
            for (std::size_t q = prev.part + 1; q < pi; ++q) c += air(up.parts[q].local);
          }
        }
        wp.push_back({pi, k});
        wp_cov.push_back(j);
        cum.push_back(c);
      }
      cov_parts.push_back(pi);
    }
    backoff_m = resume_backoff_m(p, i);
    altitudes = waypoints::whole_flight_altitudes(p);
    if (cov_parts.empty()) return;
    lead_end = cov_parts.front();
    trail_begin = cov_parts.back() + 1;
    for (std::size_t q = 0; q < lead_end; ++q) lead_len += air(up.parts[q].local);
    for (std::size_t q = trail_begin; q < up.parts.size(); ++q) trail_len += air(up.parts[q].local);
  }

  /// Where a sortie (or a resume) starting at waypoint `a` begins flying its coverage: backoff_m back
  /// along its coverage part (issue 31), so that no gap opens at the seam. None for the first waypoint,
  /// at a part's first vertex, or without a backoff; clipped at the part's first vertex.
  struct LeadIn {
    std::size_t seg = 0;  ///< the point lies on segment (seg, seg + 1) of the part, seg < vertex of a
    Point p;
    double air_m = 0.0;  ///< the stretch's air distance
  };
  std::optional<LeadIn> lead_in(std::size_t a) const {
    if (!(backoff_m > kSamePlaceM) || a == 0 || a >= n() || wp[a].vertex == 0) return std::nullopt;
    const auto& local = up.parts[wp[a].part].local;
    std::size_t k = wp[a].vertex;
    double left = backoff_m;
    LeadIn li{0, local[0], 0.0};
    while (k > 0) {
      const double len = bg::distance(local[k - 1], local[k]);
      if (len >= left) {
        const double t = len > 0 ? left / len : 0.0;
        li.seg = k - 1;
        li.p = Point(local[k].x() + t * (local[k - 1].x() - local[k].x()),
                     local[k].y() + t * (local[k - 1].y() - local[k].y()));
        break;
      }
      left -= len;
      --k;
    }
    if (k == 0) li = LeadIn{0, local[0], 0.0};
    std::vector<Point> line{li.p};
    line.insert(line.end(), local.begin() + static_cast<long>(li.seg) + 1,
                local.begin() + static_cast<long>(wp[a].vertex) + 1);
    li.air_m = air(line);
    return li;
  }
  /// Where the transit out of a sortie starting at `a` ends: its lead-in's start, or waypoint a.
  Point entry(std::size_t a) const {
    const auto li = lead_in(a);
    return li ? li->p : at(a);
  }

  std::size_t n() const { return wp.size(); }
  Point at(std::size_t g) const { return up.parts[wp[g].part].local[wp[g].vertex]; }
  bool ends_part(std::size_t g) const { return g + 1 >= n() || wp_cov[g + 1] != wp_cov[g]; }

  /// Routed transits, each computed once (bisection and build() ask for the same returns; routes
  /// through many no-fly zones are costly).
  mutable std::map<std::array<double, 4>, std::vector<Point>> routes;
  const std::vector<Point>& routed(Point a, Point b) const {
    const std::array<double, 4> key{a.x(), a.y(), b.x(), b.y()};
    auto it = routes.find(key);
    if (it == routes.end()) it = routes.emplace(key, geo.router.route(a, b)).first;
    return it->second;
  }
  double route_len(Point a, Point b) const {
    if (bg::distance(a, b) < kSamePlaceM) return 0.0;
    return air(routed(a, b));
  }
  double out_len(std::size_t a) const {
    if (a == 0 && lead_end > 0) return lead_len;
    const auto li = lead_in(a);
    return li ? route_len(start, li->p) + li->air_m : route_len(start, at(a));
  }
  double back_len(std::size_t b) const {
    return b + 1 == n() && trail_begin < up.parts.size() ? trail_len : route_len(at(b), start);
  }
  double duration(double length_m, std::size_t a, std::size_t b) const {
    return evaluation::flight_duration_min(length_m, static_cast<int>(b - a + 1), uav);
  }
  /// The minutes a sortie's climbs and descents take beyond its horizontal flight (issue 32,
  /// docs/wind.md#the-whole-flight): those of its own mission's items, take-off and landing included.
  double vertical_min(const Sortie& s) const { return vertical_min_at(plan, index, s, altitudes); }
  double cost(double out, std::size_t a, std::size_t b) const {
    return duration(out + cum[b] - cum[a] + back_len(b), a, b);
  }

  std::optional<PathPart> transit(Point a, Point b) const {
    if (bg::distance(a, b) < kSamePlaceM) return std::nullopt;
    PathPart part{PartKind::Transit, {}, {}};
    part.wgs84 = geometry::to_wgs84_dense(routed(a, b), geo.frame, &part.local);
    return part;
  }

  /// The sortie covering waypoints a..b; `out`/`back` given replace the routed transits (empty
  /// optional = route it; a given part with no vertices = none).
  Sortie build(std::size_t a, std::size_t b, const std::optional<PathPart>& out = std::nullopt,
               const std::optional<PathPart>& back = std::nullopt) const {
    Sortie s;
    s.first_waypoint = static_cast<int>(a);
    s.last_waypoint = static_cast<int>(b);
    if (out) {
      if (!out->local.empty()) s.parts.push_back(*out);
    } else if (a == 0 && lead_end > 0) {
      s.parts.insert(s.parts.end(), up.parts.begin(), up.parts.begin() + static_cast<long>(lead_end));
    } else if (auto t = transit(start, entry(a))) {
      s.parts.push_back(std::move(*t));
    }
    const auto li = lead_in(a);
    for (std::size_t j = wp_cov[a]; j <= wp_cov[b]; ++j) {
      const PathPart& src = up.parts[cov_parts[j]];
      // the first piece starts at its lead-in: the point on segment li->seg, then the vertices after it
      const bool lead = j == wp_cov[a] && li;
      const std::size_t from = j == wp_cov[a] ? (lead ? li->seg : wp[a].vertex) : 0;
      const std::size_t to = j == wp_cov[b] ? wp[b].vertex : src.local.size() - 1;
      PathPart piece{PartKind::Coverage, {}, {}};
      piece.local.assign(src.local.begin() + static_cast<long>(from),
                         src.local.begin() + static_cast<long>(to) + 1);
      piece.wgs84.assign(src.wgs84.begin() + static_cast<long>(from),
                         src.wgs84.begin() + static_cast<long>(to) + 1);
      if (lead) {  // vertex `from` replaced by the lead-in's start on the segment after it
        piece.local.front() = li->p;
        piece.wgs84.front() = geo.frame.to_wgs84(li->p);
        piece.lead_in = wp[a].vertex - li->seg;
      }
      if (!src.camera_off.empty() && to > from)  // the camera-off flags of the piece's segments
        piece.camera_off.assign(
            src.camera_off.begin() + static_cast<long>(std::min(from, src.camera_off.size())),
            src.camera_off.begin() + static_cast<long>(std::min(to, src.camera_off.size())));
      piece.attitude = src.attitude;  // the piece's own headings: those of its vertices
      if (src.attitude.heading_deg.size() == src.local.size()) {
        piece.attitude.heading_deg.assign(src.attitude.heading_deg.begin() + static_cast<long>(from),
                                          src.attitude.heading_deg.begin() + static_cast<long>(to) + 1);
        if (lead) {  // the lead-in's start lies inside segment `from`: its heading turned the short way
          const double h0 = src.attitude.heading_deg[from], h1 = src.attitude.heading_deg[from + 1];
          const double len = bg::distance(src.local[from], src.local[from + 1]);
          const double u = len > 0 ? bg::distance(src.local[from], li->p) / len : 0.0;
          const double turn = std::remainder(h1 - h0, 360.0);
          piece.attitude.heading_deg.front() = std::fmod(h0 + u * turn + 360.0, 360.0);
        }
      }
      s.parts.push_back(std::move(piece));
      if (j < wp_cov[b])
        s.parts.insert(s.parts.end(), up.parts.begin() + static_cast<long>(cov_parts[j]) + 1,
                       up.parts.begin() + static_cast<long>(cov_parts[j + 1]));
    }
    if (back) {
      if (!back->local.empty()) s.parts.push_back(*back);
    } else if (b + 1 == n() && trail_begin < up.parts.size()) {
      s.parts.insert(s.parts.end(), up.parts.begin() + static_cast<long>(trail_begin), up.parts.end());
    } else if (auto t = transit(at(b), start)) {
      s.parts.push_back(std::move(*t));
    }
    double air_m = 0.0;
    for (const auto& part : s.parts) {
      s.length_m += geometry::length(part.local);
      air_m += air(part.local);
    }
    s.turns = static_cast<int>(b - a + 1);
    s.duration_min = duration(air_m, a, b);
    return s;
  }
};

}  // namespace

std::vector<WaypointRef> coverage_waypoints(const UavPlan& uav) {
  std::vector<WaypointRef> out;
  for (std::size_t pi = 0; pi < uav.parts.size(); ++pi)
    if (uav.parts[pi].kind == PartKind::Coverage)
      for (std::size_t k = 0; k < uav.parts[pi].local.size(); ++k) out.push_back({pi, k});
  return out;
}

double budget_min(const Plan& plan, std::size_t index, const Options& options) {
  const Uav& u = plan.mission.uavs.at(index);
  if (!(u.endurance_min > 0.0) || !std::isfinite(u.endurance_min))
    throw InputError(fmt::format("uavs[{}].endurance_min", index), "must be > 0");
  return u.endurance_min * (1.0 - reserve_of(plan, options));
}

double vertical_min(const Plan& plan, std::size_t index, const Sortie& s) {
  return vertical_min_at(plan, index, s, waypoints::whole_flight_altitudes(plan));
}

namespace {

std::vector<Sortie> cut(const Layout& L, double budget, const Context* ctx = nullptr, std::size_t first = 0,
                        std::optional<std::size_t> last = std::nullopt);

/// The refusal of a flight that does not fit one battery (`what`: the leg or sortie).
InputError over_budget(const Layout& L, double budget, const std::string& what, double need_min) {
  return InputError(
      fmt::format("uavs[{}].endurance_min", L.index),
      fmt::format("UAV \"{}\": {} with the transit out and back needs {:.2f} min, more than one "
                  "battery allows ({:.2f} min: endurance {} min less the {:.0f} % reserve); give a "
                  "longer endurance or a smaller reserve",
                  L.up.id, what, need_min, budget, L.uav.endurance_min,
                  100.0 * (1.0 - budget / L.uav.endurance_min)));
}

/// The sorties given by the planner: one per entry of `starts` (indices of coverage parts that begin
/// a sortie), each from its part's first waypoint to the waypoint before the next sortie's, checked
/// against the budget.
std::vector<Sortie> given(const Layout& L, const std::vector<std::size_t>& starts, double budget,
                          const Context* ctx = nullptr) {
  const std::string field = fmt::format("sortie_starts[{}]", L.index);
  const std::size_t parts = L.cov_parts.size();
  if (starts.front() != 0) throw InputError(field, fmt::format("must begin with 0, got {}", starts.front()));
  for (std::size_t k = 0; k < starts.size(); ++k) {
    if (starts[k] >= parts)
      throw InputError(fmt::format("{}[{}]", field, k),
                       fmt::format("UAV \"{}\" has {} coverage parts, got {}", L.up.id, parts, starts[k]));
    if (k > 0 && starts[k] <= starts[k - 1])
      throw InputError(fmt::format("{}[{}]", field, k), "must be strictly increasing");
  }
  std::vector<std::size_t> first(parts + 1, L.n());  // coverage part -> its first waypoint
  for (std::size_t g = L.n(); g-- > 0;) first[L.wp_cov[g]] = g;
  std::vector<Sortie> out;
  for (std::size_t k = 0; k < starts.size(); ++k) {
    if (ctx != nullptr && ctx->stop_requested()) throw Cancelled();
    const std::size_t a = first[starts[k]];
    const std::size_t b = (k + 1 < starts.size() ? first[starts[k + 1]] : L.n()) - 1;
    Sortie s = L.build(a, b);
    if (s.duration_min > budget * (1.0 + kEps))
      throw over_budget(L, budget,
                        fmt::format("sortie {} given by the planner (waypoints {} to {})", k, a, b),
                        s.duration_min);
    // the planner times its sorties in the plane (eq. 15); with the climbs and descents one may not fit:
    // it is cut further, from its own first waypoint to its last, like any other
    if (s.duration_min + L.vertical_min(s) > budget * (1.0 + kEps)) {
      for (Sortie& piece : cut(L, budget, ctx, a, b)) out.push_back(std::move(piece));
    } else {
      out.push_back(std::move(s));
    }
  }
  for (std::size_t k = 0; k < out.size(); ++k) out[k].index = static_cast<int>(k);
  return out;
}

/// The planner's sorties of UAV `index` when `options` has them, else the cut from the endurance.
std::vector<Sortie> sorties_of(const Layout& L, const Options& options, double budget,
                               const Context* ctx = nullptr) {
  if (L.index < options.sortie_starts.size() && !options.sortie_starts[L.index].empty() && L.n() > 0)
    return given(L, options.sortie_starts[L.index], budget, ctx);
  return cut(L, budget, ctx);
}

/// Sorties cut greedily over waypoints `first`..`last` (default: the UAV's last), each the longest that
/// fits `budget` with its climbs and descents (Layout::vertical_min).
std::vector<Sortie> cut(const Layout& L, double budget, const Context* ctx, std::size_t first,
                        std::optional<std::size_t> last) {
  std::vector<Sortie> out;
  const std::size_t n = L.n();
  if (n == 0) return out;
  const std::size_t end = std::min(last.value_or(n - 1), n - 1);
  const double limit = budget * (1.0 + kEps);
  // a sortie's vertical minutes hardly depend on where it ends (take-off, landing and the height changes
  // at either end): the last sortie's are the next one's estimate, checked on the sortie built
  double vertical_est = 0.0;
  std::size_t a = first;
  for (;;) {
    if (ctx != nullptr && ctx->stop_requested()) throw Cancelled();
    const double out_len = L.out_len(a);
    const std::size_t bmin = L.ends_part(a) ? a : std::min(a + 1, end);
    if (const double need = L.cost(out_len, a, bmin); need > limit)
      throw over_budget(L, budget, fmt::format("the coverage leg from waypoint {} to {}", a, bmin), need);
    // the time of a sortie a..b grows with b (the return from b is at most the leg to b+1 shorter than
    // from b+1): the last b that fits, by bisection. First with the straight return (a lower bound, no
    // routing: many no-fly zones make routes costly), then with routed returns below that bound.
    auto last_fitting = [&](double plane_limit) {
      auto fitting = [&](std::size_t hi_end, auto&& cost) {
        if (cost(hi_end) <= plane_limit) return hi_end;
        std::size_t lo = bmin, hi = hi_end;
        while (hi - lo > 1) {
          const std::size_t mid = lo + (hi - lo) / 2;
          (cost(mid) <= plane_limit ? lo : hi) = mid;
        }
        return lo;
      };
      const std::size_t b_bound = fitting(end, [&](std::size_t b) {
        const double back =
            b + 1 == n && L.trail_begin < L.up.parts.size() ? L.trail_len : L.air(L.at(b), L.start);
        return L.duration(out_len + L.cum[b] - L.cum[a] + back, a, b);
      });
      return fitting(b_bound, [&](std::size_t b) { return L.cost(out_len, a, b); });
    };
    std::size_t b = last_fitting(limit - vertical_est);
    Sortie s = L.build(a, b);
    double vertical = L.vertical_min(s);
    if (s.duration_min + vertical > limit && b > bmin && vertical > vertical_est) {
      // the estimate was short: once more with this sortie's own climbs and descents
      b = std::max(bmin, std::min(b, last_fitting(limit - vertical)));
      s = L.build(a, b);
      vertical = L.vertical_min(s);
    }
    // routes may differ from their length, and the heights at the sortie's ends from the estimate
    while (s.duration_min + vertical > limit && b > bmin) {
      s = L.build(a, --b);
      vertical = L.vertical_min(s);
    }
    if (s.duration_min + vertical > limit)
      throw over_budget(L, budget,
                        fmt::format("the coverage leg from waypoint {} to {} with its climbs and descents "
                                    "({:.2f} min)",
                                    a, b, vertical),
                        s.duration_min + vertical);
    vertical_est = vertical;
    s.index = static_cast<int>(out.size());
    out.push_back(std::move(s));
    if (b >= end) break;
    a = L.ends_part(b) ? b + 1 : b;
  }
  return out;
}

}  // namespace

std::vector<Sortie> cut_sorties(const Plan& plan, std::size_t index, const Options& options) {
  const Geo geo(plan);
  const Layout L(plan, index, geo);
  return sorties_of(L, options, budget_min(plan, index, options));
}

void fill_sorties(Plan& plan, const Options& options, std::vector<std::string>* warnings,
                  const geometry::Router* router, const Context* ctx) {
  if (plan.uavs.size() != plan.mission.uavs.size())
    throw InputError("uavs", "the plan's UAVs do not match the mission's");
  const Geo geo = router != nullptr ? Geo(plan, *router) : Geo(plan);  // one router for every UAV
  for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
    const Layout L(plan, i, geo);
    try {
      plan.uavs[i].sorties = sorties_of(L, options, budget_min(plan, i, options), ctx);
      if (ctx != nullptr)
        ctx->report("sorties", static_cast<double>(i + 1) / static_cast<double>(plan.uavs.size()));
    } catch (const InputError& e) {
      if (warnings == nullptr) throw;
      plan.uavs[i].sorties.clear();
      warnings->push_back(std::string("no battery sorties: ") + e.what());
    }
  }
}

std::vector<Sortie> capacity_sorties(const Plan& plan, std::size_t index, std::size_t capacity,
                                     const ItemCount& count, const std::vector<Sortie>* given_base) {
  const Geo geo(plan);
  const Layout L(plan, index, geo);
  std::vector<Sortie> out;
  const std::size_t n = L.n();
  if (n == 0) return out;
  std::vector<Sortie> base = given_base != nullptr ? *given_base : plan.uavs.at(index).sorties;
  if (base.empty()) base = {L.build(0, n - 1)};
  auto items_of = [&](const Sortie& s) { return count(sortie_plan(plan, index, s), index); };
  for (const Sortie& whole : base) {
    auto a = static_cast<std::size_t>(whole.first_waypoint);
    const auto last = static_cast<std::size_t>(whole.last_waypoint);
    for (;;) {
      // the whole rest as the plan has it (its own transits), or cut: the last b that fits, by bisection
      Sortie rest = a == static_cast<std::size_t>(whole.first_waypoint) ? whole : L.build(a, last);
      if (items_of(rest) <= capacity) {
        out.push_back(std::move(rest));
        break;
      }
      const std::size_t bmin = L.ends_part(a) ? a : a + 1;
      Sortie piece = L.build(a, bmin);
      if (bmin >= last || items_of(piece) > capacity)
        throw InputError(
            "max_mission_items",
            fmt::format("UAV \"{}\": the mission of the coverage leg from waypoint {} to {} alone "
                        "has {} items, more than the vehicle stores ({})",
                        L.up.id, a, bmin, items_of(piece), capacity));
      std::size_t lo = bmin, hi = last;  // lo fits, hi does not
      while (hi - lo > 1) {
        const std::size_t mid = lo + (hi - lo) / 2;
        Sortie s = L.build(a, mid);
        if (items_of(s) <= capacity) {
          lo = mid;
          piece = std::move(s);
        } else {
          hi = mid;
        }
      }
      if (piece.last_waypoint != static_cast<int>(lo)) piece = L.build(a, lo);
      out.push_back(std::move(piece));
      a = L.ends_part(lo) ? lo + 1 : lo;
      if (a > last) break;
    }
  }
  for (std::size_t k = 0; k < out.size(); ++k) out[k].index = static_cast<int>(k);
  return out;
}

void rebuild_sorties(const Plan& plan, std::size_t index, std::vector<Sortie>& sorties,
                     const std::string& field) {
  const Geo geo(plan);
  const Layout L(plan, index, geo);
  const std::size_t n = L.n();
  if (n == 0 && !sorties.empty()) throw InputError(field, "a UAV without coverage has no sorties");
  if (sorties.empty()) return;  // none: a leg did not fit one battery when the plan was made
  std::size_t expected = 0;
  for (std::size_t k = 0; k < sorties.size(); ++k) {
    const std::string f = fmt::format("{}[{}]", field, k);
    Sortie& s = sorties[k];
    if (s.index != static_cast<int>(k)) throw InputError(f + ".index", fmt::format("expected {}", k));
    if (s.first_waypoint != static_cast<int>(expected))
      throw InputError(f + ".first_waypoint",
                       fmt::format("expected {} (sorties follow each other)", expected));
    if (s.last_waypoint < s.first_waypoint || s.last_waypoint >= static_cast<int>(n))
      throw InputError(f + ".last_waypoint",
                       fmt::format("must be in [{}, {}]", s.first_waypoint, static_cast<int>(n) - 1));
    const auto a = static_cast<std::size_t>(s.first_waypoint), b = static_cast<std::size_t>(s.last_waypoint);
    if (a == b && !L.ends_part(a))
      throw InputError(f + ".last_waypoint", "a sortie inside a coverage part flies at least one leg");
    if (s.parts.size() != 2) throw InputError(f, "expected the transit out and back");
    auto check_transit = [&](const PathPart& t, Point from, Point to, const std::string& name) {
      if (t.local.empty()) {
        if (bg::distance(from, to) > 0.01) throw InputError(f + "." + name, "missing");
        return;
      }
      if (t.local.size() < 2 || bg::distance(t.local.front(), from) > 0.01 ||
          bg::distance(t.local.back(), to) > 0.01)
        throw InputError(f + "." + name, "does not join take-off and the sortie's waypoint");
    };
    const PathPart out = s.parts[0], back = s.parts[1];
    check_transit(out, L.start, L.entry(a), "transit_out");  // to the lead-in's start (issue 31)
    check_transit(back, L.at(b), L.start, "transit_back");
    const int index_kept = s.index;
    s = L.build(a, b, out, back);
    s.index = index_kept;
    expected = L.ends_part(b) ? b + 1 : b;
    if (b + 1 == n && k + 1 != sorties.size())
      throw InputError(fmt::format("{}[{}]", field, k + 1), "follows the sortie that ends the coverage");
  }
  if (n > 0 && sorties.back().last_waypoint != static_cast<int>(n) - 1)
    throw InputError(field, fmt::format("the sorties end at waypoint {}, the coverage at {}",
                                        sorties.back().last_waypoint, n - 1));
}

Plan sortie_plan(const Plan& plan, std::size_t index, const Sortie& sortie) {
  Plan p = plan;
  UavPlan& up = p.uavs.at(index);
  up.parts = sortie.parts;
  up.length_m = sortie.length_m;
  up.turns = sortie.turns;
  up.coverage_length_m = 0.0;
  for (const auto& part : up.parts)
    if (part.kind == PartKind::Coverage) up.coverage_length_m += geometry::length(part.local);
  up.sorties = {sortie};
  return p;
}

std::vector<Sortie> resume_sorties(const Plan& plan, std::size_t index, int last_reached) {
  const Geo geo(plan);
  const Layout L(plan, index, geo);
  const int n = static_cast<int>(L.n());
  if (last_reached < -1 || last_reached >= n)
    throw InputError("last_reached_waypoint", fmt::format("must be in [-1, {}] for UAV \"{}\" ({} coverage "
                                                          "waypoints)",
                                                          n - 1, L.up.id, n));
  std::vector<Sortie> all = plan.uavs[index].sorties;
  if (all.empty() && n > 0) all = cut(L, budget_min(plan, index));
  std::vector<Sortie> out;
  for (const auto& s : all) {
    if (s.last_waypoint <= last_reached) continue;  // flown
    if (s.first_waypoint > last_reached || !out.empty()) {
      out.push_back(s);
      continue;
    }
    // the current sortie: out from take-off to where coverage stopped, the rest, back
    const auto r = static_cast<std::size_t>(last_reached);
    const std::size_t a = L.ends_part(r) ? r + 1 : r;
    Sortie rest = L.build(a, static_cast<std::size_t>(s.last_waypoint));
    rest.index = s.index;
    out.push_back(std::move(rest));
  }
  return out;
}

std::vector<std::vector<waypoints::MissionItem>> resume_items(const Plan& plan, std::size_t index,
                                                              int last_reached,
                                                              const waypoints::AltitudeOptions& altitude) {
  std::vector<std::vector<waypoints::MissionItem>> out;
  for (const auto& s : resume_sorties(plan, index, last_reached)) {
    auto items = waypoints::mission_items(sortie_plan(plan, index, s), index, altitude);
    for (auto& it : items)
      if (it.waypoint >= 0) it.waypoint += s.first_waypoint;
    out.push_back(std::move(items));
  }
  return out;
}

}  // namespace uavcover::sorties
