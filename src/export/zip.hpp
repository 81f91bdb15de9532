// ZIP archives (KMZ, DJI KMZ) built in memory.
#pragma once

#include <map>
#include <string>

namespace uavcover::exporting {

/// A ZIP archive holding `entries` (name -> bytes, deflated), as bytes. Entry times are fixed
/// (2000-01-01), so the same entries give the same archive. Throws OperationError when libzip fails.
std::string zip_bytes(const std::map<std::string, std::string>& entries);

}  // namespace uavcover::exporting
