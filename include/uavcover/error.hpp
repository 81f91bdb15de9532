// The error policy of the library, the CLI and the server:
//   InputError       the user's input is wrong             exit 2, HTTP 4xx
//   OperationError   the environment failed                exit 1, HTTP 5xx
//   Cancelled        a stop was requested (Ctrl-C, job)    exit 130, job state "cancelled"
//   TimeLimitReached the time budget ran out with no complete result to return
//                                                          exit 3, job state "failed"
// Library messages never name a command-line flag: fields are named as JSON paths of the input.
#pragma once

#include <stdexcept>
#include <string>

namespace uavcover {

/// Bad user input. `field()` names the offending field as a JSON path
/// (e.g. "uavs[1].share"); what() is the full one-line message "field: problem".
class InputError : public std::runtime_error {
 public:
  InputError(std::string field, const std::string& problem)
      : std::runtime_error(field.empty() ? problem : field + ": " + problem), field_(std::move(field)) {}
  [[nodiscard]] const std::string& field() const noexcept { return field_; }

 private:
  std::string field_;
};

/// An operation that could not be completed for a reason outside the user's input (a vehicle that
/// does not answer, a file that cannot be written, an internal failure).
class OperationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Work stopped because a stop was requested through the Context.
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("stopped on request") {}
};

/// The Context's time budget ran out before any complete result existed.
class TimeLimitReached : public std::runtime_error {
 public:
  explicit TimeLimitReached(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace uavcover
