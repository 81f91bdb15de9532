#include "export/export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "export/support.hpp"
#include "terrain/terrain.hpp"
#include "uavcover/error.hpp"

namespace uavcover::exporting {

using namespace waypoints;  // the waypoint model the formats write
using nlohmann::json;

std::string wpl_text(const Plan& plan, std::size_t index, const ExportOptions& opt) {
  const auto items = items_of(plan, index, opt, opt.altitude);
  const Uav& uav = plan.mission.uavs.at(index);
  if (uav.speed_mps > limits::kArduPilotMaxSpeed)
    warn(opt, fmt::format("uav '{}': speed {} m/s is above ArduPilot's WPNAV_SPEED range (at most {} m/s)",
                          uav.id, uav.speed_mps, limits::kArduPilotMaxSpeed));
  const LonLat home = uav.start_resolved;
  std::string out = "QGC WPL 110\n";
  // row 0: home, absolute frame, ground level (0 m without a DEM: the home's elevation is not known then)
  out += fmt::format("0\t1\t0\t16\t0\t0\t0\t0\t{:.8f}\t{:.8f}\t{}\t1\n", home.lat, home.lon,
                     num(terrain::home_ground(plan.mission, index)));
  int seq = 1;
  for (const auto& it : items) {
    out += fmt::format("{}\t0\t{}\t{}\t{}\t{}\t{}\t{}\t{:.8f}\t{:.8f}\t{}\t{}\n", seq++, it.frame, it.command,
                       num(it.param1), num(it.param2), num(it.param3), num(it.param4), it.lat, it.lon,
                       num(it.alt), it.autocontinue ? 1 : 0);
  }
  return out;
}

}  // namespace uavcover::exporting
