#include "planners/milp/milp.hpp"

#include "planners/corridor/corridor.hpp"
#include "planners/structure/structure.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numbers>
#include <numeric>
#include <set>

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/biconnected_components.hpp>

#include "geometry/geometry.hpp"
#include "planners/milp/lines.hpp"
#include "planners/milp/model.hpp"
#include "uavcover/error.hpp"

namespace uavcover::planners {

namespace {

using milp::Instance;
using milp::Routes;
using milp::Segment;

constexpr double kPi = std::numbers::pi;
constexpr const char* kStage = "milp";

/// Past the deadline the warm starts are returned as they are; only a stop request ends the work.
void stop_check(const Context& ctx) {
  if (ctx.stop_requested()) ctx.check();
}

/// Degrees clockwise from north <-> radians counter-clockwise from east (the boustrophedon's convention).
double from_bearing(double deg) { return kPi / 2 - deg * kPi / 180.0; }
double to_bearing(double rad) {
  double b = std::fmod(90.0 - rad * 180.0 / kPi, 180.0);
  if (b < 0) b += 180.0;
  return std::round(b * 1e6) / 1e6;
}

struct Params {
  std::optional<double> angle;
  milp::Direction direction = milp::Direction::LongestEdge;
  int max_segments = 12;
  int max_uavs = 1;
  long long node_limit = 100;
  double time_limit_s = 10.0;
  double nearby_penalty = 10.0;
  std::string model = "auto";
};

/// Coverage mode: extended legs end at least this far from no-fly zones (as the segments do).
constexpr double kCoverageClearanceM = 0.5;

/// `model: auto` uses the exact model up to this many pairs (waypoint pairs: segments or blocks).
constexpr int kExactMaxPairs = 4;

milp::Formulation formulation(const std::string& model, int pairs) {
  if (model == "exact") return milp::Formulation::Exact;
  if (model == "contracted") return milp::Formulation::Contracted;
  return pairs <= kExactMaxPairs ? milp::Formulation::Exact : milp::Formulation::Contracted;
}

Params read_params(const nlohmann::json& j) {
  Params p;
  if (!j.is_object()) return p;
  if (j.contains("angle_deg") && j["angle_deg"].is_number())
    p.angle = from_bearing(j["angle_deg"].get<double>());
  if (j.contains("direction") && j["direction"].is_string() && j["direction"] == "auto")
    p.direction = milp::Direction::Auto;
  auto num = [&](const char* k, auto& v) {
    if (j.contains(k) && j[k].is_number()) v = j[k].get<std::decay_t<decltype(v)>>();
  };
  num("max_segments", p.max_segments);
  num("max_uavs_per_milp", p.max_uavs);
  num("node_limit", p.node_limit);
  num("time_limit_s", p.time_limit_s);
  num("nearby_penalty", p.nearby_penalty);
  if (j.contains("model") && j["model"].is_string()) p.model = j["model"].get<std::string>();
  return p;
}

/// Transit distances: straight where clear of the no-fly zones, else the engine's route around them.
class Transit {
 public:
  explicit Transit(const MultiPolygon& no_fly) : router_(no_fly), any_(!no_fly.empty()) {}
  [[nodiscard]] double operator()(Point a, Point b) const {
    if (!any_ || router_.clear(a, b)) return boustro::dist(a, b);
    return geometry::length(router_.route(a, b));
  }

