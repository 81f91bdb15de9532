#include "usecases/plan_outputs.hpp"
#include "codec/plan_codec.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "engine/test_hold.hpp"
#include "export/export.hpp"
#include "export/formats.hpp"
#include "export/zip.hpp"
#include "geodesy/local_frame.hpp"
#include "io/plan_io.hpp"
#include "render/render.hpp"
#include "terrain/terrain.hpp"
#include "trajectory/trajectory.hpp"
#include "uavcover/error.hpp"

namespace uavcover::usecases {

namespace {

/// A time limit reached inside a stage after the planner: the stage is left out.
struct OutOfTime {};

std::string joined(const std::vector<std::string>& items) {
  std::string s;
  for (const auto& i : items) s += (s.empty() ? "" : ", ") + i;
  return s;
}

}  // namespace

void check_outputs(const Mission& mission, const OutputOptions& options) {
  if (options.exports.empty()) return;
  (void)exporting::parse_formats(options.exports);
  // every export format flies the transition altitudes: the export's own rule, before any planning
  // (altitude layers: at least one layer must fit; how many the plan needs is checked on export)
  (void)waypoints::resolve_altitudes(waypoints::AltitudeOptions{},
                                     mission.transition_altitudes == "layers" ? 1 : mission.uavs.size(),
                                     mission.altitude_m);
  for (const auto& u : mission.uavs)
    trajectory::check_options(options.trajectory, trajectory::Limits{u.speed_mps, u.max_accel_mps2});
}

PlanOutputs plan_outputs(const Plan& plan, const OutputOptions& options, const Context& ctx) {
  const std::vector<std::string> formats =
      options.exports.empty() ? std::vector<std::string>{} : exporting::parse_formats(options.exports);
  const std::string& name = plan.mission.name;
  // a stop ends everything (Cancelled); the time limit leaves out what has not finished
  std::vector<std::string> left_out;
  auto out_of_time = [&ctx] {
    if (ctx.stop_requested()) throw Cancelled();
    return ctx.time_up();
  };
  PlanOutputs out;
  nlohmann::json extra = nlohmann::json::object();
  evaluation::Evaluation ev;
  bool evaluated = false;
  if (options.evaluate) {
    ctx.report("evaluation", 0.0);
    engine::test_hold(ctx, "evaluation", name);
    try {
      if (out_of_time()) throw OutOfTime{};
      evaluation::EvaluateOptions eo;
      eo.coverage.context = &ctx;
      ev = evaluation::evaluate_plan(plan, eo);
      nlohmann::json blocks = evaluation::to_json(ev);
      // the alternative to eq. 15: flight durations of the time-parameterised trajectories (climbs to
      // the transition altitudes, corners under each UAV's v_max and a_max), through eq. 16-22
      // (the export's transition altitudes; a plan whose UAVs cannot be separated under the export's
      // ceiling is still evaluated, without the ceiling: the export will refuse it and say why)
      waypoints::AltitudeOptions altitudes;
      try {
        altitudes =
            waypoints::resolve_altitudes(altitudes, waypoints::altitude_slots(plan), plan.mission.altitude_m);
      } catch (const InputError&) {
        altitudes.transition_ceiling_m = 0;
      }
      std::vector<double> durations_min;
      for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
        if (out_of_time()) throw OutOfTime{};
        durations_min.push_back(trajectory::flight_time_s(plan, i, {}, altitudes) / 60.0);
      }
      const auto traj_cost = evaluation::evaluate_cost_from_durations(durations_min, plan.mission.uavs,
                                                                      ev.coverage.total.area_m2);
      blocks["cost_trajectory"] = evaluation::to_json(traj_cost);
      extra = std::move(blocks);
      evaluated = true;
      out.trajectory_flight_time_min = traj_cost.flight_time_min;
      out.poc = ev.coverage.total.poc;
      out.pooc = ev.coverage.total.pooc;
      if (ev.facade) {
        out.facade_poc = ev.facade->total.covered_share;
        out.facade_3plus = ev.facade->total.share_3plus;
      }
      out.flight_time_min = ev.cost.flight_time_min;
      out.total_time_min = ev.cost.total_time_min;
      out.cost_eur = ev.cost.flight_cost_eur;
    } catch (const OutOfTime&) {
      left_out.push_back("evaluation");
    } catch (const TimeLimitReached&) {
      left_out.push_back("evaluation");
    }
  }
  // with a DEM: what was read, and (with pictures) the profile of the leg terrain following changes most
  std::optional<waypoints::LegProfile> profile;
  bool profile_left_out = false;
  if (const HeightGrid* ground = terrain::grid(plan.mission)) {
    extra["terrain"] = {{"dem", ground->source},
                        {"mode", plan.mission.terrain->mode},
                        {"tolerance_m", plan.mission.terrain->tolerance_m},
                        {"grid_step_m", ground->step_m},
                        {"highest_ground_m", ground->max_m}};
    if (options.images)
      for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
        if (out_of_time()) {
          profile.reset();
          profile_left_out = true;
          break;
        }
        try {
          auto lp = waypoints::leg_profile(plan, i);
          if (lp && (!profile || lp->terrain_waypoints > profile->terrain_waypoints)) profile = std::move(lp);
        } catch (const InputError&) {
          // altitudes the export refuses: no profile (the export says why)
        }
      }
  }
  Artifacts pictures;
  if (options.images) {
    ctx.report("pictures", 0.0);
    engine::test_hold(ctx, "pictures", name);
    std::vector<std::string> missing;
    // a stop or the deadline is looked at before every picture (each is drawn at pixel resolution: at
    // 1M mega-cells x 50 UAVs all of them took 0.2 s of CPU, the evaluation 4.5 s)
    const std::size_t planned_pictures = 2 + (profile ? 1 : 0) + (evaluated ? 2 : 0);
    auto picture = [&](const char* file, auto&& make) {
      if (out_of_time())
        missing.push_back(file);
      else
        pictures.push_back(make());
      ctx.report("pictures", static_cast<double>(pictures.size() + missing.size()) /
                                 static_cast<double>(planned_pictures));
    };
    picture("plan.png", [&] { return render::plan_png(plan); });
    picture("plan.svg", [&] { return render::plan_svg(plan); });
    if (profile) picture("terrain-profile.png", [&] { return render::terrain_profile_png(*profile); });
    if (profile_left_out) missing.push_back("terrain-profile.png");
    if (evaluated) {
      picture("heatmap.png", [&] { return render::heatmap_png(ev.coverage, &ev.free); });
      picture("histogram.png", [&] { return render::histogram_png(ev.coverage.total); });
      const auto& cov = ev.coverage;
      if (options.heatmap_overlay && cov.lattice_cols > 0 && cov.lattice_rows > 0 &&
          cov.lattice_cols <= 20000 && cov.lattice_rows <= 20000) {
        if (out_of_time()) {
          missing.push_back("heatmap-overlay.png");
        } else {
          pictures.push_back(render::heatmap_overlay_png(cov));
          const auto b = evaluation::lattice_bounds(cov, geodesy::LocalFrame(plan.origin));
          out.heatmap_bounds = {{b.south, b.west}, {b.north, b.east}};
        }
      }
    } else if (options.evaluate) {
      // the evaluation was left out: the pictures drawn from it are not made either, and say so
      missing.insert(missing.end(), {"heatmap.png", "histogram.png"});
      if (options.heatmap_overlay) missing.push_back("heatmap-overlay.png");
    }
    if (!missing.empty()) left_out.push_back("pictures " + joined(missing));
  }
  Artifacts exported;
  if (!formats.empty()) {
    ctx.report("exports", 0.0);
    engine::test_hold(ctx, "exports", name);
    exporting::ExportOptions eo;
    std::vector<std::string> warnings;
    eo.warnings = &warnings;
    eo.kmz = options.kmz;
    eo.per_sortie = options.per_sortie;
    eo.trajectory_step_s = options.trajectory_step_s;
    eo.trajectory = options.trajectory;
    std::vector<std::string> missing;
    // the checks (separation, no-fly zones, upload rules) once for every format; not begun when the
    // time is already up (every format is then left out below) or a stop was requested
    std::optional<exporting::CheckedExport> checked;
    std::string refused;
    if (!out_of_time()) {
      try {
        checked.emplace(plan, eo);
      } catch (const InputError& e) {
        if (!options.refused_exports_are_warnings) throw;
        refused = e.what();
      }
    }
    // one format at a time, so that a stop or the time limit lands between formats
    for (std::size_t k = 0; k < formats.size(); ++k) {
      const std::string& format = formats[k];
      if (out_of_time()) {
        missing.push_back(format);
        continue;
      }
      if (!checked) {
        warnings.push_back(format + " export refused: " + refused);
        continue;
      }
      try {
        std::vector<std::string> format_warnings = checked->warnings();
        auto files = checked->write({format}, &format_warnings);
        warnings.insert(warnings.end(), format_warnings.begin(), format_warnings.end());
        exported.insert(exported.end(), std::make_move_iterator(files.begin()),
                        std::make_move_iterator(files.end()));
      } catch (const InputError& e) {
        if (!options.refused_exports_are_warnings) throw;
        warnings.push_back(format + " export refused: " + e.what());
      }
      ctx.report("exports", static_cast<double>(k + 1) / static_cast<double>(formats.size()));
    }
    // each format's export repeats the plan-wide warnings (altitudes, separation): once each
    for (auto& w : warnings)
      if (std::find(out.warnings.begin(), out.warnings.end(), w) == out.warnings.end())
        out.warnings.push_back(std::move(w));
    if (!missing.empty()) left_out.push_back("exports " + joined(missing));
  }
  if (ctx.stop_requested()) throw Cancelled();
  nlohmann::json pj = codec::plan_json(plan, extra);
  if (!left_out.empty()) {
    const std::string w = "time limit reached after planning: left out " + joined(left_out) +
                          " (plan.json and paths.geojson are complete; raise the time limit for the rest)";
    out.warnings.push_back(w);
    pj["warnings"].push_back(w);
  }
  out.artifacts.push_back(
      {"paths.geojson", "application/geo+json", codec::paths_geojson(plan).dump(1) + "\n"});
  out.artifacts.push_back({"plan.json", "application/json", pj.dump(1) + "\n"});
  out.evaluation = std::move(extra);
  out.artifacts.insert(out.artifacts.end(), std::make_move_iterator(pictures.begin()),
                       std::make_move_iterator(pictures.end()));
  out.artifacts.insert(out.artifacts.end(), std::make_move_iterator(exported.begin()),
                       std::make_move_iterator(exported.end()));
  out.left_out = std::move(left_out);
  return out;
}

