// FlightRequest and Command bodies (docs/flights.md): parsed and validated with the offending field named.
#include <fmt/format.h>

#include <cmath>
#include <set>

#include "flight/flight.hpp"
#include "uavcover/error.hpp"

namespace uavcover::flight {

namespace {

using nlohmann::json;

constexpr std::size_t kMaxName = 200;

const json* member(const json& obj, const char* key) {
  const auto it = obj.find(key);
  return it == obj.end() || it->is_null() ? nullptr : &*it;
}

double number(const json& obj, const char* key, double fallback, double lo, double hi,
              const std::string& path) {
  const json* v = member(obj, key);
  if (!v) return fallback;
  const std::string field = path + key;
  if (!v->is_number()) throw InputError(field, "must be a number");
  const double x = v->get<double>();
  if (!std::isfinite(x) || x < lo || x > hi)
    throw InputError(field, fmt::format("must be in [{}, {}]", lo, hi));
  return x;
}

long long integer(const json& obj, const char* key, long long fallback, long long lo, long long hi,
                  const std::string& path) {
  const json* v = member(obj, key);
  if (!v) return fallback;
  const std::string field = path + key;
  if (!v->is_number_integer()) throw InputError(field, "must be an integer");
  const long long x =
      v->is_number_unsigned() && v->get<unsigned long long>() > static_cast<unsigned long long>(hi)
          ? hi + 1
          : v->get<long long>();
  if (x < lo || x > hi) throw InputError(field, fmt::format("must be an integer in [{}, {}]", lo, hi));
  return x;
}

bool boolean(const json& obj, const char* key, bool fallback, const std::string& path) {
  const json* v = member(obj, key);
  if (!v) return fallback;
  if (!v->is_boolean()) throw InputError(path + key, "must be true or false");
  return v->get<bool>();
}

std::string text(const json& obj, const char* key, const std::string& path) {
  const json* v = member(obj, key);
  if (!v || !v->is_string()) throw InputError(path + key, "must be a string");
  auto s = v->get<std::string>();
  if (s.empty() || s.size() > kMaxName)
    throw InputError(path + key, fmt::format("must have 1..{} characters", kMaxName));
  return s;
}

/// "home" or "air" (FlightConfig::reassign_from).
std::string reassign_from(const json& obj, const std::string& path) {
  const json* v = member(obj, "reassign_from");
  if (!v || !v->is_string() || (*v != "home" && *v != "air"))
    throw InputError(path + "reassign_from",
                     "must be \"home\" (take-off points) or \"air\" (live positions)");
  return v->get<std::string>();
}

void known_keys(const json& obj, const std::set<std::string>& keys, const std::string& path) {
  for (const auto& [k, v] : obj.items())
    if (!keys.contains(k))
      throw InputError(path + (k.size() > kMaxName ? k.substr(0, kMaxName) : k), "unknown field");
}

}  // namespace

mavlink::LinkAddress link_address(const VehicleBinding& b) {
  mavlink::LinkAddress a;
  a.transport = b.transport;
  if (b.listen && b.transport == mavlink::Transport::Udp) a.transport = mavlink::Transport::UdpListen;
  if (b.listen && b.transport == mavlink::Transport::Tcp) a.transport = mavlink::Transport::TcpListen;
  a.endpoint = b.endpoint;
  a.device = b.device;
  a.baud = b.baud;
  return a;
}

std::string endpoint_text(const VehicleBinding& b) {
  mavlink::LinkAddress a = link_address(b);
  // "listen" says the direction: the endpoint keeps the plain scheme (as it always did for UDP)
  if (a.transport == mavlink::Transport::UdpListen) a.transport = mavlink::Transport::Udp;
  if (a.transport == mavlink::Transport::TcpListen) a.transport = mavlink::Transport::Tcp;
  return a.text();
}

FlightConfig parse_config(const json& body, const Plan& plan) {
  if (!body.is_object()) throw InputError("", "the flight request must be a JSON object");
  known_keys(body,
             {"vehicles", "simulate", "link_timeout_s", "reassign_after_s", "auto_reassign",
              "auto_next_sortie", "separation_m", "deviation_m", "low_battery_pct", "log_period_s",
              "acceptance_radius_m", "command_retries", "fence_rally", "waypoint_retries",
              "waypoint_timeout_factor", "waypoint_timeout_floor_s", "reassign_from"},
             "");
  FlightConfig c;
  const json* vehicles = member(body, "vehicles");
  if (!vehicles || !vehicles->is_array()) throw InputError("vehicles", "must be an array of vehicles");
  if (vehicles->empty()) throw InputError("vehicles", "needs at least one vehicle");
  if (vehicles->size() > plan.uavs.size())
    throw InputError(
        "vehicles", fmt::format("the plan has {} UAVs, got {} vehicles", plan.uavs.size(), vehicles->size()));
  std::set<std::string> seen;
  for (std::size_t i = 0; i < vehicles->size(); ++i) {
    const json& v = (*vehicles)[i];
    const std::string path = fmt::format("vehicles[{}].", i);
    if (!v.is_object()) throw InputError(fmt::format("vehicles[{}]", i), "must be an object");
    known_keys(v, {"uav", "endpoint", "listen", "sysid", "compid", "home_item"}, path);
    VehicleBinding b;
    b.uav = text(v, "uav", path);
    bool found = false;
    for (const auto& u : plan.uavs) found = found || u.id == b.uav;
    if (!found) throw InputError(path + "uav", fmt::format("the plan has no UAV \"{}\"", b.uav));
    if (!seen.insert(b.uav).second)
      throw InputError(path + "uav", fmt::format("UAV \"{}\" is bound twice", b.uav));
    const mavlink::LinkAddress address =
        mavlink::parse_link_address(text(v, "endpoint", path), path + "endpoint");
    if (address.transport == mavlink::Transport::Serial && !address.device.starts_with("/dev/"))
      throw InputError(path + "endpoint",
                       "a serial device must be under /dev/, got '" + address.device + "'");
    b.listen = boolean(v, "listen", address.listens(), path);
    if (address.listens() && !b.listen)
      throw InputError(path + "listen", "is false, but the endpoint " + address.text() + " listens");
    if (address.transport == mavlink::Transport::Serial && b.listen)
      throw InputError(path + "listen", "a serial endpoint neither listens nor connects: leave listen out");
    b.transport = address.transport == mavlink::Transport::UdpListen   ? mavlink::Transport::Udp
                  : address.transport == mavlink::Transport::TcpListen ? mavlink::Transport::Tcp
                                                                       : address.transport;
    b.endpoint = address.endpoint;
    b.device = address.device;
    b.baud = address.baud;
    b.sysid = static_cast<std::uint8_t>(integer(v, "sysid", 1, 1, 255, path));
    b.compid = static_cast<std::uint8_t>(integer(v, "compid", 1, 0, 255, path));
    b.home_item = boolean(v, "home_item", false, path);
    c.vehicles.push_back(std::move(b));
  }
  c.link_timeout_s = number(body, "link_timeout_s", c.link_timeout_s, 0.1, 600, "");
  c.reassign_after_s = number(body, "reassign_after_s", c.reassign_after_s, 0, 3600, "");
  c.auto_reassign = boolean(body, "auto_reassign", c.auto_reassign, "");
  c.auto_next_sortie = boolean(body, "auto_next_sortie", c.auto_next_sortie, "");
  c.separation_m = number(body, "separation_m", c.separation_m, 0, 1000, "");
  c.deviation_m = number(body, "deviation_m", c.deviation_m, 0.1, 10000, "");
  c.low_battery_pct = number(body, "low_battery_pct", c.low_battery_pct, 0, 100, "");
  c.log_period_s = number(body, "log_period_s", c.log_period_s, 0.05, 3600, "");
  c.acceptance_radius_m = number(body, "acceptance_radius_m", c.acceptance_radius_m, 0.1, 100, "");
  c.command_retries = static_cast<int>(integer(body, "command_retries", c.command_retries, 0, 20, ""));
  c.fence_rally = boolean(body, "fence_rally", c.fence_rally, "");
  c.waypoint_retries = static_cast<int>(integer(body, "waypoint_retries", c.waypoint_retries, 0, 10, ""));
  c.waypoint_timeout_factor = number(body, "waypoint_timeout_factor", c.waypoint_timeout_factor, 1, 100, "");
  c.waypoint_timeout_floor_s =
      number(body, "waypoint_timeout_floor_s", c.waypoint_timeout_floor_s, 1, 3600, "");
  if (member(body, "reassign_from")) c.reassign_from = reassign_from(body, "");
  return c;
}

json config_json(const FlightConfig& c) {
  json vehicles = json::array();
  for (const auto& v : c.vehicles)
    vehicles.push_back({{"uav", v.uav},
                        {"endpoint", endpoint_text(v)},
                        {"listen", v.listen},
                        {"sysid", v.sysid},
                        {"compid", v.compid},
                        {"home_item", v.home_item}});
  return {{"vehicles", vehicles},
          {"link_timeout_s", c.link_timeout_s},
          {"reassign_after_s", c.reassign_after_s},
          {"auto_reassign", c.auto_reassign},
          {"auto_next_sortie", c.auto_next_sortie},
          {"separation_m", c.separation_m},
          {"deviation_m", c.deviation_m},
          {"low_battery_pct", c.low_battery_pct},
          {"log_period_s", c.log_period_s},
          {"acceptance_radius_m", c.acceptance_radius_m},
          {"command_retries", c.command_retries},
          {"fence_rally", c.fence_rally},
          {"waypoint_retries", c.waypoint_retries},
          {"waypoint_timeout_factor", c.waypoint_timeout_factor},
          {"waypoint_timeout_floor_s", c.waypoint_timeout_floor_s},
          {"reassign_from", c.reassign_from}};
}

Command parse_command(const json& body) {
  static const std::set<std::string> kCommands{"upload",      "start",    "pause",  "continue",
                                               "rtl",         "land",     "abort",  "resume",
                                               "next_sortie", "reassign", "decline"};
  if (!body.is_object()) throw InputError("", "the command must be a JSON object");
  known_keys(body, {"command", "uav", "reassignment", "reassign_from"}, "");
  Command c;
  const json* cmd = member(body, "command");
  if (!cmd || !cmd->is_string() || !kCommands.contains(cmd->get<std::string>()))
    throw InputError("command",
                     "must be one of upload, start, pause, continue, rtl, land, abort, resume, next_sortie, "
                     "reassign, decline");
  c.command = cmd->get<std::string>();
  if (member(body, "uav")) c.uav = text(body, "uav", "");
  if (member(body, "reassignment"))
    c.reassignment = static_cast<int>(integer(body, "reassignment", 0, 1, 1'000'000, ""));
  if (member(body, "reassign_from")) {
    if (c.command != "reassign") throw InputError("reassign_from", "goes only with the command reassign");
    c.reassign_from = reassign_from(body, "");
  }
  return c;
}

}  // namespace uavcover::flight
