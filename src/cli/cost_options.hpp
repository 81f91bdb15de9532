// Command-line options of the time and cost model (eq. 18, 21), shared by evaluate and study.
#pragma once

#include <CLI/CLI.hpp>

#include "cli/validators.hpp"

#include "evaluation/cost.hpp"

namespace uavcover::cli {

inline void add_cost_options(CLI::App* cmd, evaluation::CostOptions& cost) {
  cmd->add_option("--fcm", cost.fcm_eur_per_min, "Flight cost per minute (EUR), eq. 21")
      ->capture_default_str()
      ->check(number_in(0, 1e6));
  cmd->add_option("--deploy-base", cost.deployment_base_min, "Deployment time base (min), eq. 18")
      ->capture_default_str()
      ->check(number_in(0, 1e6));
  cmd->add_option("--deploy-per-uav", cost.deployment_per_uav_min, "Deployment time per UAV (min), eq. 18")
      ->capture_default_str()
      ->check(number_in(0, 1e6));
  cmd->add_option("--battery-change", cost.battery_change_min, "Minutes per battery change, eq. 19 and 22")
      ->capture_default_str()
      ->check(number_in(0, 1e6));
}

}  // namespace uavcover::cli
