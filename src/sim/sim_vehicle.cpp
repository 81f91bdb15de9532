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
#include "uavcover/error.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::sim {

namespace mav = uavcover::mavlink;
namespace wp = uavcover::waypoints;

namespace {

constexpr double kGround = 0.05;  // metres: at or below this the vehicle is on the ground
constexpr double kBatteryCapacityMah = 5000.0;
constexpr double kSwapRadiusM = 5.0;  // arming this close to home swaps a used battery
constexpr double kCellsFull = 4.2, kCellsEmpty = 3.3;
constexpr int kCells = 4;

// PX4 custom mode: main mode in bits 16..23, sub mode in bits 24..31 (px4_custom_mode.h).
constexpr std::uint32_t px4_mode(std::uint32_t main, std::uint32_t sub) { return (main << 16) | (sub << 24); }
constexpr std::uint32_t kPx4Auto = 4;
constexpr std::uint32_t kPx4Ready = 1, kPx4Loiter = 3, kPx4Mission = 4, kPx4Rtl = 5, kPx4Land = 6;

// MAV_MODE_FLAG
constexpr std::uint8_t kCustomModeEnabled = 1, kAutoEnabled = 4, kGuidedEnabled = 8, kStabilizeEnabled = 16,
                       kSafetyArmed = 128;
// MAV_STATE
constexpr std::uint8_t kStandby = 3, kActive = 4, kCritical = 5, kEmergency = 6;

double norm(const Vec3& a) { return std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z); }
Vec3 sub(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }

bool is_global(std::uint8_t frame) {
  return frame == 0 || frame == 3 || frame == 5 || frame == 6 || frame == 10 || frame == 11;
}
bool is_amsl(std::uint8_t frame) { return frame == 0 || frame == 5; }

// The navigation commands flown (the others are done at once).
bool is_nav(std::uint16_t command) {
  return command == wp::kNavWaypoint || command == wp::kNavTakeoff || command == wp::kNavLand ||
         command == wp::kNavReturnToLaunch || (command >= 17 && command <= 19) || command == 82;
}

bool for_me(std::uint8_t target, std::uint8_t sysid) { return target == 0 || target == sysid; }

template <typename T>
T clamp_to(double v) {
  const double lo = static_cast<double>(std::numeric_limits<T>::min());
  const double hi = static_cast<double>(std::numeric_limits<T>::max());
  return static_cast<T>(std::llround(std::clamp(v, lo, hi)));
}

// The mission protocol's acceptance: items by ArduPilot's upload rules (issue 34), so that what a real
// ArduPilot refuses (NaN in a command's params, an unknown command, a bad location) is refused here with
// the same MAV_MISSION_RESULT.
void accept_as_ardupilot(mav::VehicleOptions& o) { o.check_item = autopilot::ardupilot_item_result; }

}  // namespace

