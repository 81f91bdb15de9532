#include "usecases/compare.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

#include "planners/planner.hpp"
#include "render/render.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover::usecases {

Comparison compare(const Mission& mission, const CompareOptions& options, const Context& ctx) {
  std::vector<std::string> names = options.planners;
  if (names.empty())
    for (const auto& p : planners::registry()) names.push_back(p.name);
  for (const auto& n : names) (void)planners::require(n, "planners");
  Comparison out;
  out.mission = mission.name;
  out.wind = mission.wind;
  for (std::size_t k = 0; k < names.size(); ++k) {
    CompareRow row;
    row.planner = names[k];
    const double done = static_cast<double>(k) / static_cast<double>(names.size());
    const double step = 1.0 / static_cast<double>(names.size());
    const Context sub = ctx.with_progress([&ctx, name = names[k], done, step](std::string_view, double f) {
      ctx.report(name, done + step * f);
    });
    Mission m = mission;
    if (m.planner != row.planner) {
      m.planner = row.planner;
      m.planner_params = nlohmann::json::object();  // the other planner's defaults
    }
    try {
      const auto t0 = std::chrono::steady_clock::now();
      row.plan = plan(m, {}, sub);
      row.compute_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      evaluation::EvaluateOptions eo = options.evaluation;
      eo.coverage.context = &ctx;
      row.evaluation = evaluation::evaluate_plan(row.plan, eo);
      if (mission.wind && mission.wind->speed_mps > 0.0) {  // the old model's figure, for comparison
        eo.cost.wind = Wind{};
        eo.compute_coverage = false;
        row.flight_time_calm_min = evaluation::evaluate_plan(row.plan, eo).cost.flight_time_min;
      }
      for (const auto& u : row.plan.uavs)
        row.max_share_deviation =
            std::max(row.max_share_deviation, std::fabs(u.share_actual - u.share_requested));
      row.ok = true;
    } catch (const InputError& e) {
      row.error = e.what();
    }
    out.rows.push_back(std::move(row));
  }
  ctx.report("done", 1.0);
  return out;
}

nlohmann::json compare_json(const Comparison& c) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& r : c.rows) {
    nlohmann::json e{{"planner", r.planner}, {"ok", r.ok}};
    if (!r.ok) {
      e["error"] = r.error;
      rows.push_back(std::move(e));
      continue;
    }
    const auto& t = r.evaluation.coverage.total;
    const auto& cost = r.evaluation.cost;
    double coverage_length = 0;
    for (const auto& u : r.plan.uavs) coverage_length += u.coverage_length_m;
    nlohmann::json shares = nlohmann::json::array();
    for (const auto& u : r.plan.uavs)
      shares.push_back({{"uav", u.id}, {"requested", u.share_requested}, {"actual", u.share_actual}});
    e.update(nlohmann::json{{"poc", t.poc},
                            {"pooc", t.pooc},
                            {"turns", t.turns},
                            {"length_m", t.length_m},
                            {"coverage_length_m", coverage_length},
                            {"flight_time_min", cost.flight_time_min},
                            {"batteries_per_uav", cost.batteries_per_uav},
                            {"total_time_min", cost.total_time_min},
                            {"cost_eur", cost.flight_cost_eur},
                            {"compute_time_s", r.compute_s},
                            {"complete", r.plan.complete},
                            {"max_share_deviation", r.max_share_deviation},
                            {"shares", std::move(shares)},
                            {"warnings", r.plan.warnings}});
    if (r.flight_time_calm_min) e["flight_time_calm_min"] = *r.flight_time_calm_min;
    rows.push_back(std::move(e));
  }
  nlohmann::json wind = c.wind
                            ? nlohmann::json{{"speed_mps", c.wind->speed_mps}, {"from_deg", c.wind->from_deg}}
                            : nlohmann::json(nullptr);
  return {{"mission", c.mission}, {"wind", std::move(wind)}, {"planners", std::move(rows)}};
}

std::string compare_markdown(const Comparison& c) {
  std::string md = fmt::format("# {} — planners compared\n\n", c.mission.empty() ? "Mission" : c.mission);
  md +=
      "Every plan is evaluated by the same simulation (square footprint swept along each leg) and cost "
      "model.\n\n" +
      (c.wind ? fmt::format("Times are in the mission's wind: {} m/s from {} degrees.\n\n", c.wind->speed_mps,
                            c.wind->from_deg)
              : std::string()) +
      "| planner | PoC % | PoOC % | turns | length km | coverage km | flight min | batteries/UAV | total min "
      "| "
      "cost EUR | compute s | max share dev. |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : c.rows) {
    if (!r.ok) {
      md += fmt::format("| {} | refused: {} |||||||||||\n", r.planner, r.error);
      continue;
    }
    const auto& t = r.evaluation.coverage.total;
    const auto& cost = r.evaluation.cost;
    double coverage_length = 0;
    for (const auto& u : r.plan.uavs) coverage_length += u.coverage_length_m;
    md += fmt::format(
        "| {}{} | {:.2f} | {:.2f} | {} | {:.3f} | {:.3f} | {:.2f} | {} | {:.2f} | {:.2f} | {:.3f} | {:.3f} "
        "|\n",
        r.planner, r.plan.complete ? "" : " (time limit)", 100 * t.poc, 100 * t.pooc, t.turns,
        t.length_m / 1000, coverage_length / 1000, cost.flight_time_min, cost.batteries_per_uav,
        cost.total_time_min, cost.flight_cost_eur, r.compute_s, r.max_share_deviation);
  }
  return md;
}

Artifacts compare_outputs(const Comparison& c, bool images) {
  Artifacts out{{"compare.json", "application/json", compare_json(c).dump(1) + "\n"},
                {"compare.md", "text/markdown", compare_markdown(c)}};
  if (images) {
    std::vector<render::Panel> panels;
    for (const auto& r : c.rows)
      if (r.ok)
        panels.push_back(
            {fmt::format("{}: PoC {:.1f} %, {} turns, {:.2f} km", r.planner,
                         100 * r.evaluation.coverage.total.poc, r.evaluation.coverage.total.turns,
                         r.evaluation.coverage.total.length_m / 1000),
             &r.plan});
    if (!panels.empty()) out.push_back(render::plans_png(panels));
  }
  return out;
}

}  // namespace uavcover::usecases
