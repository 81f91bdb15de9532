// Outputs as bytes: renderers and exporters return artifacts; only src/io/ writes them to disk (the
// CLI's plan folder) and the server stores and serves the same bytes from its database.
#pragma once

#include <string>
#include <vector>

namespace uavcover {

struct Artifact {
  std::string name;        ///< relative path, '/'-separated, e.g. "plan.png" or "export/uav1.plan"
  std::string media_type;  ///< e.g. "image/png", "application/json", "application/vnd.google-earth.kmz"
  std::string bytes;
};

using Artifacts = std::vector<Artifact>;

}  // namespace uavcover
