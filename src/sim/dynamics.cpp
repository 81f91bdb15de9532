// A simulated vehicle's dynamics (docs/simulate.md): what arming, mission start, pause, return and
// land do to its state, the mission items it flies, its motion with wind, the battery, and the
// failures it is told to have.
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

namespace uavcover::sim {

namespace mav = uavcover::mavlink;
namespace wp = uavcover::waypoints;
using namespace detail;

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
  if (is_amsl(item.frame)) return static_cast<double>(item.z) - cfg_.home_amsl_m;
  if (is_terrain(item.frame) && cfg_.ground && frame_) {
    const Vec3 at = to_local(item.x, item.y);
    return static_cast<double>(item.z) + ground_above_home(at.x, at.y);
  }
  return static_cast<double>(item.z);
}

double SimVehicle::ground_above_home(double x, double y) const {
  if (!cfg_.ground || !frame_) return 0.0;
  return cfg_.ground->at(frame_->to_wgs84(Point(x, y))) - cfg_.home_amsl_m;
}

bool SimVehicle::is_home_item(std::size_t seq) const {
  // ArduPilot's convention (and `uavcover upload` without --no-home): item 0 is the home position.
  return seq == 0 && mission_.size() > 1 && mission_[0].command == wp::kNavWaypoint &&
         mission_[0].frame == 0 && mission_[0].z == 0.0F;
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

namespace {
// a breach is more than this outside the fence: the controller cuts corners within its acceptance radius
constexpr double kFenceSlackM = 2.5;
}  // namespace

std::uint8_t SimVehicle::start_mission(int first, int last) {
  if (mission_.empty() || !st_.armed || st_.battery <= 0) return mav::kResultDenied;
  if (st_.mode == Mode::Mission) return mav::kResultAccepted;  // a repeated command changes nothing
  const int n = static_cast<int>(mission_.size());
  first = std::max(first, is_home_item(0) ? 1 : 0);
  if (last < 0 || last >= n) last = n - 1;
  if (first > last) return mav::kResultDenied;
  // the fence (issue 31): a mission with a position outside it is refused, as PX4's feasibility check
  // refuses a mission that violates the geofence
  if (!fence_.empty() && frame_)
    for (int i = first; i <= last; ++i) {
      const auto& it = mission_[static_cast<std::size_t>(i)];
      if (!is_global(it.frame) || (it.x == 0 && it.y == 0) || is_home_item(static_cast<std::size_t>(i)))
        continue;
      if (!autopilot::fence_allows(fence_, LonLat{it.y * 1e-7, it.x * 1e-7})) {
        status(mav::kSeverityError, "Fence: mission item " + std::to_string(i) + " lies outside the fence");
        return mav::kResultDenied;
      }
    }
  // heights above the terrain need terrain data (ArduPilot: "PreArm: Waiting for terrain data")
  if (!cfg_.ground)
    for (int i = first; i <= last; ++i)
      if (is_terrain(mission_[static_cast<std::size_t>(i)].frame) &&
          is_nav(mission_[static_cast<std::size_t>(i)].command)) {
        status(mav::kSeverityCritical,
               "PreArm: Waiting for terrain data (mission item " + std::to_string(i) + " is above terrain)");
        return mav::kResultDenied;
      }
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
  fence_breached_ = false;
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
  targets_ = {Target{{0, 0, std::max(st_.p.z, 2.0)}, false, {}}, Target{{0, 0, 0}, true, {}}};
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
  targets_ = {Target{{st_.p.x, st_.p.y, 0}, true, {}}};
  target_ = 0;
  paused_ = false;
  st_.mode = Mode::Land;
  return mav::kResultAccepted;
}

std::uint8_t SimVehicle::set_current(int seq) {
  const int n = static_cast<int>(mission_.size());
  if (seq < 0 || seq >= n || is_home_item(static_cast<std::size_t>(seq))) return mav::kResultFailed;
  st_.set_current.push_back(static_cast<std::uint16_t>(seq));
  if (st_.mode == Mode::Mission) {
    last_item_ = std::max(last_item_, static_cast<std::size_t>(seq));
    begin_item(static_cast<std::size_t>(seq));  // sends MISSION_CURRENT
  } else {
    st_.current_seq = static_cast<std::uint16_t>(seq);
    send_current();
  }
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
      return {Target{{from.x, from.y, std::max(alt, 1.0)}, false, {}}};
    case wp::kNavWaypoint:
    case 17:  // LOITER_UNLIM, LOITER_TURNS (18), LOITER_TIME (19): flown as waypoints
    case 18:
    case 19:
    case 82:  // SPLINE_WAYPOINT
      if (is_terrain(item.frame) && cfg_.ground && std::isfinite(item.z))
        return {Target{{xy.x, xy.y, alt}, false, std::clamp(static_cast<double>(item.z), 0.0, 10'000.0)}};
      return {Target{{xy.x, xy.y, alt}, false, {}}};
    case wp::kNavLand:
      return {Target{{xy.x, xy.y, from.z}, false, {}}, Target{{xy.x, xy.y, 0}, true, {}}};
    case wp::kNavReturnToLaunch:
      return {Target{{0, 0, std::max(from.z, 2.0)}, false, {}}, Target{{0, 0, 0}, true, {}}};
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
  bool terrain_leg = false;  // flying to a terrain-frame item
  const bool chained = st_.mode == Mode::Mission || st_.mode == Mode::Rtl || st_.mode == Mode::Land;
  const bool stuck = st_.failed && cfg_.failure && cfg_.failure->kind == FailureKind::Stuck;
  if (stuck && st_.mode == Mode::Mission) {
    goal = stuck_at_;  // no progress towards the mission's items
  } else if (chained && target_ < targets_.size()) {
    goal = targets_[target_].p;
    landing = targets_[target_].land;
    // above the terrain: the height follows the ground under the vehicle
    if (const auto& agl = targets_[target_].agl) {
      goal.z = ground_above_home(st_.p.x, st_.p.y) + *agl;
      terrain_leg = true;
    }
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
  // a fence breach in flight (issue 31): ArduPilot's FENCE_ACTION 1, return to launch
  if (!fence_.empty() && frame_ && st_.airborne && !fence_breached_ && st_.mode != Mode::Rtl &&
      st_.mode != Mode::Land &&
      !autopilot::fence_allows(fence_, frame_->to_wgs84(Point(st_.p.x, st_.p.y)), kFenceSlackM)) {
    fence_breached_ = true;
    st_.fence_breach = true;
    status(mav::kSeverityCritical, "Fence breached: returning to launch");
    (void)return_to_launch();
    return;
  }

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
  if (terrain_leg && st_.airborne)
    st_.agl_min_m = std::min(st_.agl_min_m, st_.p.z - ground_above_home(st_.p.x, st_.p.y));
  if (chained && !(stuck && st_.mode == Mode::Mission) && target_ < targets_.size() && !landing &&
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
      targets_ = {Target{{st_.p.x, st_.p.y, 0}, true, {}}};
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
  if (cfg_.failure->kind == FailureKind::Stuck) {
    stuck_at_ = st_.p;  // holds here in its mission from now on (fly())
    status(mav::kSeverityWarning, "failure: no progress");
    return;
  }
  status(mav::kSeverityCritical, "failure: forced landing");
  st_.mode = Mode::Land;
  paused_ = false;
  targets_ = {Target{{st_.p.x, st_.p.y, 0}, true, {}}};
  target_ = 0;
}

void SimVehicle::step(double dt) {
  st_.t += dt;
  fly(dt);
  drain(dt);
  check_failure();
  telemetry(dt);
}

}  // namespace uavcover::sim
