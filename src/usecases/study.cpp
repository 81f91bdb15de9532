#include "usecases/study.hpp"

#include <fmt/format.h>

#include <chrono>
#include <exception>
#include <set>

#include "render/render.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover::usecases {

std::vector<int> parse_uav_counts(const std::string& spec, const std::string& field) {
  std::set<int> out;
  auto bad = [&] {
    return InputError(field, "expected counts like 1..15 or 1,2,3,5 (each 1..200), got '" + spec + "'");
  };
  auto num = [&](const std::string& s) {
    if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || s.size() > 4) throw bad();
    const int v = std::stoi(s);
    if (v < 1 || v > 200) throw bad();
    return v;
  };
  std::size_t pos = 0;
  while (pos <= spec.size()) {
    const std::size_t comma = spec.find(',', pos);
    const std::string item = spec.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    const std::size_t dots = item.find("..");
    if (dots == std::string::npos) {
      out.insert(num(item));
    } else {
      const int a = num(item.substr(0, dots)), b = num(item.substr(dots + 2));
      if (a > b) throw bad();
      for (int k = a; k <= b; ++k) out.insert(k);
    }
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  if (out.empty()) throw bad();
  return {out.begin(), out.end()};
}

Mission with_uavs(const Mission& m, int n) {
  Mission out = m;
  out.uavs.clear();
  const Uav base = m.uavs.empty() ? Uav{} : m.uavs.front();
  for (int i = 0; i < n; ++i) {
    Uav u = static_cast<std::size_t>(i) < m.uavs.size() ? m.uavs[static_cast<std::size_t>(i)] : base;
    if (static_cast<std::size_t>(i) >= m.uavs.size()) u.start.reset();
    u.id = "uav-" + std::to_string(i + 1);
    u.share = 1.0 / n;
    out.uavs.push_back(u);
  }
  return out;
}

Study run_study(const Mission& mission, const StudyOptions& options, const Context& ctx) {
  Study study;
  study.mission = mission.name;
  study.wind = mission.wind;
  std::exception_ptr first_error;
  const auto& counts = options.counts;
  for (std::size_t k = 0; k < counts.size(); ++k) {
    StudyRow row;
    row.uavs = counts[k];
    const double done = static_cast<double>(k) / static_cast<double>(counts.size());
    const double step = 1.0 / static_cast<double>(counts.size());
    const std::string stage = fmt::format("{} UAV{}", row.uavs, row.uavs == 1 ? "" : "s");
    // a context for this row: the same stop token and deadline, progress mapped into the whole study
    const Context sub = ctx.with_progress(
        [&ctx, stage, done, step](std::string_view, double f) { ctx.report(stage, done + step * f); });
    try {
      PlanOptions po;
      po.seed = options.seed;
      const auto t0 = std::chrono::steady_clock::now();
      const Plan p = plan(with_uavs(mission, row.uavs), po, sub);
      row.compute_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      row.complete = p.complete;
      row.planner_diagnostics = p.diagnostics;
      evaluation::EvaluateOptions eo;
      eo.cost = options.cost;
      eo.coverage.context = &ctx;
      row.evaluation = evaluation::evaluate_plan(p, eo);
      if (mission.wind && mission.wind->speed_mps > 0.0) {  // the old model's figure, for comparison
        eo.cost.wind = Wind{};
        eo.compute_coverage = false;
        row.flight_time_calm_min = evaluation::evaluate_plan(p, eo).cost.flight_time_min;
      }
      row.ok = true;
    } catch (const Cancelled&) {
      throw;
    } catch (const TimeLimitReached&) {
      throw;
    } catch (const InputError& e) {
      row.error = e.what();
      if (!first_error) first_error = std::current_exception();
    }
    study.rows.push_back(std::move(row));
  }
  ctx.report("done", 1.0);
  bool any = false;
  for (const auto& r : study.rows) any = any || r.ok;
  if (!any && first_error) std::rethrow_exception(first_error);

  double best_total = 0.0;
  for (const auto& r : study.rows) {
    if (!r.ok) continue;
    if (study.recommended == 0 || r.evaluation.cost.total_time_min < best_total - 1e-9) {
      study.recommended = r.uavs;
      best_total = r.evaluation.cost.total_time_min;
    }
    if (study.min_single_battery == 0 && r.evaluation.cost.single_battery) study.min_single_battery = r.uavs;
  }
  return study;
}

nlohmann::json study_json(const Study& study) {
  nlohmann::json j;
  j["mission"] = study.mission;
  j["wind"] = study.wind
                  ? nlohmann::json{{"speed_mps", study.wind->speed_mps}, {"from_deg", study.wind->from_deg}}
                  : nlohmann::json(nullptr);
  j["recommended_uavs"] = study.recommended;
  j["min_uavs_single_battery"] =
      study.min_single_battery > 0 ? nlohmann::json(study.min_single_battery) : nlohmann::json(nullptr);
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& r : study.rows) {
    nlohmann::json e{{"uavs", r.uavs}};
    if (!r.ok) {
      e["error"] = r.error;
    } else {
      const auto& t = r.evaluation.coverage.total;
      const auto& c = r.evaluation.cost;
      e.update(nlohmann::json{{"poc", t.poc},
                              {"pooc", t.pooc},
                              {"max_scans", t.max_scans},
                              {"turns", t.turns},
                              {"length_m", t.length_m},
                              {"batteries_per_uav", c.batteries_per_uav},
                              {"flight_time_min", c.flight_time_min},
                              {"deployment_time_min", c.deployment_time_min},
                              {"change_battery_delay_min", c.change_battery_delay_min},
                              {"total_time_min", c.total_time_min},
                              {"cost_eur", c.flight_cost_eur},
                              {"single_battery", c.single_battery},
                              {"compute_time_s", r.compute_s},
                              {"complete", r.complete},
                              {"planner_diagnostics", r.planner_diagnostics}});
      if (r.flight_time_calm_min) e["flight_time_calm_min"] = *r.flight_time_calm_min;
    }
    rows.push_back(std::move(e));
  }
  j["rows"] = std::move(rows);
  return j;
}

Artifact study_picture(const Study& study) {
  std::vector<render::StudyPoint> pts;
  for (const auto& r : study.rows)
    if (r.ok)
      pts.push_back({r.uavs, r.evaluation.cost.flight_time_min, r.evaluation.cost.total_time_min,
                     r.evaluation.cost.flight_cost_eur});
  return render::study_png(pts, "study.png", 1200, 800, study.recommended,
                           "Multi-UAV study" + (study.mission.empty() ? "" : " - " + study.mission));
}

}  // namespace uavcover::usecases
