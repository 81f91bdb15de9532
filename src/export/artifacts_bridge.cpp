// TEMPORARY bridge until the exporters return bytes themselves: export into a scratch folder and
// read the files back as artifacts.
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "export/export.hpp"

namespace uavcover::exporting {

Artifacts export_artifacts(const Plan& plan, const std::vector<std::string>& formats,
                           const ExportOptions& opt) {
  namespace fs = std::filesystem;
  const fs::path scratch = fs::temp_directory_path() / ("uavcover-export-" + std::to_string(::getpid()));
  fs::remove_all(scratch);
  Artifacts out;
  try {
    for (const auto& p : export_plan(plan, formats, scratch, opt)) {
      std::ifstream in(p, std::ios::binary);
      std::ostringstream ss;
      ss << in.rdbuf();
      out.push_back({fs::relative(p, scratch).generic_string(), "application/octet-stream", ss.str()});
    }
  } catch (...) {
    fs::remove_all(scratch);
    throw;
  }
  fs::remove_all(scratch);
  return out;
}

}  // namespace uavcover::exporting
