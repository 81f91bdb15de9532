// Writing a plan folder that a stop can still undo (`uavcover plan`).
#pragma once

#include <filesystem>
#include <vector>

#include "uavcover/artifact.hpp"
#include "uavcover/context.hpp"

namespace uavcover::io {

/// io::write_artifacts() (a staging folder moved into place whole; a new `dir` by one rename, so that a
/// stop or a failure leaves no `dir` at all) that also stops: a stop request before the files are moved
/// into place (checked between files; the test hook's stage "storing" holds there,
/// engine/test_hold.hpp) throws Cancelled and leaves nothing behind.
std::vector<std::filesystem::path> write_artifacts(const std::filesystem::path& dir,
                                                   const Artifacts& artifacts, const Context& ctx);

}  // namespace uavcover::io
