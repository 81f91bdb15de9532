#include "planners/smt/smt.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <map>
#include <mutex>
#include <numeric>
#include <thread>

#include "geometry/geometry.hpp"
#include "planners/darp/regions.hpp"
#include "planners/smt/cover.hpp"
#include "planners/smt/lattice.hpp"
#include "planners/smt/schedule.hpp"
#include "uavcover/error.hpp"

namespace uavcover::planners {

namespace {

struct Options {
  int subgraph_size = 20;
  smt::CoverOptions cover;
  bool tree_stitch = true;
  std::optional<double> max_flight_time_s;
  double endurance_reserve = 0.2;
  bool diagonal_edges = false;
  std::optional<double> wall_clock_s;
  int max_nodes = 20000;
  int threads = 0;
  double turn_penalty_m = 0.0;
  bool strips = false;
};

Options read(const nlohmann::json& p) {
  Options o;
  o.subgraph_size = p.at("subgraph_size").get<int>();
  o.cover.bound_offset = p.at("sat_bound_offset").get<int>();
  o.cover.timeout_s = p.at("timeout_s").get<double>();
  o.cover.rlimit = static_cast<unsigned>(p.at("resource_limit").get<long long>());
  o.cover.resource_budget = static_cast<unsigned long long>(p.at("resource_budget").get<long long>());
  o.tree_stitch = p.at("stitch").get<std::string>() == "tree";
  if (!p.at("max_flight_time_s").is_null()) o.max_flight_time_s = p.at("max_flight_time_s").get<double>();
  o.endurance_reserve = p.at("endurance_reserve").get<double>();
  o.diagonal_edges = p.at("diagonal_edges").get<bool>();
  if (!p.at("wall_clock_s").is_null()) o.wall_clock_s = p.at("wall_clock_s").get<double>();
  o.max_nodes = p.at("max_nodes").get<int>();
  o.threads = p.at("threads").get<int>();
  o.turn_penalty_m = p.at("turn_penalty_m").get<double>();
  o.strips = p.at("subgraph_shape").get<std::string>() == "strip";
  return o;
}

class SmtPlanner final : public Planner {
 public:
  [[nodiscard]] Assignment plan(const Problem& problem, const nlohmann::json& params,
                                const Context& ctx) const override {
    Options opt = read(params);
    // a stop request ends planning; the deadline only cuts the z3 search short (best so far)
    const auto check = [&] {
      if (ctx.stop_requested()) ctx.check();
    };
    ctx.report("smt lattice", 0.0);
    check();
    const smt::Lattice lat = smt::build_lattice(problem, opt.diagonal_edges, opt.max_nodes, check);
    check();
    // edge weights are in ds / 1000 (lattice.hpp): the penalty in the same unit
    opt.cover.turn_penalty =
        static_cast<int>(std::lround(std::min(opt.turn_penalty_m / lat.ds * 1000.0, 1e8)));
    const std::size_t k = problem.starts.size();
    const std::vector<int> owner = smt::divide(lat, problem.starts, problem.shares);
    std::vector<std::vector<int>> nodes_of(k);
    for (int v = 0; v < lat.size(); ++v)
      nodes_of[static_cast<std::size_t>(owner[static_cast<std::size_t>(v)])].push_back(v);

    // subproblems of every UAV, solved on worker threads; the stop token and the deadline interrupt z3
    std::vector<std::vector<int>> subs;
    std::vector<std::size_t> sub_uav;
    for (std::size_t u = 0; u < k; ++u)
      for (auto& s : smt::split(lat, nodes_of[u], opt.subgraph_size, opt.strips)) {
        subs.push_back(std::move(s));
        sub_uav.push_back(u);
      }
    std::vector<smt::CoverResult> covers(subs.size());
    smt::Interrupter interrupter;
    std::atomic<std::size_t> next{0}, finished{0};
    std::mutex failure_mutex;
    std::exception_ptr failure;
    const unsigned hw = std::max(1U, std::thread::hardware_concurrency());
    const std::size_t nthreads = std::min<std::size_t>(
        subs.size(), opt.threads > 0 ? static_cast<std::size_t>(opt.threads) : std::min(4U, hw));
    if (ctx.time_up()) interrupter.interrupt_all();  // no time left: every subgraph keeps its tree walk
    {
      std::vector<std::jthread> workers;
      for (std::size_t t = 0; t < nthreads; ++t)
        workers.emplace_back([&] {
          for (std::size_t i = next++; i < subs.size(); i = next++) {
            smt::CoverOptions co = opt.cover;
            co.seed = static_cast<unsigned>((problem.seed * 1000003ULL + i) & 0x7fffffffU);
            try {
              covers[i] = smt::solve_cover(smt::subgraph(lat, subs[i]), co, &interrupter);
            } catch (...) {  // out of memory, say: reported on the planning thread
              std::lock_guard lock(failure_mutex);
              if (!failure) failure = std::current_exception();
              interrupter.interrupt_all();
            }
            ++finished;
          }
        });
      bool late = false;
      while (finished.load() < subs.size()) {
        if (ctx.stop_requested() || (!late && ctx.time_up())) {
          late = true;
          interrupter.interrupt_all();
        }
        ctx.report("smt cycles", static_cast<double>(finished.load()) / static_cast<double>(subs.size()));
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
    }  // workers joined
    if (failure) std::rethrow_exception(failure);
    check();
    const bool cut_short = interrupter.interrupted();

    Assignment out;
    out.complete = !cut_short;
    if (cut_short)
      out.warnings.push_back(
          "the time limit cut the z3 search short: subgraphs without a model are covered by the walk around "
          "a spanning tree");
    const geometry::Router router(problem.no_fly);
    // the legs between a home and an entry node are asked for again and again while stitching
    std::map<std::pair<std::pair<double, double>, std::pair<double, double>>, std::vector<Point>> legs;
    const smt::LegFn leg = [&](Point a, Point b) {
      const auto key = std::make_pair(std::make_pair(a.x(), a.y()), std::make_pair(b.x(), b.y()));
      auto it = legs.find(key);
      if (it == legs.end()) it = legs.emplace(key, router.route(a, b)).first;
      return it->second;
    };
    std::vector<int> owner_cells(lat.node_of_cell.size(), -1);
    for (int v = 0; v < lat.size(); ++v) {
      const auto [c, r] = lat.cell[static_cast<std::size_t>(v)];
      owner_cells[static_cast<std::size_t>(r) * static_cast<std::size_t>(lat.cols) +
                  static_cast<std::size_t>(c)] = owner[static_cast<std::size_t>(v)];
    }
    nlohmann::json routes_json = nlohmann::json::array();
    std::vector<double> route_times;
    int over_limit_total = 0;
    for (std::size_t u = 0; u < k; ++u) {
      ctx.report("smt routes", static_cast<double>(u) / static_cast<double>(k));
      const Uav& uav = problem.uavs[u];
      const double limit = opt.max_flight_time_s ? *opt.max_flight_time_s
                                                 : uav.endurance_min * 60.0 * (1.0 - opt.endurance_reserve);
      std::vector<smt::Walk> walks;
      for (std::size_t i = 0; i < subs.size(); ++i) {
        if (sub_uav[i] != u) continue;
        smt::Walk w;
        for (int local : covers[i].walk) w.push_back(subs[i][static_cast<std::size_t>(local)]);
        walks.push_back(std::move(w));
      }
      int over = 0;
      std::vector<smt::Route> routes;
      if (opt.tree_stitch) {
        routes = smt::stitch(lat, walks, problem.starts[u], uav, limit, leg, &over, check);
        // greedy stitching fills the first routes to the limit and leaves a short last one: try caps
        // that share the time evenly over fewer routes, keep the fewest routes (then the least time)
        auto total = [](const std::vector<smt::Route>& rs) {
          double t = 0.0;
          for (const auto& r : rs) t += r.time_s;
          return t;
        };
        const double base = total(routes);
        const auto fewest = static_cast<std::size_t>(std::max(1.0, std::ceil(base / limit)));
        for (std::size_t m = fewest; m < routes.size() && m < fewest + 3 && !ctx.time_up(); ++m)
          for (const double slack : {0.0, 0.03, 0.06, 0.1, 0.15, 0.2}) {
            const double cap = std::min(limit, base / static_cast<double>(m) * (1.0 + slack));
            int over_cap = 0;
            auto tried = smt::stitch(lat, walks, problem.starts[u], uav, cap, leg, &over_cap, check);
            if (over_cap > 0) continue;
            if (tried.size() < routes.size() ||
                (tried.size() == routes.size() && total(tried) < total(routes)))
              routes = std::move(tried);
          }
      } else {
        for (auto& w : walks) {
          smt::Route r;
          r.entry = w.front();
          r.walk = smt::flight_order(lat, w, r.entry, problem.starts[u]);
          const auto c = smt::route_cost(lat, w, r.entry, problem.starts[u], uav, leg);
          r.time_s = c.time_s, r.length_m = c.length_m, r.turns = c.turns, r.walks = 1;
          if (r.time_s <= limit) {
            routes.push_back(std::move(r));
            continue;
          }
          ++over;  // too long alone: flown in pieces, each within the limit
          for (auto& piece : smt::split_route(lat, r, problem.starts[u], uav, limit, leg))
            routes.push_back(std::move(piece));
        }
      }
      over_limit_total += over;
      UavAssignment a;
      nlohmann::json sorties = nlohmann::json::array();
      for (const auto& r : routes) {
        // each route is one sortie from home and back (the engine adds the legs)
        a.sortie_starts.push_back(a.coverage.size());
        a.coverage.push_back(smt::walk_polyline(lat, r.walk, false));  // entry to exit
        // a lone node (cut off by no-fly zones) is a coverage leg of zero length: a line needs 2 positions
        if (a.coverage.back().size() == 1) a.coverage.back().push_back(a.coverage.back().front());
        sorties.push_back({{"time_s", r.time_s},
                           {"length_m", r.length_m},
                           {"turns", r.turns},
                           {"nodes", r.walk.size()},
                           {"walks", r.walks}});
        routes_json.push_back(
            {{"uav", uav.id}, {"time_s", r.time_s}, {"length_m", r.length_m}, {"turns", r.turns}});
        route_times.push_back(r.time_s);
      }
      // the region: the cells of the UAV's nodes, clipped to the free area, pieces holding a node kept
      MultiPolygon cells = darp::cells_to_polygons(
          lat.rows, lat.cols, owner_cells, static_cast<int>(u),
          [&](int c, int r) { return Point(lat.origin.x() + c * lat.ds, lat.origin.y() + r * lat.ds); });
      MultiPolygon clipped;
      bg::intersection(cells, problem.free, clipped);
      for (auto& piece : clipped) {
        const bool holds = std::any_of(nodes_of[u].begin(), nodes_of[u].end(), [&](int v) {
          return bg::covered_by(lat.pos[static_cast<std::size_t>(v)], piece);
        });
        if (holds) a.region.push_back(std::move(piece));
      }
      if (a.region.empty() && !clipped.empty()) a.region.push_back(clipped.front());
      if (a.region.size() > 1)
        out.warnings.push_back(fmt::format(
            "UAV {}'s region has {} parts (the lattice is not connected there)", uav.id, a.region.size()));
      a.share_actual = static_cast<double>(nodes_of[u].size()) / static_cast<double>(lat.size());
      double total = 0.0;
      for (const auto& r : routes) total += r.time_s;
      a.diagnostics = {{"max_flight_time_s", limit},
                       {"nodes", nodes_of[u].size()},
                       {"routes", routes.size()},
                       {"flight_time_s", total},
                       {"sorties", std::move(sorties)}};
      out.uavs.push_back(std::move(a));
    }
    if (over_limit_total > 0)
      out.warnings.push_back(
          fmt::format("{} subgraph walk(s) exceed the flight-time limit on their own (with the legs from and "
                      "back to home), so each is flown as several routes within it; lower "
                      "planner_params.subgraph_size or raise planner_params.max_flight_time_s for fewer",
                      over_limit_total));

    long long first_total = 0, best_total = 0;
    int optimal = 0, fallback = 0, checks = 0, cuts = 0, turns = 0, timed_out = 0, budget_out = 0;
    unsigned long long resources = 0;
    for (const auto& c : covers) {
      timed_out += c.timed_out && !c.optimal ? 1 : 0;
      budget_out += c.budget_out && !c.optimal ? 1 : 0;
      resources += c.resources;
      first_total += c.first_length >= 0 ? c.first_length : c.length;
      best_total += c.length;
      optimal += c.optimal ? 1 : 0;
      fallback += c.fallback ? 1 : 0;
      checks += c.checks;
      cuts += c.cuts;
      turns += c.turns;
    }
    if (timed_out > 0)
      out.warnings.push_back(fmt::format(
          "{} subgraph search(es) ended at planner_params.timeout_s before their resource budget: the plan "
          "depends on the machine's load; raise timeout_s or lower resource_budget",
          timed_out));
    const double unit = lat.ds / 1000.0;
    int edges = 0;
    for (const auto& a : lat.adj) edges += static_cast<int>(a.size());
    out.diagnostics = {{"lattice",
                        {{"nodes", lat.size()},
                         {"edges", edges / 2},
                         {"cols", lat.cols},
                         {"rows", lat.rows},
                         {"spacing_m", lat.ds}}},
                       {"subgraphs",
                        {{"count", subs.size()},
                         {"optimal", optimal},
                         {"fallback", fallback},
                         {"checks", checks},
                         {"cuts", cuts},
                         {"resources", resources},
                         {"budget_out", budget_out},
                         {"timed_out", timed_out},
                         {"first_model_length_m", static_cast<double>(first_total) * unit},
                         {"length_m", static_cast<double>(best_total) * unit},
                         {"turn_pairs", turns},
                         {"turn_penalty_m", opt.turn_penalty_m},
                         {"threads", nthreads}}},
                       {"route_count", route_times.size()},
                       {"split_walks", over_limit_total},
                       {"routes", std::move(routes_json)}};
    if (opt.wall_clock_s) {
      const int m = smt::min_uavs(route_times, *opt.wall_clock_s);
      out.diagnostics["wall_clock_s"] = *opt.wall_clock_s;
      out.diagnostics["min_uavs_for_wall_clock"] = m > 0 ? nlohmann::json(m) : nlohmann::json(nullptr);
    }
    ctx.report("smt routes", 1.0);
    return out;
  }
};

}  // namespace

PlannerInfo smt_planner_info() {
  PlannerInfo info;
  info.name = "smt";
  info.summary =
      "POPCORN-style SMT routes (Shah et al. 2020): z3 closed walks over a lattice of capture points, "
      "stitched "
      "into sorties under the flight-time limit";
  using T = ParamSpec::Type;
  info.params = {
      {"subgraph_size",
       T::Integer,
       20,
       2.0,
       64.0,
       {},
       "lattice nodes per z3 subproblem (wadl's default: 20)"},
      {"sat_bound_offset",
       T::Integer,
       1,
       1.0,
       1000.0,
       {},
       "each tightening asks z3 for a walk shorter by this many lattice steps"},
      {"timeout_s",
       T::Number,
       60.0,
       0.01,
       3600.0,
       {},
       "wall-clock safety net of one subproblem (all its z3 checks); a search it ends depends on the "
       "machine's load (diagnostics subgraphs.timed_out, a warning)"},
      {"resource_limit",
       T::Integer,
       2000000,
       0.0,
       4e9,
       {},
       "z3 resource limit (rlimit) per check; deterministic, unlike timeout_s; 0: none"},
      {"resource_budget",
       T::Integer,
       20000000,
       0.0,
       1e12,
       {},
       "z3 resource units (rlimit) for all checks of one subproblem together; deterministic, unlike "
       "timeout_s; 0: none"},
      {"stitch",
       T::String,
       "tree",
       {},
       {},
       {"tree", "none"},
       "tree: splice neighbouring walks into routes from home under the flight-time limit; none: one route "
       "per subgraph"},
      {"max_flight_time_s",
       T::Number,
       nullptr,
       10.0,
       86400.0,
       {},
       "flight-time limit of one route (sortie) in seconds; null: each UAV's endurance minus the reserve"},
      {"endurance_reserve", T::Number, 0.2, 0.0, 0.9, {}, "share of the endurance kept in reserve"},
      {"diagonal_edges", T::Boolean, false, {}, {}, {}, "8-connected lattice (diagonal steps) instead of 4"},
      {"wall_clock_s",
       T::Number,
       nullptr,
       1.0,
       1e7,
       {},
       "report the fewest UAVs that fly all routes within this many seconds (diagnostics)"},
      {"max_nodes", T::Integer, 20000, 1.0, 200000.0, {}, "largest lattice accepted"},
      {"threads", T::Integer, 0, 0.0, 64.0, {}, "worker threads for the subproblems (0: up to 4)"},
      {"subgraph_shape",
       T::String,
       "square",
       {},
       {},
       {"square", "strip"},
       "square: square-ish lattice tiles (wadl); strip: tiles two lattice lines wide along the longer extent "
       "(fewer turns)"},
      {"turn_penalty_m",
       T::Number,
       0.0,
       0.0,
       1000.0,
       {},
       "metres added to a walk's length in the z3 objective per turn (pair of used edges meeting at an "
       "angle at a node); 0: length only, as POPCORN"},
  };
  info.supports = {.shares = true,
                   .no_fly_zones = true,
                   .strict_mode = true,
                   .coverage_mode = true,
                   .multiple_areas = true,
                   .best_so_far = true};
  info.create = [] { return std::make_unique<SmtPlanner>(); };
  return info;
}

}  // namespace uavcover::planners
