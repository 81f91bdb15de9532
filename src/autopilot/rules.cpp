// The autopilots' upload rules (rules.hpp). Each rule names the function of the autopilot's
// source it comes from; docs/exports.md lists them with their files.
#include "autopilot/rules.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <numbers>

#include "mavlink/mission_protocol.hpp"

namespace uavcover::autopilot {

using namespace waypoints;  // the waypoint model's command and frame numbers

namespace {

namespace mav = uavcover::mavlink;

// MAV_CMD numbers of the rules below (MAVLink common.xml)
enum : std::uint16_t {
  kLoiterUnlim = 17,
  kLoiterTurns = 18,
  kLoiterTime = 19,
  kContinueAndChangeAlt = 30,
  kLoiterToAlt = 31,
  kSplineWaypoint = 82,
  kAltitudeWait = 83,
  kVtolTakeoff = 84,
  kVtolLand = 85,
  kGuidedEnable = 92,
  kNavDelay = 93,
  kPayloadPlace = 94,
  kConditionDelay = 112,
  kConditionDistance = 114,
  kConditionYaw = 115,
  kDoJump = 177,
  kDoSetHome = 179,
  kDoSetRelay = 181,
  kDoRepeatRelay = 182,
  kDoSetServo = 183,
  kDoRepeatServo = 184,
  kDoLandStart = 189,
  kDoGoAround = 191,
  kDoPauseContinue = 193,
  kDoSetReverse = 194,
  kDoSetRoi = 201,
  kDoDigicamConfigure = 202,
  kDoDigicamControl = 203,
  kDoMountControl = 205,
  kDoFenceEnable = 207,
  kDoParachute = 208,
  kDoInvertedFlight = 210,
  kDoGripper = 211,
  kDoAutotuneEnable = 212,
  kDoSetResumeRepeatDist = 215,
  kDoSprayer = 216,
  kDoSendScriptMessage = 217,
  kDoGuidedLimits = 222,
  kDoEngineControl = 223,
  kDoVtolTransition = 3000,
  kImageStopCapture = 2001,
  kVideoStartCapture = 2500,
  kVideoStopCapture = 2501,
  kDoWinch = 42600,
  kNavScriptTime = 42702,
  kNavAttitudeTime = 42703,
};

// The commands AP_Mission::mavlink_int_to_mission_cmd converts (its switch); any other is
// MAV_MISSION_UNSUPPORTED. IMAGE_START_CAPTURE/STOP and VIDEO_START/STOP_CAPTURE are converted since
// ArduPilot 4.4 (AP_Camera's mission commands); the SITL (May 2024) ran them.
constexpr std::uint16_t kArduPilotCommands[] = {kNavWaypoint,
                                                kLoiterUnlim,
                                                kLoiterTurns,
                                                kLoiterTime,
                                                std::uint16_t{kNavReturnToLaunch},
                                                std::uint16_t{kNavLand},
                                                std::uint16_t{kNavTakeoff},
                                                kContinueAndChangeAlt,
                                                kLoiterToAlt,
                                                kSplineWaypoint,
                                                kGuidedEnable,
                                                kNavDelay,
                                                kConditionDelay,
                                                kConditionDistance,
                                                kConditionYaw,
                                                kDoJump,
                                                std::uint16_t{kDoChangeSpeed},
                                                kDoSetHome,
                                                kDoSetRelay,
                                                kDoRepeatRelay,
                                                kDoSetServo,
                                                kDoRepeatServo,
                                                kDoLandStart,
                                                kDoGoAround,
                                                kDoSetRoi,
                                                kDoDigicamConfigure,
                                                kDoDigicamControl,
                                                kDoMountControl,
                                                std::uint16_t{kDoSetCamTriggDist},
                                                kDoFenceEnable,
                                                kDoParachute,
                                                kDoInvertedFlight,
                                                kDoGripper,
                                                kDoGuidedLimits,
                                                kDoAutotuneEnable,
                                                kAltitudeWait,
                                                kVtolTakeoff,
                                                kVtolLand,
                                                kDoVtolTransition,
                                                kDoSetReverse,
                                                kDoEngineControl,
                                                kPayloadPlace,
                                                kDoWinch,
                                                kDoSetResumeRepeatDist,
                                                kDoSprayer,
                                                kDoSendScriptMessage,
                                                kNavScriptTime,
                                                kNavAttitudeTime,
                                                kDoPauseContinue,
                                                std::uint16_t{kDoGimbalManagerPitchyaw},
                                                std::uint16_t{kImageStartCapture},
                                                kImageStopCapture,
                                                kVideoStartCapture,
                                                kVideoStopCapture};

// AP_Mission::stored_in_location: commands whose x/y/z are a location.
bool ardupilot_location(std::uint16_t c) {
  switch (c) {
    case kNavWaypoint:
    case kLoiterUnlim:
    case kLoiterTurns:
    case kLoiterTime:
    case kNavLand:
    case kNavTakeoff:
    case kContinueAndChangeAlt:
    case kLoiterToAlt:
    case kSplineWaypoint:
    case kGuidedEnable:
    case kDoSetHome:
    case kDoLandStart:
    case kDoGoAround:
    case kDoSetRoi:
    case kVtolTakeoff:
    case kVtolLand:
    case kPayloadPlace:
      return true;
    default:
      return false;
  }
}

// FeasibilityChecker::checkMissionItemValidity: the commands PX4 runs in a mission (as MAV_CMD numbers).
constexpr std::uint16_t kPx4Commands[] = {kNavWaypoint,
                                          kLoiterUnlim,
                                          kLoiterTime,
                                          std::uint16_t{kNavReturnToLaunch},
                                          std::uint16_t{kNavLand},
                                          std::uint16_t{kNavTakeoff},
                                          kLoiterToAlt,
                                          kVtolTakeoff,
                                          kVtolLand,
                                          kNavDelay,
                                          std::uint16_t{4501} /* CONDITION_GATE */,
                                          kDoWinch,
                                          kDoGripper,
                                          kDoJump,
                                          std::uint16_t{kDoChangeSpeed},
                                          kDoSetHome,
                                          kDoSetServo,
                                          kDoLandStart,
                                          std::uint16_t{2003} /* DO_TRIGGER_CONTROL */,
                                          kDoDigicamControl,
                                          std::uint16_t{kImageStartCapture},
                                          kImageStopCapture,
                                          kVideoStartCapture,
                                          kVideoStopCapture,
                                          std::uint16_t{200} /* DO_CONTROL_VIDEO */,
                                          std::uint16_t{204} /* DO_MOUNT_CONFIGURE */,
                                          kDoMountControl,
                                          std::uint16_t{kDoGimbalManagerPitchyaw},
                                          std::uint16_t{1001} /* GIMBAL_MANAGER_CONFIGURE */,
                                          kDoSetRoi,
                                          std::uint16_t{195} /* DO_SET_ROI_LOCATION */,
                                          std::uint16_t{196} /* DO_SET_ROI_WPNEXT_OFFSET */,
                                          std::uint16_t{197} /* DO_SET_ROI_NONE */,
                                          std::uint16_t{kDoSetCamTriggDist},
                                          std::uint16_t{260} /* OBLIQUE_SURVEY */,
                                          std::uint16_t{214} /* DO_SET_CAM_TRIGG_INTERVAL */,
                                          std::uint16_t{530} /* SET_CAMERA_MODE */,
                                          std::uint16_t{531} /* SET_CAMERA_ZOOM */,
                                          std::uint16_t{532} /* SET_CAMERA_FOCUS */,
                                          kDoVtolTransition};

template <std::size_t N>
bool in(const std::uint16_t (&list)[N], std::uint16_t c) {
  for (const auto x : list)
    if (x == c) return true;
  return false;
}

// PX4's get_distance_to_next_waypoint (lib/geo): haversine on a sphere of CONSTANTS_RADIUS_OF_EARTH.
double px4_distance_m(double lat_a, double lon_a, double lat_b, double lon_b) {
  constexpr double kRadius = 6371000.0;
  const double d2r = std::numbers::pi / 180.0;
  const double dlat = (lat_b - lat_a) * d2r, dlon = (lon_b - lon_a) * d2r;
  const double a = std::sin(dlat / 2) * std::sin(dlat / 2) +
                   std::sin(dlon / 2) * std::sin(dlon / 2) * std::cos(lat_a * d2r) * std::cos(lat_b * d2r);
  return kRadius * 2.0 * std::atan2(std::sqrt(a), std::sqrt(1.0 - a));
}

}  // namespace

std::uint8_t ardupilot_item_result(const mavlink::MissionItemInt& item) {
  // AP_Mission::sanity_check_params: bit n set = param n+1 must not be NaN; infinity never allowed
  std::uint8_t nan_mask = 0xff;
  switch (item.command) {
    case kNavWaypoint:
    case kNavLand:
    case kNavTakeoff:
    case kVtolTakeoff:
      nan_mask = static_cast<std::uint8_t>(~(1u << 3));  // param 4 may be NaN
      break;
    case kVtolLand:
      nan_mask = static_cast<std::uint8_t>(~((1u << 2) | (1u << 3)));  // params 3 and 4 may be NaN
      break;
    default:
      break;
  }
  const std::array<float, 4> params = {item.param1, item.param2, item.param3, item.param4};
  for (std::size_t n = 0; n < params.size(); ++n)
    if (((nan_mask & (1u << n)) != 0 && std::isnan(params[n])) || std::isinf(params[n]))
      return static_cast<std::uint8_t>(kMissionInvalidParam1 + n);
  // AP_Mission::mavlink_int_to_mission_cmd: command 0 is reserved, unknown commands are unsupported
  if (item.command == 0) return mav::kMissionInvalid;
  if (!in(kArduPilotCommands, item.command)) return mav::kMissionUnsupported;
  if (ardupilot_location(item.command)) {
    // check_lat / check_lng (degrees * 1e7), then the altitude fits Location (LOCATION_ALT_MAX_M)
    if (std::abs(static_cast<std::int64_t>(item.x)) > 900000000LL) return kMissionInvalidParam5X;
    if (std::abs(static_cast<std::int64_t>(item.y)) > 1800000000LL) return kMissionInvalidParam6Y;
    if (std::isnan(item.z) || std::abs(item.z) >= 83000.0F) return kMissionInvalidParam7;
    switch (item.frame) {
      case 0:   // MAV_FRAME_GLOBAL
      case 2:   // MAV_FRAME_MISSION
      case 5:   // MAV_FRAME_GLOBAL_INT
      case 3:   // MAV_FRAME_GLOBAL_RELATIVE_ALT
      case 6:   // MAV_FRAME_GLOBAL_RELATIVE_ALT_INT
      case 10:  // MAV_FRAME_GLOBAL_TERRAIN_ALT (with AP_TERRAIN_AVAILABLE)
      case 11:  // MAV_FRAME_GLOBAL_TERRAIN_ALT_INT
        break;
      default:
        return mav::kMissionUnsupportedFrame;
    }
  }
  return mav::kMissionAccepted;
}

std::vector<Problem> ardupilot_problems(const std::vector<MissionItem>& items,
                                        const ArduPilotLimits& limits) {
  std::vector<Problem> out;
  const std::string sanity = "ArduPilot AP_Mission::mavlink_int_to_mission_cmd / sanity_check_params";
  for (std::size_t k = 0; k < items.size(); ++k) {
    const MissionItem& it = items[k];
    // uploaded with home as item 0: this item's seq is k + 1
    const auto result =
        ardupilot_item_result(mav::to_mission_item_int(it, static_cast<std::uint16_t>(k + 1)));
    if (result != mav::kMissionAccepted)
      out.push_back({true, static_cast<long>(k), sanity,
                     fmt::format("refused with {}", mav::mission_result_name(result))});
    if (it.command == kImageStartCapture) {
      // AP_Camera (GCS_MAVLINK::handle_command_camera, AP_Mission::start_command_camera): param1 is the
      // camera instance (0 = all; a negative one is refused), param3 the number of images
      if (it.param1 != 0.0f)
        out.push_back(
            {true, static_cast<long>(k), "ArduPilot AP_Camera (IMAGE_START_CAPTURE param1 = instance)",
             fmt::format("param1 {} selects camera instance {}, not all cameras (0)", it.param1, it.param1)});
      if (it.param3 != 1.0f)
        out.push_back({true, static_cast<long>(k),
                       "ArduPilot AP_Camera (IMAGE_START_CAPTURE param3 = images)",
                       fmt::format("param3 {} is not one image", it.param3)});
    }
    if (it.command == kDoSetCamTriggDist && it.param3 != 0.0f && it.param3 != 1.0f)
      out.push_back({true, static_cast<long>(k), "ArduPilot AP_Mission (cam_trigg_dist.trigger)",
                     fmt::format("param3 {} is neither 0 nor 1 (shoot once now)", it.param3)});
    if (it.command == kDoSetCamTriggDist && !(it.param1 >= 0.0f))
      out.push_back({true, static_cast<long>(k), "ArduPilot AP_Camera::set_trigger_distance",
                     fmt::format("trigger distance {} m is negative", it.param1)});
  }
  if (items.size() + 1 > limits.max_items)
    out.push_back(
        {false, -1, "ArduPilot AP_Mission::num_commands_max (MAV_MISSION_NO_SPACE)",
         fmt::format("{} items with home, the vehicle stores {}", items.size() + 1, limits.max_items)});
  // AP_Mission::starts_with_takeoff_cmd: the first navigation command (NAV_DELAY skipped) is a take-off
  for (const MissionItem& it : items) {
    const bool nav = it.command <= 95 /* MAV_CMD_NAV_LAST */;
    if (!nav || it.command == kNavDelay) continue;
    if (it.command != kNavTakeoff)
      out.push_back({true, -1, "ArduCopter ModeAuto::init (AP_Mission::starts_with_takeoff_cmd)",
                     "the first navigation command is not a take-off: \"Auto: Missing Takeoff Cmd\""});
    break;
  }
  return out;
}

std::vector<Problem> px4_problems(const std::vector<MissionItem>& items, LonLat home, double home_amsl_m,
                                  const Px4Params& params) {
  std::vector<Problem> out;
  const std::string feasibility = "PX4 FeasibilityChecker::";
  bool found_position = false, first_waypoint = false, have_last = false;
  double last_lat = 0, last_lon = 0;
  auto rel_alt = [&](const MissionItem& it) {
    return it.frame == kFrameGlobal ? static_cast<double>(it.alt) - home_amsl_m : static_cast<double>(it.alt);
  };
  for (std::size_t k = 0; k < items.size(); ++k) {
    const MissionItem& it = items[k];
    const long at = static_cast<long>(k);
    if (!in(kPx4Commands, it.command))
      out.push_back({true, at, feasibility + "checkMissionItemValidity",
                     fmt::format("unsupported command {}", it.command)});
    const bool pos = has_position(it);
    // MavlinkMissionManager::parse_mavlink_mission_item: global frames for positioned items, mission frame
    // for the others; coordinates are read as they are
    if (pos) {
      if (it.frame != kFrameGlobal && it.frame != kFrameGlobalRelativeAlt && it.frame != 5 && it.frame != 6)
        out.push_back({true, at, "PX4 MavlinkMissionManager::parse_mavlink_mission_item",
                       fmt::format("frame {} is not a global frame", it.frame)});
      if (!std::isfinite(it.lat) || !std::isfinite(it.lon) || !std::isfinite(it.alt) ||
          std::abs(it.lat) > 90 || std::abs(it.lon) > 180)
        out.push_back({true, at, "PX4 MavlinkMissionManager::parse_mavlink_mission_item",
                       "coordinates not finite or out of range"});
    }
    // MavlinkMissionManager::parse_mavlink_mission_item: DO_SET_ROI is read in a global frame only (the
    // mission-frame branch does not list it: MAV_MISSION_UNSUPPORTED), and its param1 must be
    // MAV_ROI_LOCATION (3) or MAV_ROI_NONE (0), else MAV_MISSION_INVALID_PARAM1
    if (it.command == kDoSetRoi) {
      if (it.frame != kFrameGlobal && it.frame != kFrameGlobalRelativeAlt && it.frame != 5 && it.frame != 6)
        out.push_back({true, at, "PX4 MavlinkMissionManager::parse_mavlink_mission_item (DO_SET_ROI)",
                       fmt::format("frame {} is not a global frame", it.frame)});
      if (it.param1 != 0.0f && it.param1 != 3.0f)
        out.push_back(
            {true, at, "PX4 MavlinkMissionManager::parse_mavlink_mission_item (DO_SET_ROI)",
             fmt::format("param1 {} is neither MAV_ROI_NONE (0) nor MAV_ROI_LOCATION (3)", it.param1)});
    }
    // checkTakeoff
    if (it.command == kNavTakeoff) {
      if (rel_alt(it) - 1.0 < params.nav_acc_rad_m)
        out.push_back({true, at, feasibility + "checkTakeoff",
                       fmt::format("take-off altitude {} m is below NAV_ACC_RAD + 1 m ({} m)", rel_alt(it),
                                   params.nav_acc_rad_m + 1.0)});
      if (found_position)
        out.push_back({true, at, feasibility + "checkTakeoff", "take-off is not the first positioned item"});
    }
    if (pos) found_position = true;
    // checkDistanceToFirstWaypoint
    if (pos && !first_waypoint) {
      first_waypoint = true;
      const double d = px4_distance_m(it.lat, it.lon, home.lat, home.lon);
      if (params.mis_dist_1wp_m > 0 && d >= params.mis_dist_1wp_m)
        out.push_back(
            {false, at, feasibility + "checkDistanceToFirstWaypoint",
             fmt::format("first waypoint {:.0f} m from home, MIS_DIST_1WP {} m", d, params.mis_dist_1wp_m)});
    }
    // checkDistancesBetweenWaypoints
    if (pos) {
      if (have_last) {
        const double d = px4_distance_m(it.lat, it.lon, last_lat, last_lon);
        if (params.mis_dist_wps_m > 0 && d > params.mis_dist_wps_m)
          out.push_back({false, at, feasibility + "checkDistancesBetweenWaypoints",
                         fmt::format("{:.0f} m from the previous waypoint, MIS_DIST_WPS {} m", d,
                                     params.mis_dist_wps_m)});
      }
      have_last = true;
      last_lat = it.lat;
      last_lon = it.lon;
    }
    // checkIfBelowHomeAltitude (a warning in PX4); a landing at home's ground is at home's altitude
    if (pos && rel_alt(it) < -0.01)
      out.push_back({false, at, feasibility + "checkIfBelowHomeAltitude",
                     fmt::format("{} m below home", -rel_alt(it))});
  }
  if (items.size() > params.max_items)
    out.push_back({false, -1, "PX4 dataman (DM_KEY_WAYPOINTS_OFFBOARD_x_MAX, MAV_MISSION_NO_SPACE)",
                   fmt::format("{} items, PX4 stores {}", items.size(), params.max_items)});
  return out;
}

std::string describe(const Problem& p, const std::vector<MissionItem>& items) {
  if (p.item < 0 || static_cast<std::size_t>(p.item) >= items.size())
    return fmt::format("the mission: {} ({})", p.message, p.rule);
  const MissionItem& it = items[static_cast<std::size_t>(p.item)];
  return fmt::format("mission item {} (MAV_CMD {}, {}): {} ({})", p.item + 1, it.command, it.role, p.message,
                     p.rule);
}

}  // namespace uavcover::autopilot
