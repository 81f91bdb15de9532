#include "planners/darp/darp.hpp"

#include <algorithm>

#include "geometry/millimetres.hpp"
#include "planners/darp/darp_planner.hpp"

namespace uavcover::planners {

namespace {

/// The free part of a region's cells. Clipped on doubles by thin zones at a slant (1 m hedges at 45
/// degrees), Boost left slivers and holes crossing themselves that plan.json's reader refused; on integer
/// millimetres (geometry::intersection_mm) its predicates are exact. A piece the rounding of the
/// intersection points might still leave invalid is dropped when under 1 m^2, so that plan.json's
/// reader accepts the region (and the export, whose fences are the region, follows it).
MultiPolygon clip_region(const MultiPolygon& cells, const MultiPolygon& free) {
  MultiPolygon out = geometry::intersection_mm(cells, free);
  std::erase_if(out, [](const Polygon& piece) { return bg::area(piece) < 1.0 && !bg::is_valid(piece); });
  return out;
}

class DarpPlanner final : public Planner {
 public:
  [[nodiscard]] Assignment plan(const Problem& problem, const nlohmann::json& params,
                                const Context& ctx) const override {
    darp::Input in;
    in.free = problem.free;
    in.no_fly = problem.no_fly;
    in.starts = problem.starts;
    in.shares = problem.shares;
    for (const auto& u : problem.uavs) in.ids.push_back(u.id);
    in.ds = problem.spacing_m;
    in.mode = problem.mode;
    for (const auto& f : problem.uav_footprints) in.own_footprint_m.push_back(f.own_camera ? f.width_m : 0.0);
    in.seed = problem.seed;
    darp::Options opt;
    opt.max_iterations = params.at("max_iterations").get<int>();
    opt.placement_evaluations = params.at("placement_evaluations").get<int>();
    opt.optimise_placement = params.at("optimise_placement").get<bool>();
    opt.extend_legs = params.at("extend_legs").get<bool>();
    opt.shift_legs = params.at("shift_legs").get<bool>();
    opt.min_turn_orientation = params.at("min_turn_orientation").get<bool>();
    opt.paper_objective = params.at("objective").get<std::string>() == "paper";
    opt.j_weight_a = params.at("j_weight_a").get<double>();
    opt.j_weight_b = params.at("j_weight_b").get<double>();
    opt.j_weight_c = params.at("j_weight_c").get<double>();
    const darp::Output res = darp::run(in, opt, ctx);

    Assignment out;
    out.warnings = res.warnings;
    out.complete = !res.stopped_early;
    if (res.stopped_early)
      out.warnings.push_back(
          "the time limit cut the grid placement or the DARP division short: this is the best plan found "
          "so far");
    const auto& p = res.placement;
    const auto& g = res.grid;
    out.diagnostics = {{"placement",
                        {{"shift_x_m", p.shift_x_m},
                         {"shift_y_m", p.shift_y_m},
                         {"rotation_deg", p.rotation_deg},
                         {"J", p.J},
                         {"J1", p.J1},
                         {"J2", p.J2},
                         {"J3", p.J3},
                         {"evaluations", p.evaluations}}},
                       {"grid",
                        {{"cell_m", g.cell_m},
                         {"rotation_deg", g.rotation_deg},
                         {"origin", {g.origin.x(), g.origin.y()}},
                         {"rows", g.rows},
                         {"cols", g.cols}}},
                       {"converged", res.converged},
                       {"iterations", res.iterations}};
    for (const auto& r : res.uavs) {
      UavAssignment a;
      // mega-cells at the area's edge reach past it: the region is what of them is free area
      if (!r.cells_outline.empty()) a.region = clip_region(r.cells_outline, problem.free);
      a.coverage = r.loops;
      a.share_actual = r.share_actual;
      a.diagnostics = {{"cells", r.cells}};
      out.uavs.push_back(std::move(a));
    }
    return out;
  }
};

}  // namespace

PlannerInfo darp_planner_info() {
  PlannerInfo info;
  info.name = "darp";
  info.summary =
      "DARP division on an optimised grid with STC coverage loops (Apostolidis et al. 2022): few turns, "
      "exact shares";
  using T = ParamSpec::Type;
  info.params = {
      {"max_iterations", T::Integer, 4000, 1.0, 1e6, {}, "DARP iterations per attempt"},
      {"placement_evaluations",
       T::Integer,
       1500,
       1.0,
       1e6,
       {},
       "grid placement budget: pre-scan plus simulated annealing steps"},
      {"optimise_placement",
       T::Boolean,
       true,
       {},
       {},
       {},
       "search the grid's shift and rotation (false: the grid at shift 0, rotation 0)"},
      {"extend_legs",
       T::Boolean,
       true,
       {},
       {},
       {},
       "lengthen the loops' U-turns at the area's edge toward the boundary (strict: up to it; coverage: up "
       "to "
       "half a footprint past it; never into a no-fly zone)"},
      {"shift_legs",
       T::Boolean,
       true,
       {},
       {},
       {},
       "move the legs along the area's edge outward, up to 0.45 spacing, until their swath reaches the "
       "boundary (strict: staying inside; never into a no-fly zone)"},
      {"min_turn_orientation",
       T::Boolean,
       true,
       {},
       {},
       {},
       "try the spanning tree's 8 orientations per region and keep the loop with the fewest turns (the "
       "paper's turn reduction, Fig. 8-9); false: one orientation"},
      {"objective",
       T::String,
       "uavcover",
       {},
       {},
       {"uavcover", "paper"},
       "what the grid placement maximises: \"uavcover\", the paper's J plus a swept-footprint coverage "
       "estimate minus a path-length term; \"paper\", the paper's J = a J1 + b J2 - c J3 alone (eq. 7)"},
      {"j_weight_a",
       T::Number,
       grid::Weights{}.a,
       0.0,
       1.0,
       {},
       "weight a of J1 (nodes in the area, eq. 8) in the paper's J = a J1 + b J2 - c J3"},
      {"j_weight_b",
       T::Number,
       grid::Weights{}.b,
       0.0,
       1.0,
       {},
       "weight b of J2 (area over the grid-snapped bounding box, eq. 9) in J"},
      {"j_weight_c",
       T::Number,
       grid::Weights{}.c,
       0.0,
       1.0,
       {},
       "weight c of the penalty J3 (unequal margins, eq. 10) in J"},
  };
  info.supports = {.shares = true,
                   .no_fly_zones = true,
                   .strict_mode = true,
                   .coverage_mode = true,
                   .multiple_areas = true,
                   .best_so_far = true};
  info.create = [] { return std::make_unique<DarpPlanner>(); };
  return info;
}

}  // namespace uavcover::planners
