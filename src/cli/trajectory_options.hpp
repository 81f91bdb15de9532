// The trajectory method's options of `uavcover plan` and `uavcover export` (docs/trajectory.md): one
// definition for both commands, and the library's field names turned into these flags in errors.
#pragma once

#include <CLI/CLI.hpp>
#include <map>
#include <string>

#include "cli/validators.hpp"
#include "trajectory/trajectory.hpp"
#include "uavcover/error.hpp"

namespace uavcover::cli {

/// --trajectory-method, --order, --v-mean, --v-min, --a-min into `opt`.
inline void add_trajectory_method_options(CLI::App* cmd, trajectory::Options& opt) {
  const std::map<std::string, trajectory::Method> methods{
      {trajectory::method_name(trajectory::Method::FilletLines), trajectory::Method::FilletLines},
      {trajectory::method_name(trajectory::Method::Polynomial), trajectory::Method::Polynomial}};
  cmd->add_option("--trajectory-method", opt.method,
                  "Trajectory: fillet-lines (lines and corner arcs, the default) or polynomial (order "
                  "--order through every waypoint, mean speed --v-mean per segment; its CSV is sampled)")
      ->transform(CLI::CheckedTransformer(methods));
  cmd->add_option("--order", opt.order, "Polynomial trajectory: the degree P of each segment (3, 5 or 7)")
      ->capture_default_str()
      ->check(CLI::IsMember({3, 5, 7}));
  cmd->add_option("--v-mean", opt.v_mean,
                  "Polynomial trajectory: each segment's mean speed before stretching (m/s, 0 = the UAV's "
                  "speed)")
      ->check(number_in(0, 1'000));
  cmd->add_option("--v-min", opt.v_min,
                  "Polynomial trajectory: lower bound of every velocity component (m/s, negative; default "
                  "minus the UAV's speed)")
      ->check(number_in(-1'000, 0, false, true));
  cmd->add_option("--a-min", opt.a_min,
                  "Polynomial trajectory: lower bound of every acceleration component (m/s^2, negative; "
                  "default minus the UAV's acceleration)")
      ->check(number_in(-1'000, 0, false, true));
}

/// The library's InputError on a trajectory option as the flag's: "v_min" -> "--v-min"; others unchanged.
[[noreturn]] inline void rethrow_as_flag(const InputError& e) {
  static const std::map<std::string, std::string> flags{
      {"order", "--order"}, {"v_mean", "--v-mean"}, {"v_min", "--v-min"}, {"a_min", "--a-min"}};
  const auto it = flags.find(e.field());
  if (it == flags.end()) throw e;
  throw InputError(it->second, std::string(e.what()).substr(e.field().size() + 2));
}

}  // namespace uavcover::cli