 private:
  geometry::Router router_;
  bool any_;
};

/// What the MILP assigns: one segment, or a block of neighbouring segments flown back and forth.
struct Item {
  std::vector<std::pair<int, bool>> legs;  ///< segment, flown from its high end (b) to its low end (a)
  Point entry, exit;
  double inner = 0.0;  ///< legs and the transits between them
};

std::pair<Point, Point> leg_ends(const Segment& s, bool reversed) {
  return reversed ? std::pair{s.b, s.a} : std::pair{s.a, s.b};
}

/// One item: the segments `legs` (neighbours on consecutive lines) flown back and forth in that order.
Item make_item(const std::vector<Segment>& segs, const std::vector<int>& legs, const Transit& transit) {
  Item it;
  for (std::size_t i = 0; i < legs.size(); ++i) {
    const bool rev = i % 2 == 1;
    const auto [p, q] = leg_ends(segs[static_cast<std::size_t>(legs[i])], rev);
    if (!it.legs.empty()) it.inner += transit(it.exit, p);
    it.inner += boustro::dist(p, q);
    if (it.legs.empty()) it.entry = p;
    it.exit = q;
    it.legs.emplace_back(legs[i], rev);
  }
  return it;
}

/// Cuts `work` (in order) into runs whose totals follow `weights` (summing to 1): `counts[g]` items for
/// run g, each run at least `min_items[g]` items when there are enough. Each cut sits just before or
/// after its cumulative target; with up to 12 runs every combination is tried and the one with the
/// smallest largest share error wins, beyond that the nearer side is taken.
std::vector<int> split_by_share(const std::vector<double>& work, const std::vector<double>& weights,
                                const std::vector<int>& min_items) {
  const std::size_t n = work.size(), g = weights.size();
  std::vector<double> cum(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) cum[i + 1] = cum[i] + work[i];
  const double total = cum[n];
  const bool enough = static_cast<int>(n) >= std::accumulate(min_items.begin(), min_items.end(), 0);
  // candidate positions of each cut: the two items around the cumulative target
  std::vector<std::array<std::size_t, 2>> cand(g > 0 ? g - 1 : 0);
  std::vector<double> targets(cand.size());
  double target = 0.0;
  for (std::size_t r = 0; r + 1 < g; ++r) {
    target += weights[r] * total;
    targets[r] = target;
    const auto it = std::lower_bound(cum.begin(), cum.end(), target);
    const std::size_t hi = std::min<std::size_t>(static_cast<std::size_t>(it - cum.begin()), n);
    cand[r] = {hi > 0 ? hi - 1 : 0, hi};
  }
  auto counts_of = [&](const std::vector<std::size_t>& cuts) {
    std::vector<int> c(g, 0);
    std::size_t at = 0;
    int need_after = std::accumulate(min_items.begin(), min_items.end(), 0);
    for (std::size_t r = 0; r < g; ++r) {
      need_after -= min_items[r];
      std::size_t end = r + 1 == g ? n : cuts[r];
      if (enough && r + 1 < g) {
        end = std::max(end, at + static_cast<std::size_t>(min_items[r]));
        end = std::min(end, n - static_cast<std::size_t>(need_after));
      }
      end = std::clamp(end, at, n);
      c[r] = static_cast<int>(end - at);
      at = end;
    }
    return c;
  };
  auto error_of = [&](const std::vector<int>& c) {
    double worst = 0.0;
    std::size_t at = 0;
    for (std::size_t r = 0; r < g; ++r) {
      const std::size_t end = at + static_cast<std::size_t>(c[r]);
      worst = std::max(worst, std::abs((cum[end] - cum[at]) / std::max(total, 1e-300) - weights[r]));
      at = end;
    }
    return worst;
  };
  std::vector<std::size_t> cuts(cand.size());
  for (std::size_t r = 0; r < cand.size(); ++r)  // nearer side
    cuts[r] = std::abs(cum[cand[r][0]] - targets[r]) < std::abs(cum[cand[r][1]] - targets[r]) ? cand[r][0]
                                                                                              : cand[r][1];
  std::vector<int> best = counts_of(cuts);
  if (cand.size() <= 11) {
    double best_err = error_of(best);
    for (std::size_t mask = 0; mask < (std::size_t{1} << cand.size()); ++mask) {
      for (std::size_t r = 0; r < cand.size(); ++r) cuts[r] = cand[r][(mask >> r) & 1];
      const std::vector<int> c = counts_of(cuts);
      const double e = error_of(c);
      if (e < best_err - 1e-12) best_err = e, best = c;
    }
  }
  return best;
}

/// One MILP: some UAVs (in the instance's order) and the items they share.
struct Cluster {
  std::vector<int> uavs;  ///< problem indices
  std::vector<Item> items;
};

/// Builds the instance: depots, then each item's entry and exit.
Instance make_instance(const Cluster& cl, const std::vector<Point>& starts, const std::vector<double>& shares,
                       const Transit& transit, double penalty, std::vector<Point>& pos, const Context& ctx) {
  Instance in;
  in.uavs = static_cast<int>(cl.uavs.size());
  in.pairs = static_cast<int>(cl.items.size());
  pos.clear();
  for (int k : cl.uavs) pos.push_back(starts[static_cast<std::size_t>(k)]);
  for (const auto& it : cl.items) {
    pos.push_back(it.entry);
    pos.push_back(it.exit);
  }
  const int n = in.nodes(), m = in.uavs;
  in.cost.assign(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      if (j % 64 == 0) stop_check(ctx);  // thousands of routed transits on fields cut by many zones
      double c;
      if (i >= m && (i - m) % 2 == 0 && j == i + 1)
        c = cl.items[static_cast<std::size_t>((i - m) / 2)].inner;  // the pair's own edge: its legs
      else
        c = transit(pos[static_cast<std::size_t>(i)], pos[static_cast<std::size_t>(j)]);
      // the paper's penalty on edges between waypoints that are not nearby (numbers more than 2 apart)
      if (i >= m && j - i > 2) c *= penalty;
      const auto ui = static_cast<std::size_t>(i), uj = static_cast<std::size_t>(j),
                 un = static_cast<std::size_t>(n);
      in.cost[ui * un + uj] = in.cost[uj * un + ui] = c;
    }
  double sum = 0.0;
  for (int k : cl.uavs) sum += shares[static_cast<std::size_t>(k)];
  for (int k : cl.uavs) in.weight.push_back(sum > 0 ? shares[static_cast<std::size_t>(k)] * m / sum : 1.0);
  return in;
}

/// Contiguous runs of the items, `counts[k]` for UAV k in numbering order, each flown forwards or
/// backwards (whichever is shorter), every item entered at its end nearer the previous exit.
Routes runs(const Instance& in, const std::vector<int>& counts) {
  const int m = in.uavs;
  Routes r;
  int at = 0;
  for (int k = 0; k < m; ++k) {
    const int n = counts[static_cast<std::size_t>(k)];
    std::vector<int> best{k};
    double best_d = 1e300;
    for (int dir = 0; dir < 2; ++dir) {
      std::vector<int> q{k};
      double d = 0.0;
      int here = k;
      for (int t = 0; t < n; ++t) {
        const int p = dir == 0 ? at + t : at + n - 1 - t;
        const int a = m + 2 * p, b = a + 1;
        const bool fwd = in.c(here, a) <= in.c(here, b);
        q.push_back(fwd ? a : b);
        q.push_back(fwd ? b : a);
        d += in.c(here, q[q.size() - 2]) + in.c(a, b);
        here = q.back();
      }
      if (here != k) d += in.c(here, k);
      if (d < best_d) best_d = d, best = std::move(q);
    }
    r.seq.push_back(std::move(best));
    at += n;
  }
  return r;
}

/// The warm start: contiguous runs of items split by share (`runs`), then each cut between two UAVs
/// moved by one item at a time while objective (8) improves.
Routes warm_start(const Instance& in, const Cluster& cl) {
  const int m = in.uavs;
  std::vector<double> work;
  for (const auto& it : cl.items) work.push_back(it.inner);
  std::vector<double> w;
  for (double x : in.weight) w.push_back(x / m);
  std::vector<int> counts = split_by_share(work, w, std::vector<int>(static_cast<std::size_t>(m), 1));
  Routes best = runs(in, counts);
  double best_o = milp::objective(in, best);
  const int least = in.pairs >= m ? 1 : 0;  // constraint (6)
  for (bool improved = true; improved;) {   // ends: every move lowers the objective
    improved = false;
    for (std::size_t k = 0; k + 1 < counts.size(); ++k)
      for (int delta : {-1, 1}) {
        std::vector<int> c = counts;
        c[k] += delta;
        c[k + 1] -= delta;
        if (c[k] < least || c[k + 1] < least) continue;
        Routes r = runs(in, c);
        const double o = milp::objective(in, r);
        if (o < best_o - 1e-9) {
          best = std::move(r);
          best_o = o;
          counts = std::move(c);
          improved = true;
        }
      }
  }
  return best;
}

/// The items of a set of segments (`members`, ascending): one per segment, or, when there are more
/// than `max_items`, blocks cut from its chains. A chain is a run of segments on consecutive lines of
/// one part where each overlaps only the next (a sweep cell): a block never jumps across a gap.
std::vector<Item> items_for(const std::vector<Segment>& segs, const std::vector<std::vector<int>>& adj,
                            const std::vector<int>& members, int max_items, const Transit& transit) {
  std::vector<Item> out;
  if (members.empty()) return out;
  std::vector<char> mine(segs.size(), 0);
  for (int s : members) mine[static_cast<std::size_t>(s)] = 1;
  auto on_line = [&](int s, int part, int line) {
    const Segment& g = segs[static_cast<std::size_t>(s)];
    return mine[static_cast<std::size_t>(s)] && g.part == part && g.line == line;
  };
  std::vector<std::vector<int>> chains;
  std::vector<int> chain_of(segs.size(), -1);
  for (int s : members) {
    const Segment& g = segs[static_cast<std::size_t>(s)];
    int prev = -1, before = 0;
    for (int t : adj[static_cast<std::size_t>(s)])
      if (on_line(t, g.part, g.line - 1)) prev = t, ++before;
    bool extends = false;
    if (before == 1) {
      int after = 0;
      for (int u : adj[static_cast<std::size_t>(prev)])
        if (on_line(u, g.part, g.line)) ++after;
      extends = after == 1 &&
                chains[static_cast<std::size_t>(chain_of[static_cast<std::size_t>(prev)])].back() == prev;
    }
    if (extends) {
      chain_of[static_cast<std::size_t>(s)] = chain_of[static_cast<std::size_t>(prev)];
    } else {
      chain_of[static_cast<std::size_t>(s)] = static_cast<int>(chains.size());
      chains.emplace_back();
    }
    chains[static_cast<std::size_t>(chain_of[static_cast<std::size_t>(s)])].push_back(s);
  }
  const int count = static_cast<int>(members.size());
  const int blocks = std::max(max_items, static_cast<int>(chains.size()));
  for (const auto& chain : chains) {
    const int n = static_cast<int>(chain.size());
    const int b =
        count <= max_items
            ? n
            : std::clamp(static_cast<int>(std::lround(static_cast<double>(blocks) * n / count)), 1, n);
    for (int i = 0; i < b; ++i) {
      const auto lo = static_cast<std::size_t>(static_cast<long long>(n) * i / b);
      const auto hi = static_cast<std::size_t>(static_cast<long long>(n) * (i + 1) / b);
      if (hi > lo)
        out.push_back(make_item(segs,
                                std::vector<int>(chain.begin() + static_cast<std::ptrdiff_t>(lo),
                                                 chain.begin() + static_cast<std::ptrdiff_t>(hi)),
                                transit));
    }
  }
  return out;
}

/// Cut vertices of the graph of the segments nobody owns yet (Boost.Graph).
std::vector<char> cut_vertices(const std::vector<std::vector<int>>& adj, const std::vector<int>& owner) {
  using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS>;
  std::vector<int> local(adj.size(), -1), global;
  for (std::size_t i = 0; i < adj.size(); ++i)
    if (owner[i] < 0) local[i] = static_cast<int>(global.size()), global.push_back(static_cast<int>(i));
  Graph g(global.size());
  for (int i : global)
    for (int j : adj[static_cast<std::size_t>(i)])
      if (i < j && owner[static_cast<std::size_t>(j)] < 0)
        boost::add_edge(static_cast<std::size_t>(local[static_cast<std::size_t>(i)]),
                        static_cast<std::size_t>(local[static_cast<std::size_t>(j)]), g);
  std::vector<std::size_t> points;
  boost::articulation_points(g, std::back_inserter(points));
  std::vector<char> cut(adj.size(), 0);
  for (std::size_t v : points) cut[static_cast<std::size_t>(global[v])] = 1;
  return cut;
}

/// Connected parts of the unowned segments without `skip`, largest work first.
std::vector<std::pair<double, std::vector<int>>> parts_without(const std::vector<std::vector<int>>& adj,
                                                               const std::vector<int>& owner,
                                                               const std::vector<double>& work, int skip) {
  std::vector<std::pair<double, std::vector<int>>> out;
  std::vector<char> seen(adj.size(), 0);
  for (std::size_t s = 0; s < adj.size(); ++s) {
    if (seen[s] || owner[s] >= 0 || static_cast<int>(s) == skip) continue;
    std::pair<double, std::vector<int>> comp{0.0, {}};
    std::vector<int> stack{static_cast<int>(s)};
    seen[s] = 1;
    while (!stack.empty()) {
      const int u = stack.back();
      stack.pop_back();
      comp.first += work[static_cast<std::size_t>(u)];
      comp.second.push_back(u);
      for (int v : adj[static_cast<std::size_t>(u)])
        if (!seen[static_cast<std::size_t>(v)] && owner[static_cast<std::size_t>(v)] < 0 && v != skip)
          seen[static_cast<std::size_t>(v)] = 1, stack.push_back(v);
    }
    out.push_back(std::move(comp));
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  return out;
}

/// Segments and the group (cluster) of each, from `connected_groups`.
struct Grouping {
  std::vector<Segment> segments;  ///< part by part, line by line, low to high (cut segments included)
  std::vector<int> group;
};

/// The segments of each cluster: grown one group after the other from one end of the sweep order
/// (`descending`: from the other end, last group first), each taking the frontier segment first in
/// that order whose removal keeps the rest connected, so every group and the rest stay connected.
/// Where every frontier segment holds the rest together, it is taken with the parts it cuts off (all
/// but the largest). Where a take would overshoot the group's share of the line length, a frontier
/// segment is cut instead: the piece at its end next to the group goes to the group, as long as the
/// share needs (or as the rest's connectivity allows), the other piece stays with the rest; both
/// pieces are at least `min_piece` long. A group takes at least `sizes[g]` segments when there are
/// enough. Returns the segments (with the cuts) and the group of each.
Grouping connected_groups(const milp::Lines& lines, const std::vector<double>& shares,
                          const std::vector<int>& sizes, bool descending, double min_piece,
                          const Context& ctx) {
  std::vector<Segment> segs = lines.segments;
  std::vector<std::vector<int>> adj = milp::adjacency(lines);
  const int S = static_cast<int>(segs.size()), C = static_cast<int>(shares.size());
  auto frame = [&](int s) -> const boustro::Frame& {
    return lines.parts[static_cast<std::size_t>(segs[static_cast<std::size_t>(s)].part)].frame;
  };
  // each segment's span along its line (frame Y) and its work (length: the scanned area per width)
  std::vector<double> lo, hi, work;
  for (int s = 0; s < S; ++s) {
    const double y0 = frame(s).to(segs[static_cast<std::size_t>(s)].a).y();
    const double y1 = frame(s).to(segs[static_cast<std::size_t>(s)].b).y();
    lo.push_back(std::min(y0, y1));
    hi.push_back(std::max(y0, y1));
    work.push_back(hi.back() - lo.back());
  }
  std::vector<int> owner(static_cast<std::size_t>(S), -1);
  const double total = std::accumulate(work.begin(), work.end(), 0.0);
  auto key = [&](int s) { return descending ? S - 1 - s : s; };
  auto at = [](auto& v, int i) -> auto& { return v[static_cast<std::size_t>(i)]; };
  // whether segment t is a neighbour of the span [a, b] on the line of segment s
  auto touches = [&](int t, int s, double a, double b) {
    const Segment &gt = at(segs, t), &gs = at(segs, s);
    if (gt.part != gs.part) return true;  // the link between parts
    if (gt.line == gs.line) return std::abs(at(hi, t) - a) < 1e-6 || std::abs(b - at(lo, t)) < 1e-6;
    return std::abs(gt.line - gs.line) == 1 && std::max(at(lo, t), a) < std::min(at(hi, t), b) - 1e-9;
  };
  // whether the unowned segments stay connected with segment s shortened to [a, b]
  auto rest_connected = [&](int s, double a, double b) {
    std::vector<char> seen(adj.size(), 0);
    std::vector<int> stack{s};
    at(seen, s) = 1;
    std::size_t reached = 0, unowned = 0;
    for (int o : owner) unowned += o < 0 ? 1 : 0;
    while (!stack.empty()) {
      const int u = stack.back();
      stack.pop_back();
      ++reached;
      for (int v : at(adj, u)) {
        if (at(seen, v) || at(owner, v) >= 0) continue;
        if ((u == s && !touches(v, s, a, b)) || (v == s && !touches(u, s, a, b))) continue;
        at(seen, v) = 1;
        stack.push_back(v);
      }
    }
    return reached == unowned;
  };
  // the longest piece (at most `need`) group g can cut from segment s: {length, piece at the high end};
  // the piece touches g's segments, unless it is g's first (`first`)
  auto best_cut = [&](int s, int g, double need, bool first) {
    std::pair<double, bool> best{0.0, false};
    const double len = at(work, s);
    if (len < 2.0 * min_piece) return best;
    for (const bool high : {true, false}) {
      std::vector<double> cand{std::clamp(need, min_piece, len - min_piece)};
      for (int t : at(adj, s))  // where the rest keeps (just) its overlap with a neighbour
        if (at(owner, t) < 0)
          cand.push_back(high ? at(hi, s) - at(lo, t) - min_piece : at(hi, t) - min_piece - at(lo, s));
      for (double a : cand) {
        if (!(a >= min_piece - 1e-9 && a <= std::min(need, len - min_piece) + 1e-9) || a <= best.first)
          continue;
        const double c = high ? at(hi, s) - a : at(lo, s) + a;
        const double alo = high ? c : at(lo, s), ahi = high ? at(hi, s) : c;
        const auto& n = at(adj, s);
        if (!first && !std::any_of(n.begin(), n.end(),
                                   [&](int t) { return at(owner, t) == g && touches(t, s, alo, ahi); }))
          continue;
        if (!rest_connected(s, high ? at(lo, s) : c, high ? c : at(hi, s))) continue;
        best = {a, high};
      }
    }
    return best;
  };
  // cuts segment s: its piece of length `a` at one end (the high one or the low one) becomes a new segment
  auto cut_segment = [&](int s, double a, bool high) {
    const int n = static_cast<int>(segs.size());
    const boustro::Frame& f = frame(s);
    const double x = f.to(at(segs, s).a).x(), c = high ? at(hi, s) - a : at(lo, s) + a;
    Segment piece = at(segs, s);
    const double plo = high ? c : at(lo, s), phi = high ? at(hi, s) : c;
    piece.a = f.from(Point{x, plo});
    piece.b = f.from(Point{x, phi});
    Segment& rest = at(segs, s);
    if (high)
      rest.b = piece.a;
    else
      rest.a = piece.b;
    segs.push_back(piece);
    const double rlo = high ? at(lo, s) : c, rhi = high ? c : at(hi, s);
    lo.push_back(plo);
    hi.push_back(phi);
    work.push_back(a);
    owner.push_back(-1);
    adj.emplace_back();
    const std::vector<int> old = at(adj, s);
    at(adj, s).clear();
    at(lo, s) = rlo, at(hi, s) = rhi, at(work, s) = rhi - rlo;
    for (int t : old) {
      auto& back = at(adj, t);
      std::erase(back, s);
      if (touches(t, s, rlo, rhi)) at(adj, s).push_back(t), back.push_back(s);
      if (touches(t, s, plo, phi)) at(adj, n).push_back(t), back.push_back(n);
    }
    at(adj, s).push_back(n);
    at(adj, n).push_back(s);
    return n;
  };
  int left = S, need_after = std::accumulate(sizes.begin(), sizes.end(), 0);
  std::vector<char> cut;
  bool cut_known = false;
  auto is_cut = [&](int s) {
    int degree = 0;
    for (int t : at(adj, s)) degree += at(owner, t) < 0 ? 1 : 0;
    if (degree <= 1) return false;
    if (!cut_known) cut = cut_vertices(adj, owner), cut_known = true;
    return at(cut, s) != 0;
  };
  for (int step = 0; step + 1 < C; ++step) {
    stop_check(ctx);
    const int g = descending ? C - 1 - step : step;
    need_after -= sizes[static_cast<std::size_t>(g)];
    const double target = shares[static_cast<std::size_t>(g)] * total;
    double acc = 0.0;
    int taken = 0;
    std::set<std::pair<int, int>> frontier;  // (key, segment)
    auto own = [&](int s) {
      at(owner, s) = g;
      acc += at(work, s);
      ++taken;
      frontier.erase({key(s), s});
      for (int u : at(adj, s))
        if (at(owner, u) < 0) frontier.insert({key(u), u});
    };
    while (left > 0) {
      if (taken % 64 == 63) stop_check(ctx);
      std::vector<int> pool;
      if (!frontier.empty())
        for (const auto& [k, s] : frontier) pool.push_back(s);
      else
        for (int k = 0; k < S; ++k)
          if (const int s = descending ? S - 1 - k : k; at(owner, s) < 0) pool.push_back(s);
      std::vector<int> take;
      for (int s : pool)
        if (!is_cut(s)) {
          take = {s};
          break;
        }
      if (take.empty()) {
        take = {pool.front()};
        const auto parts = parts_without(adj, owner, work, pool.front());
        for (std::size_t i = 1; i < parts.size(); ++i)
          take.insert(take.end(), parts[i].second.begin(), parts[i].second.end());
      }
      double amount = 0.0;
      for (int s : take) amount += at(work, s);
      // a group's first segment is cut too when whole it would overshoot the share by more than the
      // share, or leave too few segments for the groups after it (a few long lines among many UAVs:
      // a 4 km x 150 m strip has 3 lines for 6 UAVs)
      const bool first =
          taken == 0 && take.size() == 1 && (amount - target > target || left - 1 < need_after);
      // a cut too where taking `take` whole would leave too few segments for the groups after this one
      const bool too_few_left = left - static_cast<int>(take.size()) < need_after;
      if ((taken > 0 || first) && (acc + amount > target + 1e-9 || too_few_left) &&
          target - acc >= min_piece) {
        // a cut of one of the first frontier segments (a bounded number of tries)
        std::tuple<double, int, bool> best{0.0, -1, false};
        for (std::size_t i = 0; i < pool.size() && i < 16; ++i) {
          const auto [a, high] = best_cut(pool[i], g, target - acc, first);
          if (a > std::get<0>(best) + 1e-9) best = {a, pool[i], high};
        }
        if (std::get<1>(best) >= 0) {
          own(cut_segment(std::get<1>(best), std::get<0>(best), std::get<2>(best)));
          cut_known = false;
          continue;
        }
      }
      if (taken >= sizes[static_cast<std::size_t>(g)] &&
          (acc >= target - 1e-9 || acc + amount - target > target - acc))
        break;
      if (too_few_left) break;
      for (int s : take) {
        own(s);
        --left;
      }
      cut_known = false;
    }
  }
  for (auto& o : owner)
    if (o < 0) o = descending ? 0 : C - 1;
  // back to the sweep order: part by part, line by line, low to high
  std::vector<int> order(segs.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int x, int y) {
    return std::tuple(at(segs, x).part, at(segs, x).line, at(lo, x)) <
           std::tuple(at(segs, y).part, at(segs, y).line, at(lo, y));
  });
  Grouping out;
  for (int s : order) out.segments.push_back(at(segs, s)), out.group.push_back(at(owner, s));
  return out;
}

/// The largest difference between a group's part of the work and its share.
double share_error(const std::vector<int>& group, const std::vector<double>& work,
                   const std::vector<double>& shares) {
  std::vector<double> got(shares.size(), 0.0);
  double total = 0.0;
  for (std::size_t s = 0; s < group.size(); ++s)
    got[static_cast<std::size_t>(group[s])] += work[s], total += work[s];
  double worst = 0.0;
  for (std::size_t g = 0; g < shares.size(); ++g)
    worst = std::max(worst, std::abs(got[g] / std::max(total, 1e-300) - shares[g]));
  return worst;
}

class MilpPlanner final : public Planner {
 public:
  [[nodiscard]] Assignment plan(const Problem& p, const nlohmann::json& params,
                                const Context& ctx) const override {
    // a corridor: its lanes cut across by share (docs/patterns.md), the same for every lane planner
    if (!p.corridor_line.empty()) return corridor::plan(p, ctx);
    // a structure: the facade orbits (docs/patterns.md), the same for every planner that flies them
    if (p.structure) return structure::plan(p, ctx);
    if (p.pattern) {  // its MILP orders fixed line segments: the options are for its corridors only
      const Pattern& pt = *p.pattern;
      const char* asked = pt.crosshatch              ? "crosshatch"
                          : pt.turnaround_m > 0      ? "turnaround_m"
                          : pt.entry != "auto"       ? "entry"
                          : pt.alternate_transects   ? "alternate_transects"
                          : pt.capture_in_turnaround ? "capture_in_turnaround"
                                                     : nullptr;
      if (asked != nullptr)
        throw InputError(std::string("pattern.") + asked,
                         "planner \"milp\" supports the pattern options for corridors only");
    }
    stop_check(ctx);
    ctx.report(kStage, 0.0);
    const std::size_t m = p.starts.size();
    if (m == 0) throw InputError("uavs", "at least one UAV is needed");
    if (p.shares.size() != m) throw InputError("uavs", "one share per UAV is needed");
    if (!(p.spacing_m > 0.0) || !std::isfinite(p.spacing_m))
      throw InputError("spacing_m", "the line spacing must be a positive number of metres");
    const Params par = read_params(params);
    const auto t0 = std::chrono::steady_clock::now();

    Assignment out;
    out.uavs.resize(m);
    milp::Lines lines = milp::build_lines(p.free, p.no_fly, p.spacing_m, par.direction, par.angle, ctx);
    // coverage mode: legs past the outer boundary (the strips, adjacency and regions keep the lines' own)
    auto legs_of = [&](const milp::Lines& l) {
      return p.mode == Mode::Coverage
                 ? milp::extended_for_coverage(l, p.area, p.no_fly, p.footprint_m, kCoverageClearanceM)
                 : l.segments;
    };
    std::vector<Segment> segs = legs_of(lines);
    int S = static_cast<int>(segs.size());
    ctx.report(kStage, 0.05);
    const Transit transit(p.no_fly);
    const auto t_lines = std::chrono::steady_clock::now();

    // UAVs in the order of the segment nearest to their start, then clusters of consecutive UAVs
    std::vector<int> order(m);
    std::iota(order.begin(), order.end(), 0);
    std::vector<int> nearest(m, 0);
    for (std::size_t k = 0; k < m; ++k) {
      double best = 1e300;
      for (int s = 0; s < S; ++s) {
        const double d =
            bg::distance(p.starts[k], bg::model::segment<Point>{segs[static_cast<std::size_t>(s)].a,
                                                                segs[static_cast<std::size_t>(s)].b});
        if (d < best - 1e-9) best = d, nearest[k] = s;
      }
    }
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return nearest[static_cast<std::size_t>(a)] < nearest[static_cast<std::size_t>(b)];
    });
    const int M = static_cast<int>(m);
    int C = 1;
    if (S > par.max_segments || M > par.max_uavs)
      C = std::clamp(
          std::max((M + par.max_uavs - 1) / par.max_uavs, (S + par.max_segments - 1) / par.max_segments), 1,
          M);
    std::vector<Cluster> clusters(static_cast<std::size_t>(C));
    std::vector<double> group_share(static_cast<std::size_t>(C), 0.0);
    std::vector<int> group_size(static_cast<std::size_t>(C), 0);
    for (int g = 0; g < C; ++g)
      for (int i = g * M / C; i < (g + 1) * M / C; ++i) {
        const int k = order[static_cast<std::size_t>(i)];
        clusters[static_cast<std::size_t>(g)].uavs.push_back(k);
        group_share[static_cast<std::size_t>(g)] += p.shares[static_cast<std::size_t>(k)];
        ++group_size[static_cast<std::size_t>(g)];
      }
    const double share_sum = std::accumulate(group_share.begin(), group_share.end(), 0.0);
    for (auto& g : group_share) g = share_sum > 0 ? g / share_sum : 1.0 / C;
    // each cluster's segments connected (grown from both ends of the sweep order, the nearer shares of
    // the line length win), the segments at the ends of each cluster cut where its share is met
    std::vector<int> group(static_cast<std::size_t>(S), 0);
    if (C > 1) {
      auto error = [&](const Grouping& gr) {
        std::vector<double> len;
        for (const auto& s : gr.segments) len.push_back(s.length());
        return share_error(gr.group, len, group_share);
      };
      Grouping best = connected_groups(lines, group_share, group_size, false, p.spacing_m, ctx);
      Grouping other = connected_groups(lines, group_share, group_size, true, p.spacing_m, ctx);
      if (error(other) < error(best) - 1e-12) best = std::move(other);
      lines.segments = std::move(best.segments);
      group = std::move(best.group);
      segs = legs_of(lines);
      S = static_cast<int>(segs.size());
      // legs end milp::kCutGapM short of a cut (the pieces of a cut segment touch on their line)
      for (int s = 1; s < S; ++s) {
        const Segment &lo = lines.segments[static_cast<std::size_t>(s - 1)],
                      &hi = lines.segments[static_cast<std::size_t>(s)];
        if (lo.part != hi.part || lo.line != hi.line || boustro::dist(lo.b, hi.a) > 1e-6) continue;
        auto pull = [](Point& end, Point other) {
          const double d = boustro::dist(end, other);
          if (d > 4.0 * milp::kCutGapM)
            end = Point{end.x() + (other.x() - end.x()) * milp::kCutGapM / d,
                        end.y() + (other.y() - end.y()) * milp::kCutGapM / d};
        };
        pull(segs[static_cast<std::size_t>(s - 1)].b, segs[static_cast<std::size_t>(s - 1)].a);
        pull(segs[static_cast<std::size_t>(s)].a, segs[static_cast<std::size_t>(s)].b);
      }
    }
    const std::vector<std::vector<int>> adj = milp::adjacency(lines);
    {
      std::vector<std::vector<int>> members(static_cast<std::size_t>(C));
      for (int s = 0; s < S; ++s)
        members[static_cast<std::size_t>(group[static_cast<std::size_t>(s)])].push_back(s);
      for (int g = 0; g < C; ++g)
        clusters[static_cast<std::size_t>(g)].items =
            items_for(segs, adj, members[static_cast<std::size_t>(g)], par.max_segments, transit);
    }

