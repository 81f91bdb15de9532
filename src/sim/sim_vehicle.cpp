// A simulated MAVLink vehicle's link (docs/simulate.md): its UDP or TCP endpoint, the mission
// protocol (ArduPilot's upload rules), the commands it answers, and its telemetry. Its flight is in
// dynamics.cpp, the fleet in fleet.cpp.
#include "sim/sim_vehicle.hpp"

#include <poll.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include "autopilot/rules.hpp"
#include "mavlink/stream.hpp"
#include "mavlink/udp.hpp"
#include "sim/sim_internal.hpp"
#include "uavcover/error.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::sim {

namespace mav = uavcover::mavlink;
namespace wp = uavcover::waypoints;
using namespace detail;

namespace {

// The mission protocol's acceptance: items by ArduPilot's upload rules (issue 34), so that what a real
// ArduPilot refuses (NaN in a command's params, an unknown command, a bad location) is refused here with
// the same MAV_MISSION_RESULT.
void accept_as_ardupilot(mav::VehicleOptions& o) { o.check_item = autopilot::ardupilot_item_result; }

std::unique_ptr<mav::Link> open_vehicle_link(const VehicleConfig& c) {
  if (c.tcp) return std::make_unique<mav::TcpListenLink>(c.listen, c.sysid, 1);
  return std::make_unique<mav::UdpLink>(c.listen, c.sysid, 1);
}

mav::VehicleOptions protocol_options(const VehicleConfig& c) {
  mav::VehicleOptions o;
  o.store_as_received = c.store_as_received;
  o.refuse_item = c.refuse_item;
  accept_as_ardupilot(o);
  // a fence that does not read as one (vertex counts, commands) is refused whole (issue 31)
  o.check_fence = [](const std::vector<mav::MissionItemInt>& items) -> std::uint8_t {
    autopilot::Fence f;
    return autopilot::read_fence(items, f) ? mav::kMissionInvalid : mav::kMissionAccepted;
  };
  return o;
}

}  // namespace

SimVehicle::SimVehicle(const VehicleConfig& config)
    : cfg_(config),
      link_(open_vehicle_link(config)),
      protocol_(*link_, protocol_options(config)),
      v_max_(config.v_max) {
  if (cfg_.loss > 0) link_->set_loss(cfg_.loss, cfg_.seed * 1000003ULL + cfg_.sysid);
  if (cfg_.home) {
    frame_.emplace(*cfg_.home);
    home_fixed_ = true;
  }
  // wind blowing *from* wind_from_deg (clockwise from north): its velocity points the other way
  const double to = (cfg_.wind_from_deg + 180.0) * std::numbers::pi / 180.0;
  wind_ = {cfg_.wind_mps * std::sin(to), cfg_.wind_mps * std::cos(to), 0.0};
}

void SimVehicle::set_peer(const mav::Endpoint& gcs) {
  if (auto* udp = dynamic_cast<mav::UdpLink*>(link_.get())) udp->set_peer(gcs);
}

void SimVehicle::service_link() {
  using namespace std::chrono_literals;
  while (auto r = link_->receive(0ms)) {
    if (st_.link_lost) continue;  // a lost link hears nothing
    handle(*r);
  }
  service_timeouts();
}

void SimVehicle::service_timeouts() {
  if (!st_.link_lost) protocol_.on_timeout();
}

void SimVehicle::handle(const mav::Received& r) {
  if (protocol_.handle(r)) {
    if (protocol_.mission_version() != mission_version_) {  // an upload completed (or a clear)
      mission_version_ = protocol_.mission_version();
      mission_ = protocol_.mission();
      load_mission();
    }
    if (protocol_.fence_version() != fence_version_) {  // a fence upload completed (or a clear)
      fence_version_ = protocol_.fence_version();
      (void)autopilot::read_fence(protocol_.fence(), fence_);  // checked on upload (check_fence)
      if (!fence_.empty()) status(mav::kSeverityInfo, "fence loaded");
    }
    return;
  }
  if (const auto* c = std::get_if<mav::CommandLong>(&r.message)) on_command(*c, r);
}

