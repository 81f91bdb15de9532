// Sub-commands register themselves here; main() builds the CLI11 app from the registry.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace uavcover::cli {

/// Shared flags every sub-command may read.
struct GlobalFlags {
  bool quiet = false;
};
GlobalFlags& global_flags();

using CommandFactory = std::function<void(CLI::App& app)>;
struct CommandRegistry {
  static std::vector<std::pair<int, CommandFactory>>& all();
  /// `order` sorts commands in --help.
  static bool add(int order, CommandFactory f) {
    all().emplace_back(order, std::move(f));
    return true;
  }
};

}  // namespace uavcover::cli
