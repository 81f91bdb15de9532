// One thread per vehicle (docs/flights.md, "Runtime"): it owns the vehicle's UDP link, sends the GCS
// heartbeat, runs the UAV's queued actions (mission uploads, COMMAND_LONG resent until COMMAND_ACK)
// and turns telemetry into the UAV's state and waypoint statuses.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "autopilot/fence.hpp"
#include "evaluation/cost.hpp"
#include "flight/runtime.hpp"
#include "mavlink/mission_protocol.hpp"

namespace uavcover::flight {

using namespace detail;
using namespace std::chrono_literals;
namespace mav = uavcover::mavlink;

namespace {

constexpr std::uint8_t kArmedFlag = 128;
constexpr std::uint8_t kStateActive = 3, kStatePaused = 4, kStateComplete = 5;
constexpr std::size_t kBatch = 256;  // messages handled per lock

// Flight mode names from HEARTBEAT.custom_mode by autopilot (PX4 12, ArduPilot 3, else our simulator's
// generic numbering, docs/simulate.md).
std::string mode_name(std::uint8_t autopilot, std::uint32_t custom) {
  if (autopilot == 12) {
    const std::uint32_t main = (custom >> 16) & 0xFF, sub = (custom >> 24) & 0xFF;
    if (main == 4) {
      switch (sub) {
        case 1:
          return "standby";
        case 2:
          return "takeoff";
        case 3:
          return "hold";
        case 4:
          return "mission";
        case 5:
          return "rtl";
        case 6:
          return "land";
        default:
          return "auto";
      }
    }
    static const char* kMain[] = {"unknown", "manual", "altctl",   "posctl",
                                  "auto",    "acro",   "offboard", "stabilized"};
    return main < 8 ? kMain[main] : "unknown";
  }
  if (autopilot == 3) {
    switch (custom) {
      case 0:
        return "stabilize";
      case 3:
        return "mission";
      case 4:
        return "guided";
      case 5:
      case 16:
        return "hold";
      case 6:
        return "rtl";
      case 9:
        return "land";
      default:
        return "other";
    }
  }
  static const char* kGeneric[] = {"standby", "hold", "mission", "rtl", "land"};
  return custom < 5 ? kGeneric[custom] : "unknown";
}

std::string printable(std::string_view s) {
  std::string out;
  for (char c : s)
    out += (static_cast<unsigned char>(c) >= 32 && static_cast<unsigned char>(c) < 127) ? c : '?';
  return out;
}

}  // namespace

// ---- waypoint statuses ----

void Flight::Impl::set_waypoint(UavRt& u, MissionSpec& m, int waypoint, char status) {
  std::string* s = &u.waypoints;
  int at = waypoint;
  if (m.kind == "reassigned") {
    s = &m.waypoints;
    at = waypoint - m.first_waypoint;
  }
  if (at < 0 || at >= static_cast<int>(s->size())) return;
  char& c = (*s)[static_cast<std::size_t>(at)];
  const bool forward = (c == 'P' && (status == 'C' || status == 'R')) || (c == 'C' && status == 'R') ||
                       (status == 'S' && (c == 'P' || c == 'C'));
  if (!forward) return;
  c = status;
  nlohmann::json d{{"waypoint", waypoint}, {"status", std::string(1, status)}, {"mission", m.kind}};
  if (m.kind == "reassigned") d["reassignment"] = m.reassignment;
  record(u.binding.uav, "waypoint", std::move(d));
}

void Flight::Impl::on_current(UavRt& u, int item, std::uint8_t mission_state) {
  if (!airborne_phase(u.phase) || u.current >= u.missions.size()) return;
  MissionSpec& m = u.missions[u.current];
  if (m.state != "flying") return;
  const int n = static_cast<int>(m.items.size());
  if (mission_state == kStateComplete)
    item = n;  // every item done
  else if (mission_state != 0 && mission_state != kStateActive && mission_state != kStatePaused)
    return;
  if (item < 0 || item > n) return;
  // the autopilot moves on only after reaching an item: every coverage item before `item` is reached
  const int from = u.current_item.value_or(0);
  for (int j = std::max(0, from - 1); j < item; ++j)
    if (m.items[static_cast<std::size_t>(j)].waypoint >= 0)
      set_waypoint(u, m, m.items[static_cast<std::size_t>(j)].waypoint, 'R');
  if (item < n && m.items[static_cast<std::size_t>(item)].waypoint >= 0)
    set_waypoint(u, m, m.items[static_cast<std::size_t>(item)].waypoint, 'C');
  if (item >= from) u.current_item = item;
}

void Flight::Impl::on_reached(UavRt& u, int item) {
  if (!airborne_phase(u.phase) || u.current >= u.missions.size()) return;
  MissionSpec& m = u.missions[u.current];
  if (m.state != "flying" || item < 0 || item >= static_cast<int>(m.items.size())) return;
  for (int j = std::max(0, u.current_item.value_or(0) - 1); j <= item; ++j)
    if (m.items[static_cast<std::size_t>(j)].waypoint >= 0)
      set_waypoint(u, m, m.items[static_cast<std::size_t>(j)].waypoint, 'R');
  if (!u.current_item || *u.current_item < item) u.current_item = item;
}

char Flight::Impl::waypoint_status(const UavRt& u, const MissionSpec& m, int waypoint) const {
  const std::string& s = m.kind == "reassigned" ? m.waypoints : u.waypoints;
  const int at = m.kind == "reassigned" ? waypoint - m.first_waypoint : waypoint;
  return at >= 0 && at < static_cast<int>(s.size()) ? s[static_cast<std::size_t>(at)] : '\0';
}

bool Flight::Impl::coverage_done(const UavRt& u, const MissionSpec& m) const {
  return std::all_of(m.items.begin(), m.items.end(), [&](const waypoints::MissionItem& it) {
    const char c = it.waypoint < 0 ? 'R' : waypoint_status(u, m, it.waypoint);
    return c == 'R' || c == 'S' || c == '\0';
  });
}

int Flight::Impl::last_reached(const UavRt& u) const {
  const auto p = u.waypoints.find_last_of('R');
  return p == std::string::npos ? -1 : static_cast<int>(p);
}

bool Flight::Impl::has_work_left(const UavRt& u) const {
  if (u.waypoints.find_first_of("PC") != std::string::npos) return true;
  for (std::size_t k = u.current; k < u.missions.size(); ++k) {
    const auto& st = u.missions[k].state;
    if (st == "pending" || st == "uploading" || st == "ready" || st == "flying" || st == "interrupted")
      return true;
  }
  return false;
}

bool Flight::Impl::settled(const UavRt& u) const {
  if (u.phase == "done") return true;
  if (airborne_phase(u.phase) || u.phase == "uploading" || u.command_active || !u.actions.empty())
    return false;
  return !has_work_left(u);
}

// ---- telemetry ----

void Flight::Impl::on_heartbeat(UavRt& u, const mav::Heartbeat& hb) {
  if (hb.type == 6) return;  // another ground station
  const bool armed = (hb.base_mode & kArmedFlag) != 0;
  const std::string mode = mode_name(hb.autopilot, hb.custom_mode);
  if (armed != u.armed || mode != u.mode) {
    u.armed = armed;
    u.mode = mode;
    dirty = true;
  }
  // started from elsewhere (a remote control) or the start's ACK was lost
  if ((u.phase == "ready" || u.phase == "landed") && armed && mode == "mission" &&
      u.current < u.missions.size() && u.missions[u.current].state == "ready") {
    u.missions[u.current].state = "flying";
    set_phase(u, "flying");
  }
  if (u.phase == "flying" && (mode == "rtl" || mode == "land") && armed) set_phase(u, "returning");
  if (u.phase == "paused" && mode == "mission") set_phase(u, "flying");
  check_landed(u);
}

void Flight::Impl::check_landed(UavRt& u) {
  if (!airborne_phase(u.phase) || !u.airborne_seen || u.armed) return;
  u.current_item.reset();
  if (u.current >= u.missions.size()) {
    set_phase(u, has_work_left(u) ? "landed" : "done");
    return;
  }
  MissionSpec& m = u.missions[u.current];
  const bool done = coverage_done(u, m);
  m.state = done ? "done" : "interrupted";
  record(u.binding.uav, "sortie",
         {{"mission", u.current}, {"kind", m.kind}, {"index", m.index}, {"state", m.state}});
  if (done) {
    ++u.current;
    u.interrupted = false;
    set_phase(u, has_work_left(u) ? "landed" : "done");
  } else {
    u.interrupted = true;
    u.interrupted_since = Clock::now();
    set_phase(u, "landed");
  }
}

void Flight::Impl::on_position(UavRt& u, const mav::GlobalPositionInt& g) {
  if (std::abs(g.lat) > 900'000'000 || std::abs(g.lon) > 1'800'000'000) return;
  u.have_position = true;
  u.lat = g.lat * 1e-7;
  u.lon = g.lon * 1e-7;
  u.alt_m = g.relative_alt / 1000.0;
  u.speed_mps = std::hypot(g.vx, g.vy) / 100.0;
  if (g.hdg != UINT16_MAX) u.heading_deg = g.hdg / 100.0;
  const double mission_alt = plan.mission.altitude_m;
  u.band = u.alt_m < 1.0 ? "ground" : std::abs(u.alt_m - mission_alt) <= 5.0 ? "coverage" : "transit";
  if (u.alt_m > 1.0 && airborne_phase(u.phase)) u.airborne_seen = true;
  dirty = true;

  const std::array<double, 3> here{u.lon, u.lat, u.alt_m};
  const bool moved = u.trail.empty() || std::abs(u.trail.back()[2] - u.alt_m) >= 1.0 ||
                     bg::distance(frame.to_local(LonLat{u.trail.back()[0], u.trail.back()[1]}),
                                  frame.to_local(LonLat{u.lon, u.lat})) >= 1.0;
  if (moved) {
    u.trail.push_back(here);
    if (u.trail.size() > kTrailMax) u.trail.pop_front();
    if (++u.track_skip >= u.track_stride) {
      u.track_skip = 0;
      u.track.push_back(here);
      if (u.track.size() >= kTrackMax) {  // keep every other point, and add half as often
        std::size_t w = 0;
        for (std::size_t r = 0; r < u.track.size(); r += 2) u.track[w++] = u.track[r];
        u.track.resize(w);
        u.track_stride *= 2;
      }
    }
  }

  const auto now = Clock::now();
  if (now >= u.next_log) {
    u.next_log =
        now + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(config.log_period_s));
    nlohmann::json d{{"lon", u.lon},
                     {"lat", u.lat},
                     {"alt_m", u.alt_m},
                     {"speed_mps", u.speed_mps},
                     {"heading_deg", u.heading_deg},
                     {"armed", u.armed},
                     {"mode", u.mode},
                     {"band", u.band},
                     {"phase", u.phase}};
    d["battery_pct"] = u.battery_pct ? nlohmann::json(*u.battery_pct) : nlohmann::json();
    record(u.binding.uav, "telemetry", std::move(d));
  }

  // deviation: distance to the planned coverage leg being flown
  bool deviating = false;
  double dist = 0;
  if (u.band == "coverage" && u.phase == "flying" && u.current < u.missions.size() && u.current_item) {
    const MissionSpec& m = u.missions[u.current];
    const int j = *u.current_item;
    if (j > 0 && j < static_cast<int>(m.items.size()) && m.items[static_cast<std::size_t>(j)].waypoint >= 0 &&
        m.items[static_cast<std::size_t>(j - 1)].waypoint >= 0 && m.where[static_cast<std::size_t>(j)] &&
        m.where[static_cast<std::size_t>(j - 1)]) {
      const bg::model::segment<Point> leg(*m.where[static_cast<std::size_t>(j - 1)],
                                          *m.where[static_cast<std::size_t>(j)]);
      dist = bg::distance(frame.to_local(LonLat{u.lon, u.lat}), leg);
      deviating = dist > config.deviation_m;
    }
  }
  if (deviating != u.deviating) {
    u.deviating = deviating;
    set_alert("deviation", u.binding.uav, "", deviating, fmt::format("{:.0f} m from the planned leg", dist));
  }
}

// ---- commands on the link ----

bool Flight::Impl::command_effect_seen(const UavRt& u) const {
  const std::string& n = u.active.name;
  if (n == "arm") return u.armed;
  if (n == "mission_start") return u.armed && u.mode == "mission";
  if (n == "pause") return u.mode == "hold";
  if (n == "continue") return u.mode == "mission";
  if (n == "rtl") return u.mode == "rtl";
  if (n == "land") return u.mode == "land";
  return false;
}

void Flight::Impl::finish_command(UavRt& u, bool ok, const std::string& outcome) {
  u.command_active = false;
  record(u.binding.uav, "ack", {{"command", u.active.name}, {"ok", ok}, {"result", outcome}});
  if (!ok) {
    u.actions.clear();
    u.retry_after = Clock::now() + 2s;
    return;
  }
  const std::string& n = u.active.name;
  if (n == "mission_start" && u.current < u.missions.size()) {
    MissionSpec& m = u.missions[u.current];
    if (m.state == "ready") m.state = "flying";
    u.interrupted = false;
    set_phase(u, "flying");
    record(u.binding.uav, "sortie",
           {{"mission", u.current}, {"kind", m.kind}, {"index", m.index}, {"state", "flying"}});
  } else if (n == "pause" && u.phase == "flying") {
    set_phase(u, "paused");
  } else if (n == "continue" && u.phase == "paused") {
    set_phase(u, "flying");
  } else if ((n == "rtl" || n == "land") && airborne_phase(u.phase)) {
    set_phase(u, "returning");
  }
}

void Flight::Impl::vehicle_loop(std::size_t i, const std::stop_token& stop) {
  mav::Link& link = *links[i];
  Clock::time_point next_heartbeat = Clock::now();
  std::vector<mav::Received> batch;
  batch.reserve(kBatch);
  while (!stop.stop_requested()) {
    try {
      vehicle_step(i, link, next_heartbeat, batch, stop);
    } catch (const std::exception& e) {  // a socket error: said, and tried again
      {
        std::lock_guard lock(mutex);
        record(uavs[i].binding.uav, "alert",
               {{"kind", "link_error"}, {"active", true}, {"message", printable(e.what()).substr(0, 200)}});
      }
      std::this_thread::sleep_for(200ms);
    }
  }
  add_thread_cpu();
}

void Flight::Impl::vehicle_step(std::size_t i, mav::Link& link, Clock::time_point& next_heartbeat,
                                std::vector<mav::Received>& batch, const std::stop_token& stop) {
  const auto now = Clock::now();
  if (now >= next_heartbeat && link.has_peer()) {
    mav::Heartbeat hb;
    hb.type = 6;       // MAV_TYPE_GCS
    hb.autopilot = 8;  // MAV_AUTOPILOT_INVALID
    hb.system_status = 4;
    link.send(hb);
    next_heartbeat = now + 1s;
  }

  // the next action step
  std::optional<Action> upload;
  std::vector<mav::MissionItemInt> items, fence, rally;
  std::string phase_before;
  {
    std::lock_guard lock(mutex);
    UavRt& u = uavs[i];
    if (u.command_active) {
      if (u.ack_result) {
        const bool ok = *u.ack_result == mav::kResultAccepted;
        finish_command(u, ok, ok ? "accepted" : fmt::format("refused (MAV_RESULT {})", *u.ack_result));
      } else if (command_effect_seen(u)) {
        finish_command(u, true, "seen in telemetry");
      } else if (now >= u.resend_at) {
        if (u.tries_left-- > 0) {
          ++u.active.cmd.confirmation;
          link.send(u.active.cmd);
          u.resend_at = now + kCommandPeriod;
        } else {
          finish_command(u, false, "no COMMAND_ACK");
        }
      }
    } else if (!u.actions.empty() && link.has_peer()) {
      Action a = std::move(u.actions.front());
      u.actions.pop_front();
      if (a.kind == Action::Kind::Command) {
        a.cmd.target_system = u.binding.sysid;
        a.cmd.target_component = u.binding.compid;
        u.active = a;
        u.command_active = true;
        u.ack_result.reset();
        u.tries_left = config.command_retries;
        u.resend_at = now + kCommandPeriod;
        link.send(a.cmd);
        record(u.binding.uav, "command", {{"command", a.name}, {"mav_cmd", a.cmd.command}});
      } else if (a.mission < u.missions.size() &&
                 (u.missions[a.mission].state == "pending" || u.missions[a.mission].state == "ready")) {
        MissionSpec& m = u.missions[a.mission];
        std::optional<LonLat> home;
        if (u.binding.home_item) home = plan.mission.uavs[u.index].start_resolved;
        items = mav::to_mission_items(m.items, home);
        // the vehicle profile's capacity (issue 31): refused before anything is sent
        const VehicleProfile& profile = profile_of(u.index);
        const std::size_t capacity = mission_capacity(profile, plan.mission.max_mission_items);
        if (items.size() > capacity) {
          const std::string why =
              fmt::format("mission {} has {} items, more than {} stores ({}); nothing was sent", a.mission,
                          items.size(), profile.label, capacity);
          record(u.binding.uav, "ack",
                 {{"command", "upload"}, {"ok", false}, {"result", why}, {"mission", a.mission}});
          set_alert("capacity", u.binding.uav, "", true, why);
          u.actions.clear();
          return;
        }
        fence.clear();
        rally.clear();
        if (config.fence_rally && profile.fence)
          fence = mav::to_mission_items(
              autopilot::fence_items(plan, u.index, m.items, autopilot::kFenceMarginM), std::nullopt);
        if (config.fence_rally && profile.rally && !plan.rally.empty())
          rally = mav::to_mission_items(autopilot::rally_items(plan, u.index), std::nullopt);
        m.state = "uploading";
        phase_before = u.phase == "uploading" ? "idle" : u.phase;
        set_phase(u, "uploading");
        upload = a;
      }
    }
  }
  if (upload) {
    const UavRt& u0 = uavs[i];  // binding is never changed after construction
    mav::UploadOptions opt;
    opt.target_system = u0.binding.sysid;
    opt.target_component = u0.binding.compid;
    opt.stop = stop;  // DELETE /flights/{id} during an upload to a silent vehicle ends it at once
    mav::UploadResult res;
    int attempts = 0;
    while (attempts < kUploadAttempts && !stop.stop_requested()) {
      ++attempts;
      res = mav::upload_mission(link, items, opt);
      if (res.ok) break;
    }
    // then the geofence and the rally points (issue 31), each with its own mission type; a vehicle
    // that does not take them (MAV_MISSION_UNSUPPORTED) still flies the mission
    std::vector<std::pair<const char*, mav::UploadResult>> extra;
    for (const auto& [what, list, type] : {std::tuple{"fence", &fence, mav::kMissionTypeFence},
                                           std::tuple{"rally", &rally, mav::kMissionTypeRally}}) {
      if (!res.ok || list->empty() || stop.stop_requested()) continue;
      mav::UploadOptions o = opt;
      o.mission_type = type;
      o.retries = 1;  // a vehicle without fence support may stay silent
      extra.emplace_back(what, mav::upload_mission(link, *list, o));
    }
    std::lock_guard lock(mutex);
    for (const auto& [what, r] : extra)
      record(uavs[i].binding.uav, "ack",
             {{"command", what}, {"ok", r.ok}, {"result", r.ok ? "accepted" : r.error}, {"items", r.count}});
    UavRt& u = uavs[i];
    MissionSpec& m = u.missions[upload->mission];
    record(u.binding.uav, "ack",
           {{"command", "upload"},
            {"ok", res.ok},
            {"result", res.ok ? "accepted" : res.error},
            {"mission", upload->mission},
            {"items", res.count},
            {"attempts", attempts},
            {"count_sent", res.count_sent},
            {"items_sent", res.items_sent},
            {"timeouts", res.timeouts},
            {"clear_sent", res.clear_sent},
            {"cleared", res.cleared}});
    // A failed upload is followed by MISSION_CLEAR_ALL; unacknowledged, the vehicle may fly a fragment.
    if (res.partial_possible())
      set_alert(
          "partial_mission", u.binding.uav, "", true,
          "the upload failed and MISSION_CLEAR_ALL was not acknowledged: the vehicle may hold a partial "
          "mission; do not start it");
    else if (res.ok || res.cleared)
      set_alert("partial_mission", u.binding.uav, "", false,
                res.ok ? "a complete mission was uploaded" : "the vehicle's mission was cleared");
    u.last_heard = Clock::now();  // the upload read the link meanwhile
    if (res.ok) {
      m.state = "ready";
      u.airborne_seen = false;
      u.current_item.reset();
      set_phase(u, "ready");
    } else {
      m.state = "pending";
      u.actions.clear();
      u.retry_after = Clock::now() + 2s;
      set_phase(u, phase_before);
    }
    return;
  }

  // telemetry
  batch.clear();
  if (auto r = link.receive(20ms)) {
    batch.push_back(*r);
    while (batch.size() < kBatch)
      if (auto more = link.receive(0ms))
        batch.push_back(*more);
      else
        break;
  }
  std::lock_guard lock(mutex);
  UavRt& u = uavs[i];
  u.rx = link.stats().received;
  u.tx = link.stats().sent;
  for (const auto& r : batch) {
    if (r.header.sysid != u.binding.sysid || (u.binding.compid != 0 && r.header.compid != u.binding.compid))
      continue;  // another system or component: not ours
    u.last_heard = Clock::now();
    u.last_heard_ms = now_ms();
    if (u.link_state != "ok") {
      if (u.link_state == "lost") set_alert("link_lost", u.binding.uav, "", false, "link back");
      u.link_state = "ok";
      u.lost_since.reset();
      dirty = true;
    }
    std::visit(
        [&](const auto& msg) {
          using T = std::decay_t<decltype(msg)>;
          if constexpr (std::is_same_v<T, mav::Heartbeat>) {
            on_heartbeat(u, msg);
          } else if constexpr (std::is_same_v<T, mav::GlobalPositionInt>) {
            on_position(u, msg);
          } else if constexpr (std::is_same_v<T, mav::MissionCurrent>) {
            on_current(u, static_cast<int>(msg.seq) - (u.binding.home_item ? 1 : 0), msg.mission_state);
          } else if constexpr (std::is_same_v<T, mav::MissionItemReached>) {
            on_reached(u, static_cast<int>(msg.seq) - (u.binding.home_item ? 1 : 0));
          } else if constexpr (std::is_same_v<T, mav::SysStatus> || std::is_same_v<T, mav::BatteryStatus>) {
            if (msg.battery_remaining >= 0 && msg.battery_remaining <= 100 &&
                u.battery_pct != static_cast<double>(msg.battery_remaining)) {
              u.battery_pct = msg.battery_remaining;
              dirty = true;
            }
          } else if constexpr (std::is_same_v<T, mav::StatusText>) {
            record(u.binding.uav, "statustext", {{"severity", msg.severity}, {"text", printable(msg.str())}});
          } else if constexpr (std::is_same_v<T, mav::CommandAck>) {
            if (u.command_active && msg.command == u.active.cmd.command && msg.result != 5)  // 5: in progress
              u.ack_result = msg.result;
          }
        },
        r.message);
  }
}

}  // namespace uavcover::flight
