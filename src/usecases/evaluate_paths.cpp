#include "usecases/evaluate_paths.hpp"

#include <map>

#include "geodesy/local_frame.hpp"
#include "render/render.hpp"

namespace uavcover::usecases {

std::vector<Uav> match_uavs(const Mission& mission, const std::vector<std::string>& ids) {
  std::map<std::string, const Uav*> by_id;
  for (const auto& u : mission.uavs) by_id[u.id] = &u;
  std::vector<Uav> uavs;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const auto it = by_id.find(ids[i]);
    Uav u = it != by_id.end()         ? *it->second
            : i < mission.uavs.size() ? mission.uavs[i]
            : mission.uavs.empty()    ? Uav{}
                                      : mission.uavs.front();
    u.id = ids[i];
    uavs.push_back(u);
  }
  return uavs;
}

PathsEvaluation evaluate_paths(const Mission& mission, std::string_view geojson,
                               const evaluation::EvaluateOptions& options, const Context& ctx) {
  const geodesy::LocalFrame frame(geodesy::centroid(mission.area));
  const auto paths = evaluation::parse_paths_geojson(geojson, frame);
  PathsEvaluation out;
  out.uavs = match_uavs(mission, paths.uav_ids);
  // the evaluated paths drawn like a plan (no regions: other tools do not give them); its mission names
  // the matched UAVs, so that each flight is swept with its UAV's own camera
  Plan& shown = out.shown;
  shown.mission = mission;
  shown.origin = frame.origin();
  shown.mission.uavs = out.uavs;

  evaluation::EvaluateOptions opt = options;
  opt.coverage.context = &ctx;
  if (!opt.cost.wind) opt.cost.wind = mission.wind;       // other tools' paths timed in the mission's wind
  evaluation::set_oblique_camera(mission, opt.coverage);  // lines with a tilted gimbal sweep its trapezoid
  const double w =
      opt.coverage.footprint_m > 0.0 ? opt.coverage.footprint_m : evaluation::footprint_for(mission);
  evaluation::set_uav_footprints(shown.mission, out.uavs.size(), w, opt.coverage);
  const MultiPolygon free = evaluation::free_area(mission, frame);
  out.evaluation = evaluation::evaluate_flights(free, paths.flights, out.uavs, w, opt);
  shown.free_area_m2 = out.evaluation.coverage.total.area_m2;
  for (std::size_t i = 0; i < paths.flights.size(); ++i) {
    UavPlan up;
    up.id = paths.uav_ids[i];
    up.share_actual = out.evaluation.coverage.uavs[i].area_share;
    up.parts = paths.flights[i];
    if (!up.parts.empty() && !up.parts.front().wgs84.empty()) {
      shown.mission.uavs[i].start_resolved = up.parts.front().wgs84.front();
      shown.mission.uavs[i].start.reset();
    }
    shown.uavs.push_back(std::move(up));
  }
  // a structure scan (docs/patterns.md): the wall's coverage by the paths' photos (each line's attitude
  // as its properties give it; without one, the mission's altitude and the camera along the track)
  out.evaluation.facade = evaluation::evaluate_facade(shown);
  return out;
}

Artifacts evaluation_outputs(const PathsEvaluation& result, const std::string& paths_name, bool images) {
  const auto& ev = result.evaluation;
  const auto& mission = result.shown.mission;
  nlohmann::json j = evaluation::evaluation_json(ev);
  j["mission"] = mission.name;
  j["paths"] = paths_name;
  Artifacts out{{"evaluation.json", "application/json", j.dump(1) + "\n"}};
  if (images) {
    out.push_back(
        render::heatmap_png(ev.coverage, &ev.free, "heatmap.png", 1200, 900,
                            "Coverage heatmap" + (mission.name.empty() ? "" : " - " + mission.name)));
    out.push_back(render::histogram_png(ev.coverage.total));
    out.push_back(render::plan_png(result.shown, "paths.png"));
  }
  return out;
}

}  // namespace uavcover::usecases