void SimVehicle::on_command(const mav::CommandLong& c, const mav::Received& r) {
  if (!for_me(c.target_system, cfg_.sysid)) return;
  std::uint8_t result = mav::kResultUnsupported;
  switch (c.command) {
    case mav::kCmdComponentArmDisarm:
      result = arm(c.param1 > 0.5F, std::lround(c.param2) == 21196);
      break;
    case mav::kCmdMissionStart:
      result = start_mission(static_cast<int>(c.param1), c.param2 > 0 ? static_cast<int>(c.param2) : -1);
      break;
    case mav::kCmdDoPauseContinue:
      result = pause(c.param1 < 0.5F);
      break;
    case mav::kCmdNavReturnToLaunch:
      result = return_to_launch();
      break;
    case mav::kCmdNavLand:
      result = land_here();
      break;
    case mav::kCmdDoSetMissionCurrent:
      result = set_current(static_cast<int>(std::lround(c.param1)));
      break;
    default:
      break;
  }
  mav::CommandAck ack;
  ack.command = c.command;
  ack.result = result;
  ack.target_system = r.header.sysid;
  ack.target_component = r.header.compid;
  send(ack);
}

void SimVehicle::set_mission(const std::vector<mav::MissionItemInt>& items) {
  mission_ = items;
  for (std::size_t i = 0; i < mission_.size(); ++i) mission_[i].seq = static_cast<std::uint16_t>(i);
  load_mission();
}

