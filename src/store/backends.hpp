// The two store backends behind open_store().
#pragma once

#include <memory>
#include <string>

#include "store/store.hpp"

namespace uavcover::store {

/// "PATH" (parent folder created) or ":memory:".
std::unique_ptr<Store> open_sqlite(const std::string& path);
/// A libpq connection URI.
std::unique_ptr<Store> open_postgres(const std::string& uri);

}  // namespace uavcover::store