const std::vector<ExportRoute>& export_routes() {
  static const std::vector<ExportRoute> routes = [] {
    std::vector<ExportRoute> r;
    for (const exporting::Format& f : exporting::formats()) {
      ExportRoute route{std::string(f.name), std::string(f.name), std::string(f.title), {}};
      // a split export (ExportVariant::split_capacity) serves the zip of the UAV's missions
      if (f.per_sortie) route.files.push_back("export/{}" + std::string(f.extension) + ".zip");
      if (f.name == "trajectory") {
        route.files = {"trajectory/{}" + std::string(f.extension)};  // its writer names its own file
      } else if (f.name == "litchi") {
        // a mission split in parts is served as the zip of them all (build_export)
        route.files.insert(route.files.end(),
                           {"export/{}.litchi.zip", "export/{}" + std::string(f.extension)});
      } else {
        route.files.push_back("export/{}" + std::string(f.extension));
      }
      r.push_back(std::move(route));
      // a plan job builds "kml" with ExportOptions::kmz: each .kml comes with its .kmz
      if (f.name == "kml")
        r.push_back({"kmz", std::string(f.name), "KMZ (zipped KML)", {"export/{}.kmz.zip", "export/{}.kmz"}});
    }
    return r;
  }();
  return routes;
}

const ExportRoute* find_export_route(std::string_view name) {
  for (const ExportRoute& r : export_routes())
    if (r.name == name) return &r;
  return nullptr;
}

