#include "export/export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "export/support.hpp"

namespace uavcover::exporting {

using namespace waypoints;  // the waypoint model the formats write
using nlohmann::json;

std::string waypoints_csv(const Plan& plan, std::size_t index, const ExportOptions& opt) {
  const auto items = items_of(plan, index, opt, opt.altitude);
  std::string out = "seq,role,command,frame,lat,lon,alt_m,param1,param2,param3,param4\n";
  int seq = 1;
  for (const auto& it : items)
    out += fmt::format("{},{},{},{},{:.9f},{:.9f},{},{},{},{},{}\n", seq++, it.role, it.command, it.frame,
                       it.lat, it.lon, num(it.alt), num(it.param1), num(it.param2), num(it.param3),
                       num(it.param4));
  return out;
}

}  // namespace uavcover::exporting
