#include "io/plan_dir.hpp"

#include <algorithm>

#include "evaluation/evaluate.hpp"
#include "export/export.hpp"
#include "io/plan_io.hpp"
#include "render/render.hpp"
#include "trajectory/trajectory.hpp"
#include "uavcover/error.hpp"

namespace uavcover::io {

void check_export_formats(const std::vector<std::string>& formats) {
  const auto& known = exporting::known_formats();
  for (const auto& f : formats)
    if (std::find(known.begin(), known.end(), f) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw InputError("--export", "unknown format \"" + f + "\" (known: " + list + ")");
    }
}

PlanDirResult write_plan_dir(const Plan& plan, const std::filesystem::path& dir,
                             const PlanDirOptions& options) {
  check_export_formats(options.exports);
  PlanDirResult out;
  nlohmann::json extra = nlohmann::json::object();
  evaluation::Evaluation ev;
  if (options.evaluate) {
    ev = evaluation::evaluate_plan(plan);
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
  write_file_atomic(dir / "paths.geojson", paths_geojson(plan).dump(1) + "\n");
  write_file_atomic(dir / "plan.json", plan_json(plan, extra).dump(1) + "\n");
  out.files = {dir / "paths.geojson", dir / "plan.json"};
  if (options.images) {
    render::write_plan_png(plan, dir / "plan.png");
    render::write_plan_svg(plan, dir / "plan.svg");
    out.files.push_back(dir / "plan.png");
    out.files.push_back(dir / "plan.svg");
    if (options.evaluate) {
      render::write_heatmap_png(ev.coverage, ev.free, dir / "heatmap.png");
      render::write_histogram_png(ev.coverage.total, dir / "histogram.png");
      out.files.push_back(dir / "heatmap.png");
      out.files.push_back(dir / "histogram.png");
    }
  }
  if (!options.exports.empty()) {
    auto written = write_artifacts(dir, exporting::export_artifacts(plan, options.exports));
    out.files.insert(out.files.end(), written.begin(), written.end());
  }
  return out;
}

}  // namespace uavcover::io
