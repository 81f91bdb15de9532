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

struct CheckedExport::State {
  const Plan& plan;
  ExportOptions opt;  ///< altitudes resolved by the checks
  std::vector<std::string> warnings;
  CheckedPlan checked;
};

CheckedExport::CheckedExport(const Plan& plan, const ExportOptions& opt)
    : s_(std::make_unique<State>(State{plan, opt, {}, {}})) {
  s_->opt.warnings = &s_->warnings;
  s_->checked = check_plan(plan, s_->opt, s_->warnings);
  s_->opt.warnings = nullptr;
}

CheckedExport::~CheckedExport() = default;
CheckedExport::CheckedExport(CheckedExport&&) noexcept = default;

const std::vector<std::string>& CheckedExport::warnings() const { return s_->warnings; }

Artifacts CheckedExport::write(const std::vector<std::string>& formats,
                               std::vector<std::string>* warnings) const {
  const std::vector<std::string> wanted = parse_formats(formats);
  const Plan& plan = s_->plan;
  const CheckedPlan& checked = s_->checked;
  // the writers' warnings go to the caller only when the whole write succeeds
  std::vector<std::string> written;
  ExportOptions opt = s_->opt;
  opt.warnings = &written;
  Artifacts out;
  for (const auto& name : wanted) {
    const Format& f = *find_format(name);
    // the terrain frame (issue 31) is MAVLink's: formats that write heights of their own have none
    if (opt.altitude.terrain_frame && name != "qgc" && name != "wpl" && name != "csv" && name != "geojson")
      throw InputError("terrain_frame",
                       fmt::format("the {} format has no terrain frame (MAV_FRAME_GLOBAL_TERRAIN_ALT "
                                   "is for the .plan, .waypoints and CSV); export it without it",
                                   name));
    const bool split = (opt.per_sortie || opt.split_capacity) && f.per_sortie;
    for (const std::size_t i : checked.flown) {
      const std::string& id = plan.uavs[i].id;
      if (!split) {
        opt.items = &checked.items.at(i);
        f.write(plan, i, opt, "export/" + id, out);
        continue;
      }
      const auto& list = checked.sorties.at(i);
      for (std::size_t k = 0; k < list.size(); ++k) {
        opt.items = &checked.sortie_items.at({i, k});
        f.write(sorties::sortie_plan(plan, i, list[k]), i, opt,
                fmt::format("export/{}.s{}", id, list[k].index + 1), out);
      }
    }
  }
  opt.items = nullptr;
  // ids are kept unchanged, so two ids can still name one file ("a.wpml" kml/kmz vs "a" dji)
  std::map<std::string, std::size_t> seen;
  for (std::size_t k = 0; k < out.size(); ++k) {
    const auto [it, fresh] = seen.emplace(out[k].name, k);
    if (!fresh)
      throw InputError("uavs", fmt::format("two exports would both be written to {}: rename one of the UAVs",
                                           out[k].name));
  }
  if (warnings != nullptr) warnings->insert(warnings->end(), written.begin(), written.end());
  return out;
}

Artifacts export_artifacts(const Plan& plan, const std::vector<std::string>& formats,
                           const ExportOptions& options) {
  parse_formats(formats);  // an unknown format refuses before the checks run
  const CheckedExport checked(plan, options);
  std::vector<std::string> warnings = checked.warnings();
  Artifacts out = checked.write(formats, &warnings);
  // warnings go to the caller only when the whole export succeeds
  if (options.warnings != nullptr)
    options.warnings->insert(options.warnings->end(), warnings.begin(), warnings.end());
  return out;
}

}  // namespace uavcover::exporting