namespace {

std::unique_ptr<mav::Link> open_vehicle_link(const VehicleConfig& c) {
  if (c.tcp) return std::make_unique<mav::TcpListenLink>(c.listen, c.sysid, 1);
  return std::make_unique<mav::UdpLink>(c.listen, c.sysid, 1);
}

mav::VehicleOptions protocol_options(const VehicleConfig& c) {
  mav::VehicleOptions o;
  o.store_as_received = c.store_as_received;
  o.refuse_item = c.refuse_item;
  accept_as_ardupilot(o);
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

LonLat SimVehicle::position_wgs84() const {
  if (!frame_) return {};
  return frame_->to_wgs84(Point(st_.p.x, st_.p.y));
}

Vec3 SimVehicle::to_local(std::int32_t lat_e7, std::int32_t lon_e7) const {
  if (!frame_) return {};
  const Point q = frame_->to_local(LonLat{lon_e7 * 1e-7, lat_e7 * 1e-7});
  return {q.x(), q.y(), 0.0};
}

double SimVehicle::item_alt(const mav::MissionItemInt& item) const {
  return is_amsl(item.frame) ? static_cast<double>(item.z) - cfg_.home_amsl_m : static_cast<double>(item.z);
}

bool SimVehicle::is_home_item(std::size_t seq) const {
  // ArduPilot's convention (and `uavcover upload` without --no-home): item 0 is the home position.
  return seq == 0 && mission_.size() > 1 && mission_[0].command == wp::kNavWaypoint &&
         mission_[0].frame == 0 && mission_[0].z == 0.0F;
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

std::uint8_t SimVehicle::arm(bool on, bool force) {
  if (on) {
    if (st_.armed) return mav::kResultAccepted;
    // on the ground at home with a used battery: the operator swapped it (the next sortie starts full)
    if (!st_.airborne && std::hypot(st_.p.x, st_.p.y) <= kSwapRadiusM && st_.battery < 1.0) {
      st_.battery = 1.0;
      low_battery_sent_ = false;
      status(mav::kSeverityInfo, "battery swapped");
    }
    if (st_.battery <= 0) return mav::kResultDenied;
    st_.armed = true;
    st_.mode = Mode::Standby;
    status(mav::kSeverityInfo, "armed");
    return mav::kResultAccepted;
  }
  if (!st_.armed) return mav::kResultAccepted;
  if (st_.airborne && !force) return mav::kResultDenied;
  if (st_.airborne) {  // forced disarm in the air: it falls (modelled as an instant touchdown)
    status(mav::kSeverityEmergency, "disarmed in flight");
  }
  touchdown();
  return mav::kResultAccepted;
}

std::uint8_t SimVehicle::start_mission(int first, int last) {
  if (mission_.empty() || !st_.armed || st_.battery <= 0) return mav::kResultDenied;
  if (st_.mode == Mode::Mission) return mav::kResultAccepted;  // a repeated command changes nothing
  const int n = static_cast<int>(mission_.size());
  first = std::max(first, is_home_item(0) ? 1 : 0);
  if (last < 0 || last >= n) last = n - 1;
  if (first > last) return mav::kResultDenied;
  first_item_ = static_cast<std::size_t>(first);
  last_item_ = static_cast<std::size_t>(last);
  // planned path length from here (for failure injection at a fraction of the mission)
  st_.planned_m = 0;
  Vec3 at = st_.p;
  for (std::size_t i = first_item_; i <= last_item_; ++i)
    for (const Target& t : item_targets(mission_[i], at)) {
      st_.planned_m += norm(sub(t.p, at));
      at = t.p;
    }
  st_.flown_m = 0;
  st_.mission_complete = false;
  paused_ = false;
  st_.mode = Mode::Mission;
  status(mav::kSeverityInfo, "mission started");
  begin_item(first_item_);
  return mav::kResultAccepted;
}

std::uint8_t SimVehicle::pause(bool on) {
  if (on) {
    if (paused_) return mav::kResultAccepted;
    if (st_.mode != Mode::Mission) return mav::kResultDenied;
    paused_ = true;
    st_.mode = Mode::Hold;
    hold_ = st_.p;
    status(mav::kSeverityInfo, "mission paused");
  } else {
    if (st_.mode == Mode::Mission) return mav::kResultAccepted;
    if (!paused_ || st_.mode != Mode::Hold) return mav::kResultDenied;
    paused_ = false;
    st_.mode = Mode::Mission;
    status(mav::kSeverityInfo, "mission continued");
  }
  send_current();
  return mav::kResultAccepted;
}

std::uint8_t SimVehicle::return_to_launch() {
  if (!st_.airborne) return mav::kResultDenied;
  targets_ = {Target{{0, 0, std::max(st_.p.z, 2.0)}, false}, Target{{0, 0, 0}, true}};
  target_ = 0;
  paused_ = false;
  st_.mode = Mode::Rtl;
  status(mav::kSeverityInfo, "returning to launch");
  return mav::kResultAccepted;
}

std::uint8_t SimVehicle::land_here() {
  if (!st_.airborne) {
    if (st_.armed) touchdown();
    return st_.armed ? mav::kResultDenied : mav::kResultAccepted;
  }
  targets_ = {Target{{st_.p.x, st_.p.y, 0}, true}};
  target_ = 0;
  paused_ = false;
  st_.mode = Mode::Land;
  return mav::kResultAccepted;
}

std::vector<SimVehicle::Target> SimVehicle::item_targets(const mav::MissionItemInt& item,
                                                         const Vec3& from) const {
  const bool has_position = is_global(item.frame) && (item.x != 0 || item.y != 0);
  // Untrusted items: a position off the globe or an altitude that is not a number is not flown
  // (begin_item() reports it); altitudes are kept within 0..10 km.
  if (is_nav(item.command)) {
    if (has_position && (std::abs(item.x) > 900'000'000 || std::abs(item.y) > 1'800'000'000)) return {};
    if (item.command != wp::kNavLand && item.command != wp::kNavReturnToLaunch &&
        !std::isfinite(item_alt(item)))
      return {};
  }
  const Vec3 xy = has_position ? to_local(item.x, item.y) : Vec3{from.x, from.y, 0};
  const double alt = std::isfinite(item_alt(item)) ? std::clamp(item_alt(item), 0.0, 10'000.0) : 0.0;
  switch (item.command) {
    case wp::kNavTakeoff:  // straight up where it stands
      return {Target{{from.x, from.y, std::max(alt, 1.0)}, false}};
    case wp::kNavWaypoint:
    case 17:  // LOITER_UNLIM, LOITER_TURNS (18), LOITER_TIME (19): flown as waypoints
    case 18:
    case 19:
    case 82:  // SPLINE_WAYPOINT
      return {Target{{xy.x, xy.y, alt}, false}};
    case wp::kNavLand:
      return {Target{{xy.x, xy.y, from.z}, false}, Target{{xy.x, xy.y, 0}, true}};
    case wp::kNavReturnToLaunch:
      return {Target{{0, 0, std::max(from.z, 2.0)}, false}, Target{{0, 0, 0}, true}};
    default:  // DO_CHANGE_SPEED, camera triggers, ...: done at once
      return {};
  }
}

void SimVehicle::begin_item(std::size_t seq) {
  while (true) {
    item_ = seq;
    st_.current_seq = static_cast<std::uint16_t>(seq);
    const auto& item = mission_[seq];
    if (item.command == wp::kDoChangeSpeed && std::isfinite(item.param2) && item.param2 >= 0.1F &&
        item.param2 <= 100.0F)
      v_max_ = item.param2;
    targets_ = item_targets(item, st_.p);
    target_ = 0;
    send_current();
    if (!targets_.empty()) return;
    if (is_nav(item.command))
      status(mav::kSeverityWarning, "item " + std::to_string(seq) + " invalid: skipped");
    // a command without a position (speed, camera, ...): done at once
    send(mav::MissionItemReached{static_cast<std::uint16_t>(seq)});
    st_.reached.push_back(static_cast<std::uint16_t>(seq));
    if (seq >= last_item_) return complete_mission();
    ++seq;
  }
}

// The current item's last target was reached.
void SimVehicle::item_done() {
  send(mav::MissionItemReached{static_cast<std::uint16_t>(item_)});
  st_.reached.push_back(static_cast<std::uint16_t>(item_));
  if (item_ < last_item_) return begin_item(item_ + 1);
  complete_mission();
}

void SimVehicle::complete_mission() {
  st_.mission_complete = true;
  status(mav::kSeverityInfo, "reached last waypoint");
  if (st_.airborne) {
    st_.mode = Mode::Hold;
    hold_ = st_.p;
  } else {
    st_.mode = Mode::Standby;
  }
  send_current();
}

void SimVehicle::touchdown() {
  const bool was_flying = st_.airborne;
  st_.p.z = 0;
  st_.v = {};
  st_.airborne = false;
  st_.armed = false;
  if (st_.mode != Mode::Mission) st_.mode = Mode::Standby;
  if (was_flying) status(mav::kSeverityInfo, "landed, disarmed");
}

void SimVehicle::fly(double dt) {
  if (!st_.armed) return;
  // Where to go: the current target of the mission, RTL or landing; or hold.
  Vec3 goal = st_.p;
  bool landing = false;
  const bool chained = st_.mode == Mode::Mission || st_.mode == Mode::Rtl || st_.mode == Mode::Land;
  if (chained && target_ < targets_.size()) {
    goal = targets_[target_].p;
    landing = targets_[target_].land;
  } else if (st_.mode == Mode::Hold) {
    goal = hold_;
  } else if (!st_.airborne) {
    return;  // armed on the ground, waiting
  }

  // P controller on position with speed and acceleration limits (Hong et al. 2021, eq. 1-2):
  // v_cmd = Kp (p_goal - p), its horizontal norm limited to v_max (and to what the wind leaves of it
  // along the heading), its vertical part to v_up / v_down, braking distance respected; the change of
  // velocity per step limited to a_max * dt.
  const Vec3 d = sub(goal, st_.p);
  const double dh = std::hypot(d.x, d.y);
  Vec3 cmd{};
  if (dh > 1e-9) {
    const double hx = d.x / dh, hy = d.y / dh;
    double s = std::min({v_max_, cfg_.kp * dh, std::sqrt(2.0 * cfg_.a_max * dh)});
    if (cfg_.wind_mps > 0) {
      // the air speed needed for ground speed s along h is |s h - w| <= v_max: s <= w.h + sqrt(...)
      const double wh = wind_.x * hx + wind_.y * hy;
      const double disc = v_max_ * v_max_ - cfg_.wind_mps * cfg_.wind_mps + wh * wh;
      s = std::min(s, disc > 0 ? std::max(0.0, wh + std::sqrt(disc)) : 0.0);
    }
    cmd.x = s * hx;
    cmd.y = s * hy;
  }
  if (landing) {
    cmd.z = -std::min(cfg_.v_down, std::max(0.5, cfg_.kp * st_.p.z));
  } else {
    const double vz_max = d.z > 0 ? cfg_.v_up : cfg_.v_down;
    cmd.z = std::copysign(
        std::min({vz_max, cfg_.kp * std::abs(d.z), std::sqrt(2.0 * cfg_.a_max * std::abs(d.z))}), d.z);
  }
  Vec3 dv = sub(cmd, st_.v);
  const double dvn = norm(dv);
  const double dv_max = cfg_.a_max * dt;
  if (dvn > dv_max) dv = {dv.x * dv_max / dvn, dv.y * dv_max / dvn, dv.z * dv_max / dvn};
  st_.v = {st_.v.x + dv.x, st_.v.y + dv.y, st_.v.z + dv.z};
  const Vec3 before = st_.p;
  st_.p = {st_.p.x + st_.v.x * dt, st_.p.y + st_.v.y * dt, st_.p.z + st_.v.z * dt};
  if (st_.p.z > kGround) st_.airborne = true;
  if (st_.mode == Mode::Mission) st_.flown_m += norm(sub(st_.p, before));

  // Arrival.
  if (landing && st_.p.z <= kGround) {
    ++target_;
    const Mode m = st_.mode;
    touchdown();
    if (m == Mode::Mission && target_ >= targets_.size()) item_done();
    return;
  }
  if (st_.p.z < 0) {  // never below the ground
    st_.p.z = 0;
    st_.v.z = std::max(0.0, st_.v.z);
  }
  if (chained && target_ < targets_.size() && !landing &&
      norm(sub(targets_[target_].p, st_.p)) <= cfg_.acceptance_radius_m) {
    ++target_;
    if (st_.mode == Mode::Mission && target_ >= targets_.size()) item_done();
  }
}

void SimVehicle::drain(double dt) {
  if (!st_.armed || st_.battery <= 0) return;
  st_.battery = std::max(0.0, st_.battery - dt / (cfg_.endurance_min * 60.0));
  if (!low_battery_sent_ && st_.battery * 100.0 <= cfg_.low_battery_pct) {
    low_battery_sent_ = true;
    status(mav::kSeverityWarning,
           "battery low: " + std::to_string(std::lround(st_.battery * 100)) + "% left");
  }
  if (st_.battery <= 0) {
    if (st_.airborne && st_.mode != Mode::Land) {
      status(mav::kSeverityCritical, "battery empty: forced landing");
      st_.mode = Mode::Land;
      paused_ = false;
      targets_ = {Target{{st_.p.x, st_.p.y, 0}, true}};
      target_ = 0;
    } else if (!st_.airborne) {
      touchdown();
    }
  }
}

void SimVehicle::check_failure() {
  if (!cfg_.failure || st_.failed || st_.mode != Mode::Mission || st_.planned_m <= 0) return;
  if (st_.flown_m < cfg_.failure->fraction * st_.planned_m) return;
  st_.failed = true;
  st_.failed_at_s = st_.t;
  if (cfg_.failure->kind == FailureKind::Link) {
    st_.link_lost = true;  // it flies on, silent and deaf
    return;
  }
  status(mav::kSeverityCritical, "failure: forced landing");
  st_.mode = Mode::Land;
  paused_ = false;
  targets_ = {Target{{st_.p.x, st_.p.y, 0}, true}};
  target_ = 0;
}

void SimVehicle::step(double dt) {
  st_.t += dt;
  fly(dt);
  drain(dt);
  check_failure();
  telemetry(dt);
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

// ---- the fleet ----

Fleet::Fleet(const std::vector<VehicleConfig>& configs, const FleetOptions& options) : opt_(options) {
  vehicles_.reserve(configs.size());
  for (const auto& c : configs) vehicles_.push_back(std::make_unique<SimVehicle>(c));
}

void Fleet::run(const std::stop_token& stop, std::optional<double> max_sim_s) {
  using clock = std::chrono::steady_clock;
  const double dt = opt_.physics_dt;
  std::vector<pollfd> fds;
  std::vector<std::size_t> owner;  // fds[k] belongs to vehicles_[owner[k]]
  auto t0 = clock::now();
  long long tick = 0;
  while (!stop.stop_requested()) {
    if (max_sim_s && sim_time_.load() >= *max_sim_s - 1e-9) return;
    const auto due = t0 + std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(
                              static_cast<double>(tick + 1) * dt / opt_.speedup));
    // handle the network until the next step is due
    while (true) {
      const auto left = due - clock::now();
      const auto wait = std::min<clock::duration>(std::max<clock::duration>(left, clock::duration::zero()),
                                                  std::chrono::milliseconds(20));
      timespec ts{};
      ts.tv_sec = static_cast<time_t>(std::chrono::duration_cast<std::chrono::seconds>(wait).count());
      ts.tv_nsec = static_cast<long>(std::chrono::duration_cast<std::chrono::nanoseconds>(wait).count() %
                                     1'000'000'000);
      // rebuilt each time: a TCP vehicle's descriptors change as clients come and go
      fds.clear();
      owner.clear();
      for (std::size_t i = 0; i < vehicles_.size(); ++i)
        for (int fd : vehicles_[i]->poll_handles()) {
          fds.push_back(pollfd{fd, POLLIN, 0});
          owner.push_back(i);
        }
      const int n = ::ppoll(fds.data(), fds.size(), &ts, nullptr);
      if (n > 0) {
        std::size_t last = vehicles_.size();
        for (std::size_t k = 0; k < fds.size(); ++k)
          if ((fds[k].revents & (POLLIN | POLLHUP | POLLERR)) && owner[k] != last) {
            last = owner[k];
            vehicles_[owner[k]]->service_link();
          }
      }
      if (stop.stop_requested()) return;
      if (clock::now() >= due) break;
    }
    for (auto& v : vehicles_) {
      v->service_timeouts();  // the mission protocol's re-requests (wall time)
      v->step(dt);
    }
    ++tick;
    sim_time_.store(sim_time_.load() + dt);
    // Fallen far behind (an overloaded machine): let simulated time slip instead of rushing.
    if (clock::now() - due > std::chrono::seconds(1)) {
      t0 = clock::now() - std::chrono::duration_cast<clock::duration>(
                              std::chrono::duration<double>(static_cast<double>(tick) * dt / opt_.speedup));
    }
  }
}

std::pair<std::uint8_t, Failure> parse_failure(const std::string& text, const std::string& field) {
  const std::string usage = "expected ID@FRACTION[:link|:land] (e.g. 2@0.4:land), got '" + text + "'";
  const auto at = text.find('@');
  if (at == std::string::npos || at == 0) throw InputError(field, usage);
  unsigned id = 0;
  const char* b = text.data();
  const auto [p1, e1] = std::from_chars(b, b + at, id);
  if (e1 != std::errc{} || p1 != b + at || id < 1 || id > 255)
    throw InputError(field, "vehicle id must be a system id in 1..255, got '" + text.substr(0, at) + "'");
  std::string rest = text.substr(at + 1);
  Failure f;
  if (const auto colon = rest.find(':'); colon != std::string::npos) {
    const std::string kind = rest.substr(colon + 1);
    if (kind == "link")
      f.kind = FailureKind::Link;
    else if (kind == "land")
      f.kind = FailureKind::Land;
    else
      throw InputError(field, "failure kind must be 'link' or 'land', got '" + kind + "'");
    rest = rest.substr(0, colon);
  }
  double frac = 0;
  const auto [p2, e2] = std::from_chars(rest.data(), rest.data() + rest.size(), frac);
  if (e2 != std::errc{} || p2 != rest.data() + rest.size() || !(frac > 0.0 && frac < 1.0))
    throw InputError(field, "fraction must be a number in (0, 1), got '" + rest + "'");
  f.fraction = frac;
  return {static_cast<std::uint8_t>(id), f};
}

}  // namespace uavcover::sim
