#include "usecases/plan_outputs.hpp"

#include <algorithm>

#include "export/export.hpp"
#include "geodesy/local_frame.hpp"
#include "io/plan_io.hpp"
#include "render/render.hpp"
#include "terrain/terrain.hpp"
#include "trajectory/trajectory.hpp"
#include "uavcover/error.hpp"

namespace uavcover::usecases {

PlanOutputs plan_outputs(const Plan& plan, const OutputOptions& options, const Context& ctx) {
  if (!options.exports.empty()) (void)exporting::parse_formats(options.exports);  // refuse unknown ones first
  PlanOutputs out;
  nlohmann::json extra = nlohmann::json::object();
  evaluation::Evaluation ev;
  if (options.evaluate) {
    evaluation::EvaluateOptions eo;
    eo.coverage.context = &ctx;
    ev = evaluation::evaluate_plan(plan, eo);
    extra = evaluation::to_json(ev);
    // the alternative to eq. 15: flight durations of the time-parameterised trajectories (climbs to
    // the transition altitudes, corners under each UAV's v_max and a_max), through eq. 16-22
    // (the export's transition altitudes; a plan whose UAVs cannot be separated under the export's
    // ceiling is still evaluated, without the ceiling: the export will refuse it and say why)
    exporting::AltitudeOptions altitudes;
    try {
      altitudes = exporting::resolve_altitudes(altitudes, plan.uavs.size(), plan.mission.altitude_m);
    } catch (const InputError&) {
      altitudes.transition_ceiling_m = 0;
    }
    std::vector<double> durations_min;
    for (std::size_t i = 0; i < plan.uavs.size(); ++i)
      durations_min.push_back(trajectory::flight_time_s(plan, i, {}, altitudes) / 60.0);
    const auto traj_cost =
        evaluation::evaluate_cost_from_durations(durations_min, plan.mission.uavs, ev.coverage.total.area_m2);
    extra["cost_trajectory"] = evaluation::to_json(traj_cost);
    out.trajectory_flight_time_min = traj_cost.flight_time_min;
    out.poc = ev.coverage.total.poc;
    out.pooc = ev.coverage.total.pooc;
    out.flight_time_min = ev.cost.flight_time_min;
    out.total_time_min = ev.cost.total_time_min;
    out.cost_eur = ev.cost.flight_cost_eur;
  }
  // with a DEM: what was read, and (with pictures) the profile of the leg terrain following changes most
  std::optional<exporting::LegProfile> profile;
  if (const HeightGrid* ground = terrain::grid(plan.mission)) {
    extra["terrain"] = {{"dem", ground->source},
                        {"mode", plan.mission.terrain->mode},
                        {"tolerance_m", plan.mission.terrain->tolerance_m},
                        {"grid_step_m", ground->step_m},
                        {"highest_ground_m", ground->max_m}};
    if (options.images)
      for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
        try {
          auto lp = exporting::leg_profile(plan, i);
          if (lp && (!profile || lp->terrain_waypoints > profile->terrain_waypoints)) profile = std::move(lp);
        } catch (const InputError&) {
          // altitudes the export refuses: no profile (the export says why)
        }
      }
  }
  out.artifacts.push_back({"paths.geojson", "application/geo+json", io::paths_geojson(plan).dump(1) + "\n"});
  out.artifacts.push_back({"plan.json", "application/json", io::plan_json(plan, extra).dump(1) + "\n"});
  out.evaluation = std::move(extra);
  if (options.images) {
    ctx.report("pictures", 0.0);
    out.artifacts.push_back(render::plan_png(plan));
    out.artifacts.push_back(render::plan_svg(plan));
    if (profile) out.artifacts.push_back(render::terrain_profile_png(*profile));
    if (options.evaluate) {
      out.artifacts.push_back(render::heatmap_png(ev.coverage, &ev.free));
      out.artifacts.push_back(render::histogram_png(ev.coverage.total));
      const auto& cov = ev.coverage;
      if (options.heatmap_overlay && cov.lattice_cols > 0 && cov.lattice_rows > 0 &&
          cov.lattice_cols <= 20000 && cov.lattice_rows <= 20000) {
        out.artifacts.push_back(render::heatmap_overlay_png(cov));
        const auto b = evaluation::lattice_bounds(cov, geodesy::LocalFrame(plan.origin));
        out.heatmap_bounds = {{b.south, b.west}, {b.north, b.east}};
      }
    }
  }
  if (!options.exports.empty()) {
    ctx.report("exports", 0.0);
    exporting::ExportOptions eo;
    eo.warnings = &out.warnings;
    eo.kmz = options.kmz;
    eo.per_sortie = options.per_sortie;
    auto add = [&](const std::vector<std::string>& formats) {
      auto exported = exporting::export_artifacts(plan, formats, eo);
      out.artifacts.insert(out.artifacts.end(), std::make_move_iterator(exported.begin()),
                           std::make_move_iterator(exported.end()));
    };
    if (!options.refused_exports_are_warnings) {
      add(options.exports);
    } else {
      for (const auto& format : exporting::parse_formats(options.exports)) {
        try {
          add({format});
        } catch (const InputError& e) {
          out.warnings.push_back(format + " export refused: " + e.what());
        }
      }
    }
  }
  return out;
}

}  // namespace uavcover::usecases
