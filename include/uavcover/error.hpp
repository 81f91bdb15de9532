#pragma once

#include <stdexcept>
#include <string>

namespace uavcover {

/// Bad user input. `field()` names the offending field as a JSON path
/// (e.g. "uavs[1].share"); what() is the full one-line message "field: problem".
/// The CLI maps it to exit code 2, the server to HTTP 400.
class InputError : public std::runtime_error {
 public:
  InputError(std::string field, const std::string& problem)
      : std::runtime_error(field.empty() ? problem : field + ": " + problem), field_(std::move(field)) {}
  [[nodiscard]] const std::string& field() const noexcept { return field_; }

 private:
  std::string field_;
};

/// An operation that could not be completed for a reason outside the program (a vehicle that does
/// not answer, a file that cannot be written). The CLI prints "error: ..." and exits with 1.
class OperationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace uavcover
