// File fixtures shared by the tests.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "uavcover/mission.hpp"

namespace uavcover::testing {

/// A fresh temporary folder, removed with the object.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& tag)
      : path(std::filesystem::temp_directory_path() /
             ("uavcover_" + tag + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Text of a region of the paper's evaluation, e.g. roi_text("roi09.json").
inline std::string roi_text(const std::string& file) {
  return slurp(std::filesystem::path(UAVCOVER_BENCH_DATA) / "apostolidis2022" / file);
}

/// The mission with its first UAV copied `n` times: ids uav-1.., equal shares, seeded random starts.
inline Mission with_equal_uavs(Mission m, int n) {
  const Uav base = m.uavs.at(0);
  m.uavs.clear();
  for (int i = 0; i < n; ++i) {
    Uav u = base;
    u.id = "uav-" + std::to_string(i + 1);
    u.share = 1.0 / n;
    u.start.reset();
    m.uavs.push_back(u);
  }
  return m;
}

}  // namespace uavcover::testing
