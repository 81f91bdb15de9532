// uavcover command line: a thin shell over the library facade (include/uavcover/uavcover.hpp).
#include <cstdio>
#include <iostream>

#include "cli/command.hpp"
#include "cli/interrupt.hpp"
#include "cli/validators.hpp"
#include "io/plan_io.hpp"
#include "uavcover/error.hpp"

namespace uavcover::cli {

GlobalFlags& global_flags() {
  static GlobalFlags flags;
  return flags;
}

std::vector<std::pair<int, CommandFactory>>& CommandRegistry::all() {
  static std::vector<std::pair<int, CommandFactory>> registry;
  return registry;
}

}  // namespace uavcover::cli

namespace {

int run(int argc, char** argv) {
  using namespace uavcover;
  CLI::App app{
      "uavcover: multi-UAV coverage mission planner.\n"
      "Divides an area among drones with a choice of planners (DARP, boustrophedon, ...), gives each\n"
      "a coverage path, evaluates coverage, time and cost, and exports flight-ready files.\n"
      "Exit codes: 0 ok, 1 internal or environment error, 2 bad input or usage, 3 time limit reached\n"
      "without a complete plan, 130 interrupted (Ctrl-C)."};
  app.require_subcommand(1);
  app.fallthrough();  // global flags (--quiet) may follow the sub-command
  app.set_version_flag("--version", "uavcover 0.1.0");
  app.add_flag("-q,--quiet", cli::global_flags().quiet, "No progress bar or summary");
  app.add_option("--max-input-mb",
                 "Refuse input files larger than this many MiB (default 64, or "
                 "$UAVCOVER_MAX_INPUT_MB; see docs/limits.md)")
      ->check(cli::integer_in(1, 4096))
      ->each([](const std::string& mb) { io::set_max_input_bytes(std::stoull(mb) << 20); });
  auto& registry = cli::CommandRegistry::all();
  std::stable_sort(registry.begin(), registry.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [order, factory] : registry) factory(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  } catch (const InputError& e) {
    std::cerr << "uavcover: error: " << e.what() << "\n";
    return 2;
  } catch (const Cancelled&) {
    std::cerr << "\nuavcover: stopped (interrupted); nothing was written\n";
    return 130;
  } catch (const TimeLimitReached& e) {
    std::cerr << "uavcover: error: " << e.what() << "; nothing was written (raise --time-limit)\n";
    return 3;
  } catch (const OperationError& e) {
    std::cerr << "uavcover: error: " << e.what() << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "uavcover: internal error: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "uavcover: internal error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  uavcover::cli::install_interrupt_handler();
  try {
    return run(argc, argv);
  } catch (...) {  // e.g. while building the command-line app: never let an exception escape
    std::cerr << "uavcover: internal error: unexpected exception\n";
    return 1;
  }
}
