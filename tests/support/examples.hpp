// Planned examples and error helpers shared by the tests.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "support/files.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover::testing {

/// examples/olive-grove.json planned once (3 UAVs, DARP, seed 42).
inline const Plan& olive_grove_plan() {
  static const Plan p = plan(
      parse_mission(slurp(std::filesystem::path(UAVCOVER_SOURCE_DIR) / "examples" / "olive-grove.json")));
  return p;
}

/// The field an InputError thrown by `f` names, or "(no InputError)".
inline std::string input_error_field(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.field();
  }
  return "(no InputError)";
}

}  // namespace uavcover::testing
