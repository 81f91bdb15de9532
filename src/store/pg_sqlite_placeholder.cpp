// TEMPORARY (branch store-pg only): lets test_store link before the SQLite backend (sqlite_store.cpp,
// written on branch store-sqlite) is merged. Delete this file when merging; the real open_sqlite()
// then replaces it (a duplicate definition would fail the link, so it cannot be forgotten).
#include "store/backends.hpp"

namespace uavcover::store {

std::unique_ptr<Store> open_sqlite(const std::string&) {
  throw StoreError("the SQLite backend is not part of this build (branch store-pg)");
}

}  // namespace uavcover::store
