#include "planners/spiral/spiral.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>

#include "planners/spiral/footprint.hpp"
#include "planners/spiral/mesh.hpp"
#include "planners/spiral/partition.hpp"
#include "planners/spiral/path.hpp"
#include "uavcover/error.hpp"

namespace uavcover::planners {

namespace {

using namespace spiral;

/// Rings of the free area closer than this are one ring for the mesh.
constexpr double kRingSnapM = 1e-3;

/// The free area with rings that touch (up to rounding) merged: a hole and a no-fly zone sharing an
/// edge come out of the overlay as two rings 1e-10 m apart, and refining the mesh between two such
/// constraints never ends (issue 26: 600 x 400 m at 30 m hit the 2 000 000-triangle bound after 20 s).
/// An opening (shrink, then grow back, by kRingSnapM with mitred corners) merges them; an area whose
/// rings all keep kRingSnapM apart is returned as it is.
MultiPolygon merge_touching_rings(const MultiPolygon& free) {
  using Line = bg::model::linestring<Point>;
  std::vector<Line> rings;
  for (const auto& poly : free) {
    rings.emplace_back(poly.outer().begin(), poly.outer().end());
    for (const auto& in : poly.inners()) rings.emplace_back(in.begin(), in.end());
  }
  bool close = false;
  for (std::size_t i = 0; i < rings.size() && !close; ++i)
    for (std::size_t j = i + 1; j < rings.size() && !close; ++j)
      close = bg::distance(rings[i], rings[j]) < kRingSnapM;
  if (!close) return free;
  bg::strategy::buffer::side_straight side;
  bg::strategy::buffer::join_miter join;
  bg::strategy::buffer::end_flat end;
  bg::strategy::buffer::point_square point;
  MultiPolygon shrunk, out;
  bg::buffer(free, shrunk, bg::strategy::buffer::distance_symmetric<double>(-kRingSnapM), side, join, end,
             point);
  bg::buffer(shrunk, out, bg::strategy::buffer::distance_symmetric<double>(kRingSnapM), side, join, end,
             point);
  // an opening stays inside the free area (up to rounding: intersecting with it again would bring the
  // two rings back)
  return out.empty() ? free : out;
}
using nlohmann::json;

constexpr const char* kStage = "spiral";
/// The most triangles it meshes (about 0.5 GB of CGAL triangulation at the bound).
constexpr std::size_t kMaxTriangles = 2'000'000;

json to_json(const AngleStats& s) {
  return {{"histogram_10deg", s.bins},
          {"min_deg", s.min_deg},
          {"mean_min_deg", s.mean_min_deg},
          {"fraction_50_70_deg", s.within_10_of_60}};
}

json to_json(const PathStats& s) {
  return {{"length_m", s.length_m},
          {"waypoints", s.waypoints},
          {"min_step_m", s.min_step_m},
          {"max_step_m", s.max_step_m},
          {"min_angle_deg", s.min_angle_deg},
          {"max_angle_deg", s.max_angle_deg},
          {"mean_angle_deg", s.mean_angle_deg},
          {"angle_histogram_30deg", s.angle_bins}};
}

/// The footprint that sizes the triangles: the camera's of width `width_m` (with the gimbal pitch), else
/// a square of ds.
Footprint footprint_of(const Problem& p, double width_m, const json& params,
                       std::vector<std::string>& warnings) {
  const double pitch = params.value("gimbal_pitch_deg", 0.0);
  const bool has_vfov = params.contains("vfov_deg") && params["vfov_deg"].is_number();
  if (!p.camera || !(width_m > 0.0) || !(p.altitude_m > 0.0)) {
    if (pitch != 0.0 || has_vfov)
      warnings.push_back(
          "planner_params: gimbal_pitch_deg and vfov_deg need a camera; triangles are sized by spacing_m");
    // the rule: ds is the footprint side; "footprint": the mission's footprint width (1.5 ds),
    // which the evaluator sweeps; triangles with edges <= sqrt(3)/2 w lie within w/2 of their centroid
    const bool by_footprint =
        params.value("size_by", std::string("spacing")) == "footprint" && p.footprint_m > 0.0;
    return square_footprint(by_footprint ? p.footprint_m : p.spacing_m);
  }
  const double hfov = 2.0 * std::atan(width_m / (2.0 * p.altitude_m)) * 180.0 / std::numbers::pi;
  const double vfov = has_vfov ? params["vfov_deg"].get<double>() : hfov;
  return camera_footprint(p.altitude_m, hfov, vfov, pitch);
}

class SpiralPlanner final : public Planner {
 public:
  [[nodiscard]] Assignment plan(const Problem& p, const json& params, const Context& ctx) const override {
    ctx.check();
    const std::size_t n = p.starts.size();
    if (n == 0) throw InputError("uavs", "at least one UAV is needed");
    if (p.shares.size() != n) throw InputError("uavs", "one share per UAV is needed");
    if (!(p.spacing_m > 0.0) || !std::isfinite(p.spacing_m))
      throw InputError("spacing_m", "the line spacing must be a positive number of metres");
    Assignment out;
    out.uavs.resize(n);
    const double free_area = bg::area(p.free);
    if (p.free.empty() || !(free_area > 0.0)) return out;
    ctx.report(kStage, 0.0);

    // 1. FoV-sized triangles (§IV eq. 1-8)
    const Footprint fp = footprint_of(p, p.footprint_m, params, out.warnings);
    if (!(fp.side_m > 0.0) || !std::isfinite(fp.side_m))
      throw InputError("camera", "gives no positive footprint for the spiral mesh");
    // heterogeneous cameras (uavs[i].camera): each UAV's W_d from its own footprint at the mission's
    // altitude; the shared mesh uses the team's largest (the paper), smaller ones re-mesh their sub-area
    if (!p.uav_footprints.empty() && p.uav_footprints.size() != n)
      throw InputError("uavs", "one footprint per UAV is needed");
    std::vector<double> side(n, fp.side_m);
    std::size_t smallest_at = 0;
    for (std::size_t k = 0; k < p.uav_footprints.size(); ++k) {
      if (p.uav_footprints[k].own_camera) {
        std::vector<std::string> ignored;  // the same warnings as the mission's footprint
        side[k] = footprint_of(p, p.uav_footprints[k].width_m, params, ignored).side_m;
        if (!(side[k] > 0.0) || !std::isfinite(side[k]))
          throw InputError("uavs[" + std::to_string(k) + "].camera",
                           "gives no positive footprint for the spiral mesh");
      }
      if (side[k] < side[smallest_at]) smallest_at = k;
    }
    const double team_side = *std::max_element(side.begin(), side.end());
    const double smallest = side[smallest_at];
    // an equilateral triangle of side W_d covers sqrt(3)/4 W_d^2; refined meshes hold about 1.5x more;
    // bounded at the smallest W_d, as if one UAV re-meshed the whole area
    const double estimate = 1.5 * free_area / (std::sqrt(3.0) / 4.0 * smallest * smallest);
    if (estimate > static_cast<double>(kMaxTriangles))
      throw InputError(smallest < fp.side_m ? "uavs[" + std::to_string(smallest_at) + "].camera"
                                            : std::string("spacing_m"),
                       "the spiral mesh would need about " +
                           std::to_string(static_cast<long long>(estimate)) + " triangles (at most " +
                           std::to_string(kMaxTriangles) + "); use a larger spacing or a smaller area");

    // 2. mesh
    MeshOptions mo;
    mo.max_edge_m = team_side;
    mo.lloyd_iterations = params.value("lloyd_iterations", 10);
    mo.lloyd =
        params.value("lloyd_method", std::string("local")) == "cgal" ? LloydMethod::Cgal : LloydMethod::Local;
    mo.max_triangles = kMaxTriangles;
    MeshReport mr;
    const Mesh mesh = build_mesh(merge_touching_rings(p.free), mo, ctx, mr);
    ctx.report(kStage, 0.4);
    if (mesh.triangles.empty()) throw InputError("area", "the free area is too thin to mesh");
    const std::vector<Point> centroid = centroids(mesh);
    const std::vector<double> area = areas(mesh);

    // 3. partition by share
    const auto t0 = std::chrono::steady_clock::now();
    const Partition part =
        partition(mesh, centroid, area, p.starts, p.shares, params.value("share_tolerance", 0.01), ctx);
    const double partition_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ctx.report(kStage, 0.6);
    if (part.max_deviation > params.value("share_tolerance", 0.01) + 1e-12)
      out.warnings.push_back("spiral: a share is off by " + std::to_string(part.max_deviation * 100.0) +
                             " % of itself (the mesh or the area's shape allows no closer division)");

    // 4. border-to-centre levels, 5. spiral waypoint lists
    const std::vector<int> level = levels(mesh, part.owner);
    const double s_s = params.value("valley_sensitivity", 2.0);
    const double reversal_deg = params.value("smooth_reversal_deg", 0.0);
    for (std::size_t k = 0; k < n; ++k) {
      auto& ua = out.uavs[k];
      ua.share_actual = part.share[k];
      if (part.seed[k] < 0) continue;
      const int uav = static_cast<int>(k);
      ua.region = region_of(mesh, part.owner, uav);
      // a UAV with a smaller footprint re-meshes its own sub-area at its own W_d
      const bool own_mesh = side[k] < team_side * (1.0 - 1e-9);
      Mesh sub;
      MeshReport sub_report;
      if (own_mesh) {
        MeshOptions own = mo;
        own.max_edge_m = side[k];
        sub = build_mesh(ua.region, own, ctx, sub_report);
        if (sub.triangles.empty()) continue;
      }
      const Mesh& m = own_mesh ? sub : mesh;
      const std::vector<Point> sub_centroid = own_mesh ? centroids(sub) : std::vector<Point>{};
      const std::vector<Point>& c = own_mesh ? sub_centroid : centroid;
      const std::vector<int> sub_owner =
          own_mesh ? std::vector<int>(sub.triangles.size(), uav) : std::vector<int>{};
      const std::vector<int>& owner = own_mesh ? sub_owner : part.owner;
      const std::vector<int> sub_level = own_mesh ? levels(sub, sub_owner) : std::vector<int>{};
      const std::vector<int>& lv = own_mesh ? sub_level : level;
      SpiralOrder so = spiral_order(m, c, owner, lv, uav, p.starts[k], s_s, ctx);
      json smoothing;
      if (reversal_deg > 0.0) {
        // the turns of the centroid sequence before and after the smoothing pass
        auto turns = [&](const std::vector<int>& order) {
          std::vector<Point> pts;
          pts.reserve(order.size());
          for (const int t : order) pts.push_back(c[static_cast<std::size_t>(t)]);
          int below = 0;
          for (std::size_t i = 1; i + 1 < pts.size(); ++i)
            if (turn_angle_deg(pts[i - 1], pts[i], pts[i + 1]) < reversal_deg) ++below;
          const PathStats st = path_stats({pts});
          return json{{"reversals", below},
                      {"length_m", st.length_m},
                      {"mean_angle_deg", st.mean_angle_deg},
                      {"angle_histogram_30deg", st.angle_bins}};
        };
        smoothing["reversal_deg"] = reversal_deg;
        smoothing["before"] = turns(so.order);
        smoothing["runs_reversed"] = smooth_order(c, lv, so.order, reversal_deg, ctx);
        smoothing["after"] = turns(so.order);
      }
      ua.coverage = route(m, c, owner, uav, so.order, ctx);
      int max_level = 0, triangles = 0;
      for (std::size_t t = 0; t < lv.size(); ++t)
        if (owner[t] == uav) max_level = std::max(max_level, lv[t]), ++triangles;
      ua.diagnostics = {{"triangles", triangles},
                        {"triangle_side_m", side[k]},
                        {"own_mesh", own_mesh},
                        {"levels", max_level + 1},
                        {"valley_step_bound_m", so.step_bound_m},
                        {"valley_deferrals", so.deferred},
                        {"path", to_json(path_stats(ua.coverage))}};
      if (!smoothing.is_null()) ua.diagnostics["smoothing"] = smoothing;
      if (own_mesh)
        ua.diagnostics["mesh"] = {{"max_edge_m", sub_report.max_edge_m},
                                  {"refine_s", sub_report.refine_s},
                                  {"lloyd_s", sub_report.lloyd_s},
                                  {"angles_after_lloyd", to_json(sub_report.after_lloyd)}};
      ctx.report(kStage, 0.6 + 0.4 * static_cast<double>(k + 1) / static_cast<double>(n));
    }
    out.diagnostics = {{"footprint",
                        {{"near_width_m", fp.near_width_m},
                         {"far_width_m", fp.far_width_m},
                         {"length_m", fp.length_m},
                         {"inradius_m", fp.inradius_m},
                         {"triangle_side_m", fp.side_m}}},
                       {"mesh",
                        {{"triangles", mesh.triangles.size()},
                         {"triangles_before_lloyd", mr.triangles_before_lloyd},
                         {"vertices", mesh.vertices.size()},
                         {"max_edge_m", mr.max_edge_m},
                         {"refine_s", mr.refine_s},
                         {"lloyd_iterations", mo.lloyd_iterations},
                         {"lloyd_method", mo.lloyd == LloydMethod::Cgal ? "cgal" : "local"},
                         {"lloyd_s", mr.lloyd_s},
                         {"lloyd_cpu_s", mr.lloyd_cpu_s},
                         {"angles_before_lloyd", to_json(mr.before_lloyd)},
                         {"angles_after_lloyd", to_json(mr.after_lloyd)}}},
                       {"partition",
                        {{"max_share_deviation", part.max_deviation},
                         {"moves", part.moves},
                         {"extra_seeds", part.extra_seeds},
                         {"time_s", partition_s}}}};
    ctx.report(kStage, 1.0);
    return out;
  }
};

ParamSpec number(std::string name, json def, std::optional<double> lo, std::optional<double> hi,
                 std::string what, ParamSpec::Type type = ParamSpec::Type::Number) {
  return param(std::move(name), type, std::move(def), lo, hi, std::move(what));
}

ParamSpec choice(std::string name, std::string def, std::vector<std::string> choices, std::string what) {
  return param(std::move(name), ParamSpec::Type::String, std::move(def), std::nullopt, std::nullopt,
               std::move(what), std::move(choices));
}

}  // namespace

PlannerInfo spiral_planner_info() {
  PlannerInfo info;
  info.name = "spiral";
  info.summary =
      "Border-to-centre spirals over a FoV-sized constrained Delaunay mesh (CGAL, Lloyd), sub-areas grown by "
      "share "
      "(Balampanis et al. 2017)";
  info.params.push_back(number("lloyd_iterations", 10, 0.0, 1000.0,
                               "Lloyd optimisation steps after refinement", ParamSpec::Type::Integer));
  info.params.push_back(choice("lloyd_method", "local", {"local", "cgal"},
                               "local: each step moves every free vertex to its restricted Voronoi centroid "
                               "on the triangulation (flips; linear); cgal: CGAL's lloyd_optimize_mesh_2 "
                               "(super-linear)"));
  info.params.push_back(
      number("valley_sensitivity", 2.0, 1.0, 1000.0,
             "S_s: a step longer than S_s times the largest neighbour distance is deferred"));
  info.params.push_back(
      number("share_tolerance", 0.01, 0.001, 0.5,
             "stop balancing the sub-areas when every share is this close to its request (0.01: 1 % "
             "of it)"));
  info.params.push_back(
      number("vfov_deg", nullptr, 1.0, 170.0,
             "vertical (along-track) field of view; absent: the same as the horizontal one"));
  info.params.push_back(number("smooth_reversal_deg", 0.0, 0.0, 179.0,
                               "smoothing pass: turns sharper than this (180 = straight on) are reversals, "
                               "removed by reversing runs of 2-4 triangles of one level; 0: off"));
  info.params.push_back(
      choice("size_by", "spacing", {"spacing", "footprint"},
             "without a camera: spacing (the footprint side is ds, the issue's rule) or "
             "footprint (the mission's footprint width, 1.5 ds, which the evaluator sweeps: "
             "larger triangles, a shorter path)"));
  info.params.push_back(number("gimbal_pitch_deg", 0.0, 0.0, 80.0,
                               "camera pitch forward from nadir (the footprint becomes a trapezoid)"));
  info.supports = Capabilities{true, true, true, true, true, false};
  info.create = [] { return std::make_unique<SpiralPlanner>(); };
  return info;
}

}  // namespace uavcover::planners
