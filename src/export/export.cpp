#include "export/export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <map>

#include "export/checks.hpp"
#include "export/formats.hpp"
#include "sorties/sorties.hpp"
#include "uavcover/error.hpp"

namespace uavcover::exporting {

using namespace waypoints;  // the waypoint model the formats write
using nlohmann::json;

bool idle(const UavPlan& uav) {
  return std::none_of(uav.parts.begin(), uav.parts.end(),
                      [](const PathPart& p) { return p.kind == PartKind::Coverage && !p.wgs84.empty(); });
}

Artifacts export_artifacts(const Plan& plan, const std::vector<std::string>& formats,
                           const ExportOptions& options) {
  const std::vector<std::string> wanted = parse_formats(formats);
  // warnings go to the caller only when the whole export succeeds
  std::vector<std::string> warnings;
  ExportOptions opt = options;
  opt.warnings = &warnings;
  const CheckedPlan checked = check_plan(plan, opt, warnings);

  Artifacts out;
  for (const auto& name : wanted) {
    const Format& f = *find_format(name);
    const bool split = opt.per_sortie && f.per_sortie;
    for (const std::size_t i : checked.flown) {
      const std::string& id = plan.uavs[i].id;
      if (!split) {
        f.write(plan, i, opt, "export/" + id, out);
        continue;
      }
      for (const auto& s : checked.sorties.at(i))
        f.write(sorties::sortie_plan(plan, i, s), i, opt, fmt::format("export/{}.s{}", id, s.index + 1), out);
    }
  }
  // ids are kept unchanged, so two ids can still name one file ("a.wpml" kml/kmz vs "a" dji)
  std::map<std::string, std::size_t> seen;
  for (std::size_t k = 0; k < out.size(); ++k) {
    const auto [it, fresh] = seen.emplace(out[k].name, k);
    if (!fresh)
      throw InputError("uavs", fmt::format("two exports would both be written to {}: rename one of the UAVs",
                                           out[k].name));
  }
  if (options.warnings != nullptr)
    options.warnings->insert(options.warnings->end(), warnings.begin(), warnings.end());
  return out;
}

}  // namespace uavcover::exporting
