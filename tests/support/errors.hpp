// The field an InputError names, for tests of refusals.
#pragma once

#include <functional>
#include <string>

#include "uavcover/error.hpp"

namespace uavcover::testing {

/// The field() of the InputError `f` throws, or "(no error)" when it throws none.
inline std::string field_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.field();
  }
  return "(no error)";
}

}  // namespace uavcover::testing
