#include "usecases/jobs.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <tuple>

#include "export/export.hpp"
#include "export/separation.hpp"
#include "planners/planner.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/compare.hpp"
#include "usecases/plan_outputs.hpp"
#include "usecases/study.hpp"

namespace uavcover::usecases {

using nlohmann::json;

namespace {

/// The largest time limit a job may ask for (a day).
constexpr double kMaxTimeLimitS = 86'400.0;

void reject_unknown(const json& params, std::initializer_list<const char*> known) {
  for (auto it = params.begin(); it != params.end(); ++it)
    if (std::none_of(known.begin(), known.end(), [&](const char* k) { return it.key() == k; })) {
      std::string list;
      for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
      throw InputError(it.key(), "unknown parameter (known: " + list + ")");
    }
}

void check_seed(const json& params) {
  if (!params.contains("seed")) return;
  const json& s = params["seed"];
  if (!s.is_number_integer() ||
      (s.is_number_integer() && !s.is_number_unsigned() && s.get<std::int64_t>() < 0))
    throw InputError("seed", "must be an integer >= 0, got " + s.dump());
}

void check_time_limit(const json& params) {
  if (!params.contains("time_limit_s")) return;
  const json& t = params["time_limit_s"];
  if (!t.is_number() || !std::isfinite(t.get<double>()) || t.get<double>() <= 0 ||
      t.get<double>() > kMaxTimeLimitS)
    throw InputError("time_limit_s", fmt::format("must be a number in (0, {}] seconds, got {}",
                                                 kMaxTimeLimitS, t.dump().substr(0, 40)));
}

std::optional<std::uint64_t> seed_of(const json& params) {
  if (!params.contains("seed")) return std::nullopt;
  return params["seed"].get<std::uint64_t>();
}

Context limited(const Context& ctx, const json& params) {
  if (!params.contains("time_limit_s")) return ctx;
  return ctx.with_time_limit(std::chrono::duration_cast<Context::Clock::duration>(
      std::chrono::duration<double>(params["time_limit_s"].get<double>())));
}

/// The job's progress from the stages' own fractions (each stage counts 0..1 on its own): every stage
/// gets its slice of [0, 1] when it is known (`slices`), else half of what is left before `end` (the
/// planners' stages: placement, division, paths, transit, ...); the fraction sent never goes backwards,
/// so a progress bar only moves forward.
Context job_progress(const Context& ctx, std::vector<std::tuple<std::string, double, double>> slices,
                     double end) {
  struct Ratchet {
    std::mutex mutex;
    double sent = 0.0;
    std::string stage;
    double from = 0.0;
  };
  auto r = std::make_shared<Ratchet>();
  return ctx.with_progress([ctx, r, slices = std::move(slices), end](std::string_view stage, double f) {
    double value = 0.0;
    {
      const std::lock_guard lock(r->mutex);
      if (stage != r->stage) {
        r->stage = std::string(stage);
        r->from = r->sent;
      }
      double lo = r->from, hi = r->from + (end - r->from) / 2;
      for (const auto& [name, a, b] : slices)
        if (name == stage) lo = a, hi = b;
      value = std::max(r->sent, lo + (hi - lo) * f);
      r->sent = value;
    }
    ctx.report(stage, value);
  });
}

/// The mission with the job's planner and parameters applied.
Mission with_planner(const Mission& mission, const json& params) {
  Mission m = mission;
  if (params.contains("planner")) {
    const std::string name = params["planner"].get<std::string>();
    if (name != m.planner) m.planner_params = json::object();
    m.planner = name;
  }
  if (params.contains("planner_params")) m.planner_params = params["planner_params"];
  return m;
}

/// The outputs of a plan job: the CLI's `plan --export <every format>`, refusals as warnings.
OutputOptions plan_job_outputs(const json& params) {
  OutputOptions oo;
  if (params.contains("trajectory_step_s")) oo.trajectory_step_s = params["trajectory_step_s"].get<double>();
  oo.exports = exporting::known_formats();
  oo.kmz = true;
  oo.refused_exports_are_warnings = true;
  oo.heatmap_overlay = true;
  return oo;
}

JobResult plan_job(const Mission& mission, const json& params, const Context& ctx) {
  const Mission m = with_planner(mission, params);
  PlanOptions po;
  po.seed = seed_of(params);
  // one deadline for the whole job: the planner, then evaluation, pictures and exports (what does not
  // fit is left out and named in the warnings); a cancel lands in every stage
  const Context job = limited(ctx, params);
  // planning: the planner's stages share [0, 0.75]; then evaluation, pictures and exports
  const Plan p = plan(m, po, job_progress(job, {}, 0.75));
  // a plan job stores what a plan is (plan.json, paths.geojson, the evaluation and the pictures); its
  // exports are made from them on first request (build_export(), docs/cache.md)
  OutputOptions stored = plan_job_outputs(params);
  stored.exports.clear();
  PlanOutputs out =
      plan_outputs(p, stored, job_progress(job, {{"evaluation", 0.75, 0.95}, {"pictures", 0.95, 1.0}}, 1.0));

  // evaluation.json: the coverage and cost blocks of plan.json
  out.artifacts.push_back({"evaluation.json", "application/json", out.evaluation.dump(1) + "\n"});

  json uavs = json::array();
  double length = 0;
  long turns = 0;
  for (const auto& u : p.uavs) {
    uavs.push_back({{"id", u.id},
                    {"share_requested", u.share_requested},
                    {"share_actual", u.share_actual},
                    {"regions", u.regions},
                    {"coverage_length_m", u.coverage_length_m},
                    {"length_m", u.length_m},
                    {"turns", u.turns},
                    {"transition_altitude_m", u.transition_altitude_m}});
    length += u.length_m;
    turns += u.turns;
  }
  std::vector<std::string> warnings = p.warnings;
  warnings.insert(warnings.end(), out.warnings.begin(), out.warnings.end());
  // the hazards every export warns about (a UAV taking off inside another's region, ...) belong to the
  // plan: the job reports them at once, not only with an export made later (X-Export-Warnings)
  for (auto& w : exporting::separation_warnings(p)) warnings.push_back(std::move(w));
  json metrics = {{"length_m", length}, {"turns", turns}, {"compute_time_s", p.compute_time_s}};
  if (out.poc >= 0) {
    metrics["poc"] = out.poc;
    metrics["pooc"] = out.pooc;
    metrics["flight_time_min"] = out.flight_time_min;
    metrics["trajectory_flight_time_min"] = out.trajectory_flight_time_min;
    metrics["total_time_min"] = out.total_time_min;
    metrics["cost_eur"] = out.cost_eur;
  }
  if (out.facade_poc >= 0) {  // a structure scan: the wall's coverage (the plans list shows it, not PoC)
    metrics["facade_poc"] = out.facade_poc;
    metrics["facade_3plus"] = out.facade_3plus;
  }
  JobResult r;
  r.result = {{"planner", p.planner},    {"seed", p.mission.seed},        {"complete", p.complete},
              {"uavs", std::move(uavs)}, {"metrics", std::move(metrics)}, {"warnings", std::move(warnings)}};
  if (!out.heatmap_bounds.is_null()) r.result["heatmap_bounds"] = std::move(out.heatmap_bounds);
  r.artifacts = std::move(out.artifacts);
  return r;
}

JobResult study_job(const Mission& mission, const json& params, const Context& ctx) {
  StudyOptions so;
  so.counts = parse_uav_counts(params["uavs"].get<std::string>(), "uavs");
  so.seed = seed_of(params);
  const Study study = run_study(mission, so, limited(ctx, params));
  JobResult r;
  r.result = study_json(study);
  r.artifacts = {{"study.json", "application/json", r.result.dump(1) + "\n"}, study_picture(study)};
  return r;
}

JobResult comparison_job(const Mission& mission, const json& params, const Context& ctx) {
  Mission m = mission;
  if (const auto seed = seed_of(params)) m.seed = *seed;
  CompareOptions co;
  if (params.contains("planners")) co.planners = params["planners"].get<std::vector<std::string>>();
  const Comparison c = compare(m, co, limited(ctx, params));
  JobResult r;
  r.result = compare_json(c);
  r.artifacts = compare_outputs(c, true);
  return r;
}

}  // namespace

json validate_job_params(JobType type, const Mission& mission, const json& params_in) {
  json params = params_in.is_null() ? json::object() : params_in;
  if (!params.is_object()) throw InputError("body", "expected a JSON object of job parameters");
  check_seed(params);
  check_time_limit(params);
  switch (type) {
    case JobType::Plan: {
      reject_unknown(params, {"planner", "planner_params", "seed", "time_limit_s", "trajectory_step_s"});
      if (params.contains("trajectory_step_s")) {
        const json& s = params["trajectory_step_s"];
        if (!s.is_number() || !std::isfinite(s.get<double>()) || s.get<double>() < 0.001 ||
            s.get<double>() > 60)
          throw InputError("trajectory_step_s",
                           "must be a number in [0.001, 60] seconds (the sampled trajectory CSV), got " +
                               s.dump().substr(0, 40));
      }
      std::string name = mission.planner;
      if (params.contains("planner")) {
        if (!params["planner"].is_string()) throw InputError("planner", "must be a planner name (a string)");
        name = params["planner"].get<std::string>();
      }
      json given = json::object();
      if (params.contains("planner_params"))
        given = params["planner_params"];
      else if (name == mission.planner)
        given = mission.planner_params;
      params["planner"] = name;
      if (name == "auto") {  // each candidate plans with its defaults (docs/planners.md)
        if (!given.is_null() && !(given.is_object() && given.empty()))
          throw InputError("planner_params", "\"planner\": \"auto\" plans with each planner's defaults");
        params["planner_params"] = json::object();
      } else {
        params["planner_params"] = planners::validate_params(planners::require(name, "planner"), given);
      }
      // refused before planning: transition altitudes that cannot fit under the export's ceiling
      check_outputs(mission, plan_job_outputs(params));
      break;
    }
    case JobType::Study: {
      reject_unknown(params, {"uavs", "seed", "time_limit_s"});
      if (!params.contains("uavs")) throw InputError("uavs", "required: the UAV counts, e.g. \"1..5\"");
      if (params["uavs"].is_number_unsigned())
        params["uavs"] = std::to_string(params["uavs"].get<std::uint64_t>());
      if (!params["uavs"].is_string()) throw InputError("uavs", "expected counts like \"1..5\" or \"1,2,4\"");
      (void)parse_uav_counts(params["uavs"].get<std::string>(), "uavs");
      break;
    }
    case JobType::Comparison: {
      reject_unknown(params, {"planners", "seed", "time_limit_s"});
      if (params.contains("planners")) {
        const json& p = params["planners"];
        if (!p.is_array() || p.empty() || p.size() > 32)
          throw InputError("planners", "expected a list of 1 to 32 planner names");
        for (std::size_t i = 0; i < p.size(); ++i) {
          if (!p[i].is_string()) throw InputError(fmt::format("planners[{}]", i), "must be a planner name");
          (void)planners::require(p[i].get<std::string>(), fmt::format("planners[{}]", i));
        }
      }
      break;
    }
  }
  return params;
}

JobResult run_job(JobType type, const Mission& mission, const json& params, const Context& ctx) {
  switch (type) {
    case JobType::Plan:
      // a refly (POST /flights/{id}/refly): the mission of the gaps the route made, stored with the job
      if (const auto r = params.find("refly"); r != params.end() && r->is_object() && r->contains("mission"))
        return plan_job(parse_mission(r->at("mission").dump()), params, ctx);
      return plan_job(mission, params, ctx);
    case JobType::Study:
      return study_job(mission, params, ctx);
    case JobType::Comparison:
      return comparison_job(mission, params, ctx);
  }
  throw OperationError("unknown job type");
}

std::optional<std::string> export_artifact_name(const std::vector<std::string>& names,
                                                const std::string& format, const std::string& uav) {
  // the file of each route, in order of preference (Litchi: the zip of all parts when split)
  const ExportRoute* route = find_export_route(format);
  if (route == nullptr) return std::nullopt;
  const std::vector<std::string>& patterns = route->files;
  auto has = [&](const std::string& n) { return std::find(names.begin(), names.end(), n) != names.end(); };
  if (!uav.empty()) {
    for (const auto& pattern : patterns) {
      const std::string n = fmt::format(fmt::runtime(pattern), uav);
      if (has(n)) return n;
    }
    return std::nullopt;
  }
  // no UAV named: the one UAV's file, when exactly one UAV has one
  std::optional<std::string> found;
  for (const auto& pattern : patterns) {
    const auto brace = pattern.find("{}");
    const std::string prefix = pattern.substr(0, brace), suffix = pattern.substr(brace + 2);
    for (const auto& n : names) {
      if (n.size() <= prefix.size() + suffix.size() || !n.starts_with(prefix) || !n.ends_with(suffix))
        continue;
      const std::string id = n.substr(prefix.size(), n.size() - prefix.size() - suffix.size());
      if (id.find('/') != std::string::npos || fmt::format(fmt::runtime(pattern), id) != n) continue;
      // "a.kmz" also ends like "a.wpml.kmz" of dji and "a.1.litchi.csv" like a Litchi part: skip those
      if (format == "kmz" && id.ends_with(".wpml")) continue;
      if (format == "litchi" && suffix == ".litchi.csv" && id.find('.') != std::string::npos) continue;
      if (found && *found != n) return std::nullopt;  // several UAVs: the caller must choose
      found = n;
    }
    if (found) return found;
  }
  return found;
}

json resolve_catalog_refs(const json& document, const CatalogLookup& uav, const CatalogLookup& camera) {
  json doc = document;
  if (!doc.is_object()) return doc;
  auto ref_id = [](const json& v, const std::string& field) {
    if (!v.is_number_integer() || v.get<std::int64_t>() <= 0 || v.get<std::int64_t>() > (1LL << 53))
      throw InputError(field, "expected a catalog id (a positive integer), got " + v.dump().substr(0, 40));
    return static_cast<long long>(v.get<std::int64_t>());
  };
  auto fill = [](json& target, const json& entry, std::initializer_list<const char*> keys) {
    for (const char* k : keys)
      if (!target.contains(k) && entry.contains(k) && !entry[k].is_null()) target[k] = entry[k];
  };
  // the mission's camera as given (before its own catalog reference is resolved below): a catalog
  // UAV's camera_id other than it becomes the UAV's own camera at the same altitude and overlaps
  const json mission_camera =
      doc.contains("camera") && doc["camera"].is_object() ? doc["camera"] : json(nullptr);
  std::optional<long long> mission_camera_id;
  if (mission_camera.is_object() && mission_camera.contains("catalog_id") &&
      mission_camera["catalog_id"].is_number_integer())
    mission_camera_id = mission_camera["catalog_id"].get<long long>();
  if (doc.contains("uavs") && doc["uavs"].is_array()) {
    auto& list = doc["uavs"];
    for (std::size_t i = 0; i < list.size(); ++i) {
      json& u = list[i];
      if (!u.is_object() || !u.contains("catalog_id")) continue;
      const std::string field = fmt::format("uavs[{}].catalog_id", i);
      const auto entry = uav(ref_id(u["catalog_id"], field));
      if (!entry) throw InputError(field, "no UAV with this id in the catalog (GET /api/v1/uavs)");
      u.erase("catalog_id");
      fill(u, *entry, {"speed_mps", "max_accel_mps2", "endurance_min"});
      // the UAV's camera (issue 29): when the mission shoots with a camera block and this UAV carries
      // another catalog camera, that camera with the mission's altitude and overlaps is the UAV's own
      // (the library's heterogeneous cameras); a UAV with a camera block of its own keeps it
      const auto cam_it = entry->find("camera_id");
      if (cam_it == entry->end() || !cam_it->is_number_integer() || u.contains("camera") ||
          !mission_camera.is_object())
        continue;
      const long long cam_id = cam_it->get<long long>();
      if (mission_camera_id && *mission_camera_id == cam_id) continue;  // the mission's camera already
      const auto cam = camera(cam_id);
      if (!cam) continue;  // deleted from the catalog since: the mission's camera
      const bool fov = mission_camera.contains("overlap") || mission_camera.contains("hfov_deg");
      json own = json::object();
      for (const char* k : {"altitude_m", "overlap", "side_overlap", "front_overlap",
                            "min_trigger_interval_s", "gimbal_pitch_deg", "capture", "image_size_mb"})
        if (mission_camera.contains(k)) own[k] = mission_camera[k];
      if (fov) {
        if (!cam->contains("hfov_deg") || !(*cam)["hfov_deg"].is_number())
          continue;  // cannot be described so
        own["hfov_deg"] = (*cam)["hfov_deg"];
      } else {
        bool complete = true;
        for (const char* k : {"sensor_width_mm", "focal_length_mm", "image_width_px"}) {
          if (!cam->contains(k) || !(*cam)[k].is_number())
            complete = false;
          else
            own[k] = (*cam)[k];
        }
        if (!complete) continue;
      }
      u["camera"] = std::move(own);
    }
  }
  if (doc.contains("camera") && doc["camera"].is_object() && doc["camera"].contains("catalog_id")) {
    json& c = doc["camera"];
    const auto entry = camera(ref_id(c["catalog_id"], "camera.catalog_id"));
    if (!entry)
      throw InputError("camera.catalog_id", "no camera with this id in the catalog (GET /api/v1/cameras)");
    c.erase("catalog_id");
    if (c.contains("overlap") || c.contains("hfov_deg"))
      fill(c, *entry, {"hfov_deg"});  // the paper's convention (eq. 14)
    else
      fill(c, *entry, {"sensor_width_mm", "focal_length_mm", "image_width_px"});  // QGroundControl's
  }
  return doc;
}

}  // namespace uavcover::usecases
