// Helpers for end-to-end tests that run the built `uavcover` binary.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "support/files.hpp"

namespace uavcover::testing {

struct RunResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

/// Runs `uavcover ARGS` through the shell; `env` ("NAME=value ...") is set for that run only.
inline RunResult run_cli(const std::string& args, const std::string& env = "") {
  const std::string cmd = env + (env.empty() ? "" : " ") + std::string(UAVCOVER_CLI) + " " + args + " 2>&1";
  RunResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

inline nlohmann::json read_json(const std::filesystem::path& p) { return nlohmann::json::parse(slurp(p)); }

/// A fresh, empty temporary folder for one test.
inline std::filesystem::path temp_dir(const std::string& name) {
  const auto d =
      std::filesystem::temp_directory_path() / ("uavcover-test-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

inline std::filesystem::path example(const std::string& name) {
  return std::filesystem::path(UAVCOVER_SOURCE_DIR) / "examples" / name;
}

}  // namespace uavcover::testing
