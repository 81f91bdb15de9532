// Writes a plan's folder as `uavcover plan` does (no evaluation, no images) and reads it back with the
// plan folder reader, as `uavcover export` and the server do.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

#include "io/plan_io.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/plan_outputs.hpp"

namespace uavcover::testing {

/// The plan read back from its folder, written to a fresh temporary folder named after `name` (removed
/// again either way); throws what the reader throws.
inline Plan write_and_read_plan_folder(const Plan& plan, const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  usecases::OutputOptions oo;
  oo.evaluate = false;
  oo.images = false;
  try {
    io::write_artifacts(dir, usecases::plan_outputs(plan, oo).artifacts);
    Plan loaded = io::load_plan_dir(dir);
    std::filesystem::remove_all(dir);
    return loaded;
  } catch (...) {
    std::filesystem::remove_all(dir);
    throw;
  }
}

}  // namespace uavcover::testing
