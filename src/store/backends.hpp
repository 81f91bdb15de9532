// The two store backends behind open_store().
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "store/store.hpp"

namespace uavcover::store {

/// "PATH" (parent folder created) or ":memory:".
std::unique_ptr<Store> open_sqlite(const std::string& path);
/// A libpq connection URI.
std::unique_ptr<Store> open_postgres(const std::string& uri);

/// The rule for a job taken up again after its worker was gone (Store::claim, requeue at start): one
/// that has had `max_attempts` attempts is marked failed instead, with this error.
inline bool interrupted_too_often(int attempts, int max_attempts) { return attempts >= max_attempts; }
/// The error of such a job: "the job was interrupted N times".
inline nlohmann::json interrupted_error(int attempts) {
  return {{"field", ""}, {"message", "the job was interrupted " + std::to_string(attempts) + " times"}};
}

}  // namespace uavcover::store
