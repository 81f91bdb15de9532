// The stores the conformance suite runs against (store_test_urls()); every test opens a fresh one:
// - "sqlite:" -> a new SQLite file in a new temporary folder, removed afterwards;
// - a PostgreSQL server, when $UAVCOVER_TEST_PG gives its URI or a file holds it ($UAVCOVER_TEST_PG_URL_FILE,
//   or the build's UAVCOVER_TEST_PG_URL_FILE: the throwaway cluster of scripts/pg-test-cluster): a new
//   database on that server for every test (CREATE DATABASE), dropped afterwards. So tests in parallel
//   processes never share a queue.
// The tests still do not assume empty tables (unique names, counts before and after), so they also
// hold on a shared database.
// (This file is not called backends.hpp: "store/backends.hpp" must keep naming src/store/backends.hpp.)
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdint>
#include <functional>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "store/backends.hpp"

#ifdef UAVCOVER_STORE_HAS_POSTGRES
#include <libpq-fe.h>
#endif

namespace uavcover::testing {

/// A stand-in for the PostgreSQL URI that is read from a file when a test starts ("pg-url-file:PATH"):
/// under ctest the throwaway cluster only comes up (and writes the file) after the tests are listed.
inline constexpr std::string_view kPgUrlFile = "pg-url-file:";

/// The PostgreSQL server to test against too, or "": $UAVCOVER_TEST_PG, else the file named by
/// $UAVCOVER_TEST_PG_URL_FILE or by the build (UAVCOVER_TEST_PG_URL_FILE, scripts/pg-test-cluster's).
inline std::string pg_test_url() {
  if (const char* pg = std::getenv("UAVCOVER_TEST_PG"); pg && *pg) return pg;
  if (const char* file = std::getenv("UAVCOVER_TEST_PG_URL_FILE"); file && *file)
    return std::string(kPgUrlFile) + file;
#if defined(UAVCOVER_STORE_HAS_POSTGRES) && defined(UAVCOVER_TEST_PG_URL_FILE)
  return std::string(kPgUrlFile) + UAVCOVER_TEST_PG_URL_FILE;
#else
  return "";
#endif
}

/// The URI a "pg-url-file:PATH" stands for (the first line of PATH); other URLs as they are.
inline std::string resolve_test_url(const std::string& url) {
  if (!url.starts_with(kPgUrlFile)) return url;
  const std::string file = url.substr(kPgUrlFile.size());
  std::ifstream in(file);
  std::string uri;
  if (!std::getline(in, uri) || uri.empty())
    throw store::StoreError("no PostgreSQL test server: " + file +
                            " is missing (run through ctest, or scripts/pg-test-cluster start DIR)");
  return uri;
}

inline std::vector<std::string> store_test_urls() {
  std::vector<std::string> urls{"sqlite:"};
  if (const std::string pg = pg_test_url(); !pg.empty()) urls.push_back(pg);
  return urls;
}

/// A name no other test (nor an earlier run against the same PostgreSQL database) uses.
/// The kill -9 tests: reads the 64-bit values a child process writes to `fd` (what the store acknowledged
/// to it) and hands each to `on_value`; once that returns true, kills the child with SIGKILL, drains the
/// pipe and reaps the child. True when the child was killed by that SIGKILL (not stopped before).
inline bool read_until_killed(int fd, pid_t child, const std::function<bool(std::int64_t)>& on_value) {
  bool killed = false;
  for (;;) {
    std::int64_t value = 0;
    std::size_t got = 0;
    while (got < sizeof value) {
      const ssize_t n = ::read(fd, reinterpret_cast<char*>(&value) + got, sizeof value - got);
      if (n <= 0) break;
      got += static_cast<std::size_t>(n);
    }
    if (got < sizeof value) break;  // the child is gone and the pipe drained
    if (on_value(value) && !killed) {
      if (::kill(child, SIGKILL) != 0) break;
      killed = true;
    }
  }
  ::close(fd);
  int status = 0;
  if (::waitpid(child, &status, 0) != child) return false;
  return killed && WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
}

/// The kill -9 tests' set-up: forks a child that runs `writer` until it is killed; `writer` reports each
/// value the store acknowledged to it through its argument (a pipe to the parent). The parent hands each
/// value to `on_value` and kills the child with SIGKILL once that returns true (read_until_killed).
/// True when the child was killed by that SIGKILL, not stopped before (a writer error exits the child).
inline bool kill_nine_during(const std::function<void(const std::function<void(std::int64_t)>&)>& writer,
                             const std::function<bool(std::int64_t)>& on_value) {
  int fds[2];
  if (::pipe(fds) != 0) return false;
  const pid_t child = ::fork();
  if (child < 0) return false;
  if (child == 0) {
    ::close(fds[0]);
    try {
      writer([&](std::int64_t value) {
        if (::write(fds[1], &value, sizeof value) != static_cast<ssize_t>(sizeof value)) ::_exit(3);
      });
    } catch (...) {
      ::_exit(2);
    }
    ::_exit(0);
  }
  ::close(fds[1]);
  return read_until_killed(fds[0], child, on_value);
}

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

/// The database named by a libpq URI ("postgresql://host:port/NAME?params"), "" when none.
inline std::string pg_database(const std::string& uri) {
  const std::size_t scheme = uri.find("://");
  if (scheme == std::string::npos) return "";
  const std::size_t query = std::min(uri.find('?', scheme + 3), uri.size());
  const std::size_t slash = uri.find('/', scheme + 3);
  if (slash == std::string::npos || slash > query) return "";
  return uri.substr(slash + 1, query - slash - 1);
}

/// The same URI naming database `name` instead.
inline std::string pg_with_database(const std::string& uri, const std::string& name) {
  const std::size_t scheme = uri.find("://");
  if (scheme == std::string::npos) return uri;
  const std::size_t query = std::min(uri.find('?', scheme + 3), uri.size());
  const std::size_t slash = uri.find('/', scheme + 3);
  if (slash == std::string::npos || slash > query)
    return uri.substr(0, query) + "/" + name + uri.substr(query);
  return uri.substr(0, slash + 1) + name + uri.substr(query);
}

#ifdef UAVCOVER_STORE_HAS_POSTGRES
/// Runs one statement on the server of `uri`; throws with the server's message.
inline void pg_admin(const std::string& uri, const std::string& sql) {
  PGconn* c = PQconnectdb(uri.c_str());
  std::string error;
  if (PQstatus(c) != CONNECTION_OK) {
    error = PQerrorMessage(c);
  } else {
    PGresult* r = PQexec(c, sql.c_str());
    if (PQresultStatus(r) != PGRES_COMMAND_OK) error = PQerrorMessage(c);
    PQclear(r);
  }
  PQfinish(c);
  if (!error.empty()) throw store::StoreError(sql + ": " + error);
}
#endif

/// The URL a test opens: a fresh SQLite file, or a fresh database on the PostgreSQL server.
inline std::string fresh_store_url(const std::string& test_url) {
  if (test_url == "sqlite:") return "sqlite:" + fresh_sqlite_path();
  const std::string url = resolve_test_url(test_url);
#ifdef UAVCOVER_STORE_HAS_POSTGRES
  std::string name = "uavcover_conformance_" + unique_name("db");
  for (char& ch : name)
    if (ch == '-') ch = '_';
  pg_admin(url, "CREATE DATABASE " + name);
  return pg_with_database(url, name);
#else
  return url;
#endif
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

/// Removes what fresh_store_url() made: the SQLite folder, or the PostgreSQL database.
inline void remove_test_store(const std::string& url) {
  if (url.starts_with("sqlite:/")) {
    const auto dir = std::filesystem::path(url.substr(7)).parent_path();
    if (!dir.filename().string().starts_with("uavcover-store-test-")) return;  // not one of ours
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
    return;
  }
#ifdef UAVCOVER_STORE_HAS_POSTGRES
  const std::string name = pg_database(url);
  if (!name.starts_with("uavcover_conformance_")) return;
  try {
    pg_admin(pg_with_database(url, "postgres"), "DROP DATABASE IF EXISTS " + name + " WITH (FORCE)");
  } catch (const store::StoreError&) {
    // a leftover database on a throwaway server is harmless
  }
#endif
}

}  // namespace uavcover::testing
