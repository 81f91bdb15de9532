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

/// The camera a UAV catalog entry's data names ("camera_id"), or 0 (none, or not a UAV). Both backends
/// check it in the transaction that writes the UAV, and a camera's delete checks its users in its own,
/// so no UAV is ever left with a dangling camera_id (issue 28).
inline Id camera_ref(CatalogKind kind, const nlohmann::json& data) {
  if (kind != CatalogKind::Uav || !data.is_object()) return 0;
  const auto it = data.find("camera_id");
  return it != data.end() && it->is_number_integer() ? it->get<Id>() : 0;
}
/// Conflict's text when a UAV names a camera that does not exist (deleted meanwhile).
inline std::string camera_missing_text(Id camera) {
  return "camera_id: no camera " + std::to_string(camera) + " (deleted meanwhile?)";
}
/// Conflict's text when a camera that a UAV carries is deleted.
inline std::string camera_in_use_text(Id camera, Id uav, const std::string& uav_name) {
  return "camera " + std::to_string(camera) + " is used by UAV " + std::to_string(uav) + " (\"" +
         uav_name.substr(0, 80) + "\"): change or delete that UAV first";
}

}  // namespace uavcover::store