void SimVehicle::load_mission() {
  // Home from the mission when none was given and the vehicle has not flown yet.
  if (!home_fixed_ && !st_.airborne && !st_.armed && !mission_.empty()) {
    std::optional<std::size_t> from;
    if (is_home_item(0) && std::abs(mission_[0].x) <= 900'000'000 && std::abs(mission_[0].y) <= 1'800'000'000)
      from = 0;
    for (std::size_t i = 0; !from && i < mission_.size(); ++i)
      if (is_global(mission_[i].frame) && (mission_[i].x != 0 || mission_[i].y != 0) &&
          std::abs(mission_[i].x) <= 900'000'000 && std::abs(mission_[i].y) <= 1'800'000'000)
        from = i;
    if (from) frame_.emplace(LonLat{mission_[*from].y * 1e-7, mission_[*from].x * 1e-7});
  }
  st_.current_seq.reset();
  st_.mission_complete = false;
  paused_ = false;
  if (st_.mode == Mode::Mission) {  // a new mission in flight: hold until started again
    st_.mode = Mode::Hold;
    hold_ = st_.p;
    status(mav::kSeverityNotice, "new mission: holding");
  }
  send_current();
}

void SimVehicle::send(const mav::Message& m) {
  if (st_.link_lost || !link_->has_peer()) return;
  link_->send(m);
}

void SimVehicle::status(std::uint8_t severity, const std::string& text) {
  send(mav::StatusText::make(severity, text));
}

void SimVehicle::send_current() {
  mav::MissionCurrent c;
  c.seq = st_.current_seq.value_or(static_cast<std::uint16_t>(is_home_item(0) ? 1 : 0));
  c.total = static_cast<std::uint16_t>(std::min<std::size_t>(mission_.size(), 65534));
  if (mission_.empty()) {
    c.seq = 0;
    c.mission_state = kMissionStateNoMission;
  } else if (st_.mission_complete) {
    c.mission_state = kMissionStateComplete;
  } else if (!st_.current_seq) {
    c.mission_state = kMissionStateNotStarted;
  } else if (paused_) {
    c.mission_state = kMissionStatePaused;
  } else {
    c.mission_state = kMissionStateActive;
  }
  c.mission_mode = st_.mode == Mode::Mission ? 1 : 2;
  send(c);
}

mav::Heartbeat SimVehicle::heartbeat() const {
  mav::Heartbeat hb;
  hb.type = 2;                                               // MAV_TYPE_QUADROTOR
  hb.autopilot = cfg_.autopilot == Autopilot::Px4 ? 12 : 0;  // MAV_AUTOPILOT_PX4 / GENERIC
  hb.base_mode = kCustomModeEnabled | kStabilizeEnabled | kGuidedEnabled;
  if (st_.mode == Mode::Mission || st_.mode == Mode::Rtl || st_.mode == Mode::Land)
    hb.base_mode |= kAutoEnabled;
  if (st_.armed) hb.base_mode |= kSafetyArmed;
  if (cfg_.autopilot == Autopilot::Px4) {
    switch (st_.mode) {
      case Mode::Standby:
        hb.custom_mode = px4_mode(kPx4Auto, st_.armed ? kPx4Loiter : kPx4Ready);
        break;
      case Mode::Hold:
        hb.custom_mode = px4_mode(kPx4Auto, kPx4Loiter);
        break;
      case Mode::Mission:
        hb.custom_mode = px4_mode(kPx4Auto, kPx4Mission);
        break;
      case Mode::Rtl:
        hb.custom_mode = px4_mode(kPx4Auto, kPx4Rtl);
        break;
      case Mode::Land:
        hb.custom_mode = px4_mode(kPx4Auto, kPx4Land);
        break;
    }
  } else {
    hb.custom_mode = static_cast<std::uint32_t>(st_.mode);  // docs/simulate.md lists the values
  }
  if (st_.failed && cfg_.failure && cfg_.failure->kind == FailureKind::Land)
    hb.system_status = kEmergency;
  else if (st_.battery * 100.0 <= cfg_.low_battery_pct)
    hb.system_status = kCritical;
  else
    hb.system_status = st_.armed ? kActive : kStandby;
  hb.mavlink_version = 3;
  return hb;
}

void SimVehicle::telemetry(double dt) {
  (void)dt;
  if (st_.link_lost || !link_->has_peer()) return;
  const double t = st_.t;
  if (t + 1e-9 >= next_fast_) {
    next_fast_ = t + 1.0 / cfg_.telemetry_hz;
    mav::GlobalPositionInt g;
    g.time_boot_ms = static_cast<std::uint32_t>(std::llround(t * 1000.0));
    const LonLat ll = position_wgs84();
    g.lat = clamp_to<std::int32_t>(ll.lat * 1e7);
    g.lon = clamp_to<std::int32_t>(ll.lon * 1e7);
    g.alt = clamp_to<std::int32_t>((cfg_.home_amsl_m + st_.p.z) * 1000.0);
    g.relative_alt = clamp_to<std::int32_t>(st_.p.z * 1000.0);
    g.vx = clamp_to<std::int16_t>(st_.v.y * 100.0);   // north
    g.vy = clamp_to<std::int16_t>(st_.v.x * 100.0);   // east
    g.vz = clamp_to<std::int16_t>(-st_.v.z * 100.0);  // down
    if (std::hypot(st_.v.x, st_.v.y) > 0.2) {
      double hdg = std::atan2(st_.v.x, st_.v.y) * 180.0 / std::numbers::pi;
      if (hdg < 0) hdg += 360.0;
      heading_cdeg_ = static_cast<std::uint16_t>(std::lround(hdg * 100.0) % 36000);
    }
    g.hdg = heading_cdeg_;
    link_->send(g);
    send_current();
  }
  if (t + 1e-9 >= next_slow_) {
    next_slow_ = t + 1.0;
    link_->send(heartbeat());
    const double volts = kCells * (kCellsEmpty + (kCellsFull - kCellsEmpty) * st_.battery);
    const std::int16_t current_ca = st_.armed ? (st_.airborne ? 1500 : 200) : 0;
    const auto pct = static_cast<std::int8_t>(std::lround(st_.battery * 100.0));
    mav::SysStatus s;
    s.onboard_control_sensors_present = s.onboard_control_sensors_enabled = s.onboard_control_sensors_health =
        0x0000'002F;  // gyro, accel, mag, abs pressure, GPS
    s.load = 250;
    s.voltage_battery = clamp_to<std::uint16_t>(volts * 1000.0);
    s.current_battery = current_ca;
    s.drop_rate_comm = clamp_to<std::uint16_t>(cfg_.loss * 10000.0);
    s.battery_remaining = pct;
    link_->send(s);
    mav::BatteryStatus b;
    b.current_consumed = static_cast<std::int32_t>(std::lround(kBatteryCapacityMah * (1.0 - st_.battery)));
    b.energy_consumed = -1;
    b.temperature = INT16_MAX;
    b.voltages.fill(UINT16_MAX);
    for (int i = 0; i < kCells; ++i)
      b.voltages[static_cast<std::size_t>(i)] = clamp_to<std::uint16_t>(volts / kCells * 1000.0);
    b.current_battery = current_ca;
    b.id = 0;
    b.battery_function = 1;  // MAV_BATTERY_FUNCTION_ALL
    b.type = 1;              // MAV_BATTERY_TYPE_LIPO
    b.battery_remaining = pct;
    b.time_remaining = static_cast<std::int32_t>(std::lround(st_.battery * cfg_.endurance_min * 60.0));
    b.charge_state = st_.battery <= 0                                  ? 4
                     : st_.battery * 100.0 <= cfg_.low_battery_pct / 2 ? 3
                     : st_.battery * 100.0 <= cfg_.low_battery_pct     ? 2
                                                                       : 1;
    link_->send(b);
  }
}

}  // namespace uavcover::sim