    // one MILP per cluster
    std::vector<int> owner(static_cast<std::size_t>(S), -1);
    nlohmann::json diag_clusters = nlohmann::json::array();
    bool hit_time = false, not_optimal = false;
    double worst_gap = 0.0;
    std::vector<double> uav_distance(m, 0.0);
    for (int g = 0; g < C; ++g) {
      stop_check(ctx);
      const Cluster& cl = clusters[static_cast<std::size_t>(g)];
      milp::Limits lim;
      lim.max_nodes = par.node_limit;
      lim.max_seconds = par.time_limit_s;
      lim.model = formulation(par.model, static_cast<int>(cl.items.size()));
      lim.stage = C > 1 ? fmt::format("{} {}/{}", kStage, g + 1, C) : std::string(kStage);
      lim.f0 = 0.05 + 0.85 * g / C;
      lim.f1 = 0.05 + 0.85 * (g + 1) / C;
      ctx.report(lim.stage, lim.f0);
      std::vector<Point> pos;
      const Instance in = make_instance(cl, p.starts, p.shares, transit, par.nearby_penalty, pos, ctx);
      const Routes start = warm_start(in, cl);
      milp::Result r;
      if (cl.items.empty()) {
        r.routes = start;
        r.objective = milp::objective(in, start);
        r.optimal = true;
        r.status = "optimal";
        r.model = "none";
      } else {
        r = milp::solve(in, start, lim, ctx);
      }
      stop_check(ctx);
      if (r.status == "stopped" || r.status == "time_limit") hit_time = true;
      if (!r.optimal) not_optimal = true;
      worst_gap = std::max(worst_gap, r.gap);
      nlohmann::json seqs = nlohmann::json::array();
      const int mm = in.uavs;
      for (int k = 0; k < mm; ++k) {
        const int uav = cl.uavs[static_cast<std::size_t>(k)];
        auto& ua = out.uavs[static_cast<std::size_t>(uav)];
        const auto& q = r.routes.seq[static_cast<std::size_t>(k)];
        nlohmann::json seq = nlohmann::json::array();
        nlohmann::json flown = nlohmann::json::array();
        double d = 0.0;
        Point here = p.starts[static_cast<std::size_t>(uav)];
        for (std::size_t t = 0; t < q.size(); ++t) seq.push_back(q[t] + 1);
        seq.push_back(k + 1);
        for (std::size_t t = 1; t + 1 < q.size(); t += 2) {
          const int node = q[t];
          const int item = (node - mm) / 2;
          const bool backwards = (node - mm) % 2 == 1;
          const Item& it = cl.items[static_cast<std::size_t>(item)];
          std::vector<std::pair<int, bool>> legs = it.legs;
          if (backwards) {
            std::reverse(legs.begin(), legs.end());
            for (auto& l : legs) l.second = !l.second;
          }
          for (const auto& [s, rev] : legs) {
            const auto [a, b] = leg_ends(segs[static_cast<std::size_t>(s)], rev);
            d += transit(here, a) + boustro::dist(a, b);
            here = b;
            ua.coverage.push_back({a, b});
            owner[static_cast<std::size_t>(s)] = uav;
            flown.push_back({{"segment", s}, {"from", rev ? "high" : "low"}});
          }
        }
        d += transit(here, p.starts[static_cast<std::size_t>(uav)]);
        uav_distance[static_cast<std::size_t>(uav)] = d;
        ua.diagnostics = {{"cluster", g},
                          {"sequence", std::move(seq)},
                          {"legs", std::move(flown)},
                          {"distance_m", d},
                          {"weighted_distance_m", d / in.weight[static_cast<std::size_t>(k)]}};
        seqs.push_back(ua.diagnostics["sequence"]);
      }
      diag_clusters.push_back({{"uavs", cl.uavs},
                               {"pairs", in.pairs},
                               {"segments", std::accumulate(cl.items.begin(), cl.items.end(), 0,
                                                            [](int a, const Item& it) {
                                                              return a + static_cast<int>(it.legs.size());
                                                            })},
                               {"model", r.model},
                               {"nodes", in.nodes()},
                               {"variables", r.variables},
                               {"binaries", r.binaries},
                               {"rows", r.rows},
                               {"pruned_arcs", r.pruned_arcs},
                               {"objective", r.objective},
                               {"bound", r.bound},
                               {"gap", r.gap},
                               {"status", r.status},
                               {"optimal", r.optimal},
                               {"bb_nodes", r.bb_nodes},
                               {"solve_time_s", r.seconds},
                               {"first_incumbent_s", r.first_incumbent_s},
                               {"incumbent_is_warm_start", r.from_warm_start},
                               {"warm_start_objective", milp::objective(in, start)},
                               {"sequences", std::move(seqs)}});
    }
    ctx.report(kStage, 0.9);
    const auto t_milp = std::chrono::steady_clock::now();