std::string export_route_list() {
  std::vector<std::string> names;
  for (const ExportRoute& r : export_routes()) names.push_back(r.name);
  return joined(names);
}

nlohmann::json export_routes_json() {
  nlohmann::json out = nlohmann::json::array();
  for (const ExportRoute& r : export_routes())
    out.push_back({{"name", r.name}, {"format", r.format}, {"title", r.title}});
  return out;
}

std::string export_source_format(const std::string& format) {
  const ExportRoute* route = find_export_route(format);
  return route == nullptr ? format : route->format;
}

std::string ExportVariant::key() const {
  std::string k;
  if (!autopilot.empty()) k += "@autopilot=" + autopilot;
  if (terrain_frame) k += "@terrain_frame";
  if (split_capacity) k += "@split_capacity";
  const trajectory::Options& t = trajectory;
  if (t.method != trajectory::Options{}.method) {
    k += fmt::format("@method={}@order={}", trajectory::method_name(t.method), t.order);
    if (t.v_mean > 0) k += fmt::format("@v_mean={}", t.v_mean);
    if (!std::isnan(t.v_min)) k += fmt::format("@v_min={}", t.v_min);
    if (!std::isnan(t.a_min)) k += fmt::format("@a_min={}", t.a_min);
  }
  return k;
}

ExportVariant ExportVariant::for_format(std::string_view format) const {
  ExportVariant v = *this;
  if (const exporting::Format* f = exporting::find_format(format)) {
    if (!f->trajectory_options) v.trajectory = {};
    if (!f->per_sortie) v.split_capacity = false;
  }
  return v;
}

std::string split_zip_name(const std::string& id, std::string_view extension) {
  return "export/" + id + std::string(extension) + ".zip";
}

