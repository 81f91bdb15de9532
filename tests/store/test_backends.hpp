// (named test_backends.hpp, not backends.hpp: "store/backends.hpp" must keep naming src/store/backends.hpp)
// The stores the conformance suite runs against. Every test gets a store of its own URL:
// - "sqlite:" -> a fresh temporary SQLite file for each test (removed afterwards);
// - UAVCOVER_TEST_PG, when set, a PostgreSQL URL: one database for the whole run, so tests never
//   assume empty tables (they use unique names, compare counts before and after, and leave no job
//   queued or running).
#pragma once

#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "store/backends.hpp"

namespace uavcover::testing {

inline std::vector<std::string> store_test_urls() {
  std::vector<std::string> urls{"sqlite:"};
  if (const char* pg = std::getenv("UAVCOVER_TEST_PG"); pg && *pg) urls.emplace_back(pg);
  return urls;
}

/// A name no other test (nor an earlier run against the same PostgreSQL database) uses.
inline std::string unique_name(const std::string& prefix) {
  static std::atomic<int> counter{0};
  static const unsigned salt = std::random_device{}();
  return prefix + "-" + std::to_string(::getpid()) + "-" + std::to_string(salt) + "-" +
         std::to_string(counter++);
}

/// A path for a new SQLite file in a fresh temporary folder.
inline std::string fresh_sqlite_path() {
  const auto dir = std::filesystem::temp_directory_path() / unique_name("uavcover-store-test");
  return (dir / "store.db").string();
}

/// The URL a test opens: "sqlite:" becomes a fresh file, any other URL is used as it is.
inline std::string fresh_store_url(const std::string& url) {
  return url == "sqlite:" ? "sqlite:" + fresh_sqlite_path() : url;
}

/// Opens a test store: SQLite through open_sqlite, others through open_store (which needs the
/// PostgreSQL backend linked in).
inline std::unique_ptr<store::Store> open_test_store(const std::string& url) {
  if (url.starts_with("sqlite:")) return store::open_sqlite(url.substr(7));
#ifdef UAVCOVER_STORE_HAS_POSTGRES
  return store::open_store(url);
#else
  throw store::StoreError("this build has no PostgreSQL store backend for " + url);
#endif
}

/// Removes a fresh SQLite file's folder (nothing for other URLs).
inline void remove_test_store(const std::string& url) {
  if (!url.starts_with("sqlite:/")) return;
  const auto dir = std::filesystem::path(url.substr(7)).parent_path();
  if (!dir.filename().string().starts_with("uavcover-store-test-")) return;  // not one of ours
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
}

}  // namespace uavcover::testing
