// `uavcover study MISSION.json --uavs 1..15 [--out DIR]`: the multi-robot marginal utility study of
// Apostolidis et al. 2022 §3.2 (Tables 7 and 8): plan for each UAV count, evaluate, compare.
#include <fmt/format.h>

#include <chrono>
#include <exception>
#include <filesystem>
#include <iostream>
#include <set>

#include "cli/command.hpp"
#include "cli/cost_options.hpp"
#include "cli/progress.hpp"
#include "cli/validators.hpp"
#include "evaluation/evaluate.hpp"
#include "io/plan_io.hpp"
#include "render/render.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover::cli {
namespace {

struct StudyArgs {
  std::string mission;
  std::string uavs = "1..15";
  std::string out = ".";
  std::optional<std::uint64_t> seed;
  bool no_images = false;
  evaluation::CostOptions cost;
};

/// "1..15", "1,2,3,5" or a mix ("1..3,5,7,9..15").
std::vector<int> parse_counts(const std::string& spec) {
  std::set<int> out;
  auto bad = [&] {
    return InputError("--uavs", "expected counts like 1..15 or 1,2,3,5 (each 1..200), got '" + spec + "'");
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

/// The mission with n UAVs: the mission's own UAVs first (with their starts), then copies of the
/// first UAV's parameters with seeded random starts; equal shares.
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

struct Row {
  int n = 0;
  bool ok = false;
  std::string error;
  evaluation::Evaluation ev;
  double compute_s = 0.0;
  bool converged = true;
};

void run_study(const StudyArgs& a) {
  const Mission mission = parse_mission(io::read_text_file(a.mission, "MISSION"));
  const std::vector<int> counts = parse_counts(a.uavs);
  const bool quiet = global_flags().quiet;
  const Progress bar = make_progress_bar(quiet);
  std::vector<Row> rows;
  std::exception_ptr first_error;
  for (std::size_t k = 0; k < counts.size(); ++k) {
    Row row;
    row.n = counts[k];
    const double done = static_cast<double>(k) / static_cast<double>(counts.size());
    const double step = 1.0 / static_cast<double>(counts.size());
    Progress sub;
    if (bar) {
      const std::string stage = fmt::format("{} UAV{}", row.n, row.n == 1 ? "" : "s");
      sub = [&bar, stage, done, step](std::string_view, double f) { bar(stage, done + step * f); };
    }
    try {
      PlanOptions po;
      po.seed = a.seed;
      const auto t0 = std::chrono::steady_clock::now();
      const Plan p = plan(with_uavs(mission, row.n), po, sub);
      row.compute_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      row.converged = p.darp_converged;
      evaluation::EvaluateOptions eo;
      eo.cost = a.cost;
      row.ev = evaluation::evaluate_plan(p, eo);
      row.ok = true;
    } catch (const std::exception& e) {
      row.error = e.what();
      if (!first_error) first_error = std::current_exception();
    }
    rows.push_back(std::move(row));
  }
  if (bar) bar("done", 1.0);
  finish_progress_bar();
  bool any = false;
  for (const auto& r : rows) any = any || r.ok;
  if (!any && first_error) std::rethrow_exception(first_error);

  // recommendation: minimum total time; fewest UAVs for which every UAV flies on one battery
  int best = 0, single = 0;
  double best_total = 0.0;
  for (const auto& r : rows) {
    if (!r.ok) continue;
    if (best == 0 || r.ev.cost.total_time_min < best_total - 1e-9) {
      best = r.n;
      best_total = r.ev.cost.total_time_min;
    }
    if (single == 0 && r.ev.cost.single_battery) single = r.n;
  }

  nlohmann::json j;
  j["mission"] = mission.name;
  j["recommended_uavs"] = best;
  j["min_uavs_single_battery"] = single > 0 ? nlohmann::json(single) : nlohmann::json(nullptr);
  nlohmann::json jr = nlohmann::json::array();
  std::vector<render::StudyPoint> pts;
  for (const auto& r : rows) {
    nlohmann::json e{{"uavs", r.n}};
    if (!r.ok) {
      e["error"] = r.error;
    } else {
      const auto& t = r.ev.coverage.total;
      const auto& c = r.ev.cost;
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
                              {"darp_converged", r.converged}});
      pts.push_back({r.n, c.flight_time_min, c.total_time_min, c.flight_cost_eur});
    }
    jr.push_back(std::move(e));
  }
  j["rows"] = std::move(jr);
  const std::filesystem::path dir(a.out);
  io::write_file_atomic(dir / "study.json", j.dump(1) + "\n");
  if (!a.no_images)
    render::write_study_png(pts, dir / "study.png", 1200, 800, best,
                            "Multi-UAV study" + (mission.name.empty() ? "" : " - " + mission.name));
  if (quiet) return;

  std::cout << fmt::format("{} — study over {} UAV count(s)\n", mission.name, counts.size());
  std::cout << fmt::format("{:>5} {:>7} {:>7} {:>8} {:>10} {:>10} {:>10} {:>10} {:>9} {:>9}\n", "#UAVs",
                           "PoC%", "PoOC%", "#Bat/UAV", "Flight", "Deploy", "ChangeBat", "Total", "Cost",
                           "Compute");
  std::cout << fmt::format("{:>5} {:>7} {:>7} {:>8} {:>10} {:>10} {:>10} {:>10} {:>9} {:>9}\n", "", "", "",
                           "", "(min)", "(min)", "(min)", "(min)", "(EUR)", "(s)");
  for (const auto& r : rows) {
    if (!r.ok) {
      std::cout << fmt::format("{:>5}  failed: {}\n", r.n, r.error);
      continue;
    }
    const auto& t = r.ev.coverage.total;
    const auto& c = r.ev.cost;
    std::cout << fmt::format(
        "{:>5} {:>7.2f} {:>7.2f} {:>8} {:>10.2f} {:>10.2f} {:>10.2f} {:>10.2f} {:>9.2f} {:>9.2f}{}\n", r.n,
        100 * t.poc, 100 * t.pooc, c.batteries_per_uav, c.flight_time_min, c.deployment_time_min,
        c.change_battery_delay_min, c.total_time_min, c.flight_cost_eur, r.compute_s,
        r.n == best ? "  <- minimum total time" : "");
  }
  std::cout << fmt::format("recommended: {} UAV(s) (minimum total time {:.2f} min)\n", best, best_total);
  if (single > 0)
    std::cout << fmt::format("fewest UAVs in this study with which every UAV finishes on one battery: {}\n",
                             single);
  else
    std::cout << "no UAV count in this study lets every UAV finish on one battery\n";
  std::cout << "wrote " << (dir / "study.json").string() << (a.no_images ? "" : " and study.png") << "\n";
}

const bool registered = CommandRegistry::add(40, [](CLI::App& app) {
  auto a = std::make_shared<StudyArgs>();
  auto* cmd = app.add_subcommand(
      "study",
      "Multi-UAV study: plan and evaluate the mission for several UAV counts, recommend the best count");
  cmd->add_option("MISSION", a->mission,
                  "Mission file (its first UAV's speed/endurance are used for added UAVs)")
      ->required();
  cmd->add_option("--uavs", a->uavs, "UAV counts: 1..15, or 1,2,3,5, or a mix")->capture_default_str();
  cmd->add_option("--out,-o", a->out, "Output folder for study.json and study.png")
      ->capture_default_str()
      ->force_callback()  // the default (the current folder) is checked too
      ->check(output_folder());
  cmd->add_option("--seed", a->seed, "Random seed (overrides the mission's seed)")
      ->check(integer_in<std::uint64_t>(0, std::numeric_limits<std::uint64_t>::max()));
  cmd->add_flag("--no-images", a->no_images, "Do not write study.png");
  add_cost_options(cmd, a->cost);
  cmd->footer(
      "UAVs beyond those the mission lists copy the first UAV's parameters and get seeded random starts;\n"
      "shares are equal. Exit codes: 0 ok, 1 internal error, 2 bad input.");
  cmd->callback([a] { run_study(*a); });
});

}  // namespace
}  // namespace uavcover::cli