namespace {

/// A split export's files export/<id>.s<k><ext> replaced by one zip per UAV and extension (the
/// entries named <id>.s<k><ext>; k = 1, 2, ... is the flight order).
void zip_split_parts(Artifacts& files, const Plan& plan) {
  std::map<std::string, std::map<std::string, std::string>> zips;  // zip name -> its entries
  Artifacts kept;
  // the longest id first: "a.s1"'s export/a.s1.s2.plan is not UAV "a"'s
  std::vector<const UavPlan*> uavs;
  for (const auto& u : plan.uavs) uavs.push_back(&u);
  std::sort(uavs.begin(), uavs.end(),
            [](const UavPlan* a, const UavPlan* b) { return a->id.size() > b->id.size(); });
  for (auto& f : files) {
    bool taken = false;
    for (const UavPlan* up : uavs) {
      const UavPlan& u = *up;
      const std::string prefix = "export/" + u.id + ".s";
      if (!f.name.starts_with(prefix)) continue;
      const std::size_t digits = f.name.find_first_not_of("0123456789", prefix.size());
      if (digits == prefix.size() || digits == std::string::npos || f.name[digits] != '.') continue;
      zips[split_zip_name(u.id, f.name.substr(digits))][f.name.substr(7)] = std::move(f.bytes);
      taken = true;
      break;
    }
    if (!taken) kept.push_back(std::move(f));
  }
  for (const auto& [name, entries] : zips)
    kept.push_back({name, "application/zip", exporting::zip_bytes(entries)});
  files = std::move(kept);
}

}  // namespace

BuiltExport build_export(const std::string& plan_json_text, const std::string& paths_geojson_text,
                         const std::string& format, double trajectory_step_s, const Context& ctx,
                         const std::function<void(Mission&)>& load_terrain, const ExportVariant& variant) {
  nlohmann::json pj, pg;
  Plan plan;
  try {
    pj = nlohmann::json::parse(plan_json_text);
    pg = nlohmann::json::parse(paths_geojson_text);
    plan = codec::load_plan(pj, pg);
    // a terrain plan's heights are above mean sea level: the ground comes with it (issue 31)
    if (plan.mission.terrain && load_terrain) load_terrain(plan.mission);
  } catch (const nlohmann::json::exception& e) {
    throw OperationError(std::string("the stored plan cannot be read: ") + e.what());
  } catch (const InputError& e) {
    throw OperationError(std::string("the stored plan cannot be read: ") + e.what());
  }
  if (ctx.stop_requested()) throw Cancelled();
  BuiltExport out;
  // a plan job's export options (plan_job_outputs() in jobs.cpp): every .kml with its .kmz
  exporting::ExportOptions eo;
  std::vector<std::string> warnings;
  eo.warnings = &warnings;
  eo.kmz = true;
  eo.trajectory_step_s = trajectory_step_s;  // the job's trajectory_step_s (0: the segment form)
  eo.autopilot = variant.autopilot;
  eo.altitude.terrain_frame = variant.terrain_frame;
  eo.split_capacity = variant.split_capacity;
  eo.trajectory = variant.trajectory;
  try {
    out.files = exporting::export_artifacts(plan, {format}, eo);
  } catch (const InputError& e) {
    out.refused_field = e.field();
    out.refused = e.what();
    return out;
  }
  for (auto& w : warnings)
    if (std::find(out.warnings.begin(), out.warnings.end(), w) == out.warnings.end())
      out.warnings.push_back(std::move(w));
  if (variant.split_capacity) zip_split_parts(out.files, plan);
  if (format == "geojson") {
    // the per-UAV document is the UAV's part of the stored paths.geojson: the same features with the
    // lengths measured on the planner's own coordinates (a plan read back from WGS84 measures its
    // parts again in a projected frame, a few 1e-10 m apart)
    for (auto& f : out.files) {
      const std::string id = f.name.substr(7, f.name.size() - 7 - 8);  // export/<id>.geojson
      nlohmann::json doc = pg;
      nlohmann::json kept = nlohmann::json::array();
      for (auto& feature : doc["features"]) {
        const auto& props = feature["properties"];
        if (!props.contains("uav") || props["uav"] == id) kept.push_back(std::move(feature));
      }
      doc["features"] = std::move(kept);
      f.bytes = doc.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
    }
  }
  if (format == "litchi") {
    // Litchi missions of more than 99 waypoints come in parts: one zip per UAV holds them all
    std::map<std::string, std::map<std::string, std::string>> parts;
    for (const auto& a : out.files)
      if (a.name.starts_with("export/") && a.name.ends_with(".litchi.csv")) {
        const std::string stem = a.name.substr(7, a.name.size() - 7 - 11);  // "<id>" or "<id>.<k>"
        const auto dot = stem.rfind('.');
        if (dot != std::string::npos && stem.find_first_not_of("0123456789", dot + 1) == std::string::npos)
          parts[stem.substr(0, dot)][a.name.substr(7)] = a.bytes;
      }
    for (const auto& [id, files] : parts)
      out.files.push_back({"export/" + id + ".litchi.zip", "application/zip", exporting::zip_bytes(files)});
  }
  if (ctx.stop_requested()) throw Cancelled();
  return out;
}

}  // namespace uavcover::usecases