    const std::vector<MultiPolygon> regs = milp::regions(lines, p.free, owner, M, ctx);
    for (std::size_t k = 0; k < m; ++k) out.uavs[k].region = regs[k];
    if (hit_time) {
      out.complete = false;
      out.warnings.push_back(fmt::format(
          "milp: the time limit ended the search; the best assignment found is returned (gap {:.1f} %)",
          100.0 * worst_gap));
    } else if (not_optimal) {
      out.warnings.push_back(fmt::format(
          "milp: not proven optimal within planner_params.node_limit (gap {:.1f} %)", 100.0 * worst_gap));
    }
    nlohmann::json parts = nlohmann::json::array();
    for (const auto& part : lines.parts)
      parts.push_back({{"angle_deg", to_bearing(part.angle)},
                       {"lines", part.xs.size()},
                       {"lines_with_segments", part.lines_with_segments}});
    double dmax = 0.0, dsum = 0.0;
    for (double d : uav_distance) dmax = std::max(dmax, d), dsum += d;
    out.diagnostics = {
        {"parts", std::move(parts)},
        {"segments", S},
        {"clusters", std::move(diag_clusters)},
        {"max_distance_m", dmax},
        {"mean_distance_m", dsum / static_cast<double>(m)},
        {"max_gap", worst_gap},
        {"proven_optimal", !not_optimal},
        {"milp_time_s", std::chrono::duration<double>(t_milp - t_lines).count()},
        {"regions_time_s", std::chrono::duration<double>(std::chrono::steady_clock::now() - t_milp).count()},
        {"solve_time_s", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()}};
    ctx.report(kStage, 1.0);
    return out;
  }
};

}  // namespace

PlannerInfo milp_planner_info() {
  using T = ParamSpec::Type;
  PlannerInfo info;
  info.name = "milp";
  info.summary =
      "Back-and-forth lines assigned to the UAVs by a min-max MILP solved with COIN-OR CBC (Hong et al. "
      "2021); "
      "clusters by share beyond max_segments";
  info.params = {
      param("angle_deg", T::Number, nullptr, -360.0, 360.0,
            "Direction of the lines in degrees clockwise from north (0: north-south lines); absent: per "
            "part of the area, as `direction` says"),
      param("direction", T::String, "longest_edge", std::nullopt, std::nullopt,
            "Without angle_deg: lines along the longest boundary edge of each part (the paper) or `auto`: "
            "the hull edge direction with the fewest lines",
            {"longest_edge", "auto"}),
      param("max_segments", T::Integer, 12, 2.0, 60.0,
            "The most line segments (waypoint pairs) in one MILP; beyond, the UAVs are clustered by share "
            "and neighbouring lines are merged into blocks"),
      param("max_uavs_per_milp", T::Integer, 1, 1.0, 10.0,
            "The most UAVs in one MILP; beyond, the UAVs are clustered by share. 1 (default): the lines are "
            "split by share and each UAV's MILP orders its own; 2 to 10: the paper's joint assignment, which "
            "balances distance (weights 1/share) rather than area"),
      param("node_limit", T::Integer, 100, 0.0, 10000000.0,
            "Branch-and-bound nodes per MILP (a deterministic budget); the best assignment found is kept"),
      param("time_limit_s", T::Number, 10.0, 0.01, 3600.0,
            "CBC's time per MILP (the mission's time limit applies too); reaching it returns the best "
            "assignment with its gap and marks the plan incomplete"),
      param("model", T::String, "auto", std::nullopt, std::nullopt,
            "MILP formulation: `exact` (the paper's, one node per waypoint with the back-and-forth "
            "constraint), `contracted` (one node per segment and orientation, same optimum, fewer rows) or "
            "`auto` (exact up to 4 waypoint pairs, contracted beyond)",
            {"exact", "contracted", "auto"}),
      param("nearby_penalty", T::Number, 10.0, 1.0, 100.0,
            "Factor on the cost of edges between waypoints numbered more than 2 apart (the paper's "
            "non-nearby penalty)"),
  };
  info.supports = Capabilities{true, true, true, true, true, true};
  // the pattern options on corridors only (an area mission asking for one is refused by plan())
  info.supports.corridor = info.supports.crosshatch = info.supports.turnaround = info.supports.entry =
      info.supports.alternate_transects = info.supports.capture_in_turnaround = true;
  info.supports.structure = true;  // facade orbits (src/planners/structure/)
  info.create = [] { return std::make_unique<MilpPlanner>(); };
  return info;
}

}  // namespace uavcover::planners
