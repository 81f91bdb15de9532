// The MAVLink messages of the mission protocol, commands and the telemetry of a flying vehicle
// (common.xml / minimal.xml), written by hand.
// Each struct lists its fields; encode_payload() writes them in wire order: the base fields sorted
// by type size (largest first, stable), then the extension fields in declaration order.
// CRC_EXTRA values agree with the c_library_v2 MAVLINK_MESSAGE_CRCS table and are re-derived from
// the field definitions in tests/mavlink (crc_extra_test.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <variant>
#include <vector>

namespace uavcover::mavlink {

struct MessageInfo {
  std::uint32_t id = 0;
  std::string_view name;
  std::uint8_t crc_extra = 0;
  std::uint8_t min_length = 0;  ///< base fields only (MAVLink 1 length)
  std::uint8_t max_length = 0;  ///< with every extension field we know
};

/// MAV_MISSION_RESULT values used here.
enum MissionResult : std::uint8_t {
  kMissionAccepted = 0,
  kMissionError = 1,
  kMissionUnsupportedFrame = 2,
  kMissionUnsupported = 3,
  kMissionNoSpace = 4,
  kMissionInvalid = 5,
  kMissionInvalidSequence = 13,
  kMissionDenied = 14,
  kMissionOperationCancelled = 15,
};
std::string_view mission_result_name(std::uint8_t result);

/// MAV_MISSION_TYPE
enum MissionType : std::uint8_t { kMissionTypeMission = 0, kMissionTypeFence = 1, kMissionTypeRally = 2 };

struct Heartbeat {
  static constexpr MessageInfo info{0, "HEARTBEAT", 50, 9, 9};
  std::uint32_t custom_mode = 0;
  std::uint8_t type = 0;       ///< MAV_TYPE (6 = GCS, 2 = quadrotor)
  std::uint8_t autopilot = 0;  ///< MAV_AUTOPILOT (3 = ArduPilot, 8 = invalid / GCS)
  std::uint8_t base_mode = 0;
  std::uint8_t system_status = 0;
  std::uint8_t mavlink_version = 3;
  friend bool operator==(const Heartbeat&, const Heartbeat&) = default;
};

struct MissionCount {
  static constexpr MessageInfo info{44, "MISSION_COUNT", 221, 4, 9};
  std::uint8_t target_system = 0;
  std::uint8_t target_component = 0;
  std::uint16_t count = 0;
  std::uint8_t mission_type = kMissionTypeMission;  // extension
  std::uint32_t opaque_id = 0;                      // extension
  friend bool operator==(const MissionCount&, const MissionCount&) = default;
};

struct MissionRequestInt {
  static constexpr MessageInfo info{51, "MISSION_REQUEST_INT", 196, 4, 5};
  std::uint8_t target_system = 0;
  std::uint8_t target_component = 0;
  std::uint16_t seq = 0;
  std::uint8_t mission_type = kMissionTypeMission;  // extension
  friend bool operator==(const MissionRequestInt&, const MissionRequestInt&) = default;
};

/// Deprecated MISSION_REQUEST (float items): some autopilots still send it during an upload; the guide
/// says to answer it like MISSION_REQUEST_INT, with MISSION_ITEM_INT.
struct MissionRequest {
  static constexpr MessageInfo info{40, "MISSION_REQUEST", 230, 4, 5};
  std::uint8_t target_system = 0;
  std::uint8_t target_component = 0;
  std::uint16_t seq = 0;
  std::uint8_t mission_type = kMissionTypeMission;  // extension
  friend bool operator==(const MissionRequest&, const MissionRequest&) = default;
};

struct MissionItemInt {
  static constexpr MessageInfo info{73, "MISSION_ITEM_INT", 38, 37, 38};
  std::uint8_t target_system = 0;
  std::uint8_t target_component = 0;
  std::uint16_t seq = 0;
  std::uint8_t frame = 0;
  std::uint16_t command = 0;
  std::uint8_t current = 0;
  std::uint8_t autocontinue = 1;
  float param1 = 0, param2 = 0, param3 = 0, param4 = 0;
  std::int32_t x = 0;  ///< latitude * 1e7 in global frames
  std::int32_t y = 0;  ///< longitude * 1e7 in global frames
  float z = 0;
  std::uint8_t mission_type = kMissionTypeMission;  // extension
  friend bool operator==(const MissionItemInt&, const MissionItemInt&) = default;
};

struct MissionAck {
  static constexpr MessageInfo info{47, "MISSION_ACK", 153, 3, 8};
  std::uint8_t target_system = 0;
  std::uint8_t target_component = 0;
  std::uint8_t type = kMissionAccepted;             ///< MAV_MISSION_RESULT
  std::uint8_t mission_type = kMissionTypeMission;  // extension
  std::uint32_t opaque_id = 0;                      // extension
  friend bool operator==(const MissionAck&, const MissionAck&) = default;
};

struct MissionClearAll {
  static constexpr MessageInfo info{45, "MISSION_CLEAR_ALL", 232, 2, 3};
  std::uint8_t target_system = 0;
  std::uint8_t target_component = 0;
  std::uint8_t mission_type = kMissionTypeMission;  // extension
  friend bool operator==(const MissionClearAll&, const MissionClearAll&) = default;
};

struct MissionCurrent {
  static constexpr MessageInfo info{42, "MISSION_CURRENT", 28, 2, 18};
  std::uint16_t seq = 0;
  std::uint16_t total = 0;            // extension (UINT16_MAX: not supported)
  std::uint8_t mission_state = 0;     // extension (MISSION_STATE)
  std::uint8_t mission_mode = 0;      // extension
  std::uint32_t mission_id = 0;       // extension
  std::uint32_t fence_id = 0;         // extension
  std::uint32_t rally_points_id = 0;  // extension
  friend bool operator==(const MissionCurrent&, const MissionCurrent&) = default;
};

struct MissionItemReached {
  static constexpr MessageInfo info{46, "MISSION_ITEM_REACHED", 11, 2, 2};
  std::uint16_t seq = 0;
  friend bool operator==(const MissionItemReached&, const MissionItemReached&) = default;
};

/// SYS_STATUS (1): the fields a GCS reads for battery and health.
struct SysStatus {
  static constexpr MessageInfo info{1, "SYS_STATUS", 124, 31, 43};
  std::uint32_t onboard_control_sensors_present = 0;
  std::uint32_t onboard_control_sensors_enabled = 0;
  std::uint32_t onboard_control_sensors_health = 0;
  std::uint16_t load = 0;             ///< d%
  std::uint16_t voltage_battery = 0;  ///< mV (UINT16_MAX: unknown)
  std::int16_t current_battery = -1;  ///< cA (-1: unknown)
  std::uint16_t drop_rate_comm = 0;   ///< c%
  std::uint16_t errors_comm = 0;
  std::uint16_t errors_count1 = 0, errors_count2 = 0, errors_count3 = 0, errors_count4 = 0;
  std::int8_t battery_remaining = -1;                          ///< % (-1: unknown)
  std::uint32_t onboard_control_sensors_present_extended = 0;  // extension
  std::uint32_t onboard_control_sensors_enabled_extended = 0;  // extension
  std::uint32_t onboard_control_sensors_health_extended = 0;   // extension
  friend bool operator==(const SysStatus&, const SysStatus&) = default;
};

/// GLOBAL_POSITION_INT (33): the fused global position.
struct GlobalPositionInt {
  static constexpr MessageInfo info{33, "GLOBAL_POSITION_INT", 104, 28, 28};
  std::uint32_t time_boot_ms = 0;
  std::int32_t lat = 0;           ///< degE7
  std::int32_t lon = 0;           ///< degE7
  std::int32_t alt = 0;           ///< mm above mean sea level
  std::int32_t relative_alt = 0;  ///< mm above home
  std::int16_t vx = 0;            ///< cm/s north
  std::int16_t vy = 0;            ///< cm/s east
  std::int16_t vz = 0;            ///< cm/s down
  std::uint16_t hdg = 0;          ///< cdeg (UINT16_MAX: unknown)
  friend bool operator==(const GlobalPositionInt&, const GlobalPositionInt&) = default;
};

/// MAV_CMD numbers of the commands a simulated vehicle answers.
enum MavCommand : std::uint16_t {
  kCmdNavReturnToLaunch = 20,
  kCmdNavLand = 21,
  kCmdDoPauseContinue = 193,
  kCmdDoSetMissionCurrent = 224,  ///< param1: the item to fly to now (seq); ACK FAILED when out of range
  kCmdMissionStart = 300,
  kCmdComponentArmDisarm = 400,
};

/// MAV_RESULT
enum MavResult : std::uint8_t {
  kResultAccepted = 0,
  kResultTemporarilyRejected = 1,
  kResultDenied = 2,
  kResultUnsupported = 3,
  kResultFailed = 4,
};

/// COMMAND_LONG (76)
struct CommandLong {
  static constexpr MessageInfo info{76, "COMMAND_LONG", 152, 33, 33};
  float param1 = 0, param2 = 0, param3 = 0, param4 = 0, param5 = 0, param6 = 0, param7 = 0;
  std::uint16_t command = 0;
  std::uint8_t target_system = 0;
  std::uint8_t target_component = 0;
  std::uint8_t confirmation = 0;
  friend bool operator==(const CommandLong&, const CommandLong&) = default;
};

/// COMMAND_ACK (77)
struct CommandAck {
  static constexpr MessageInfo info{77, "COMMAND_ACK", 143, 3, 10};
  std::uint16_t command = 0;
  std::uint8_t result = kResultAccepted;  ///< MAV_RESULT
  std::uint8_t progress = 0;              // extension
  std::int32_t result_param2 = 0;         // extension
  std::uint8_t target_system = 0;         // extension
  std::uint8_t target_component = 0;      // extension
  friend bool operator==(const CommandAck&, const CommandAck&) = default;
};

/// BATTERY_STATUS (147)
struct BatteryStatus {
  static constexpr MessageInfo info{147, "BATTERY_STATUS", 154, 36, 54};
  std::int32_t current_consumed = -1;        ///< mAh (-1: unknown)
  std::int32_t energy_consumed = -1;         ///< hJ (-1: unknown)
  std::int16_t temperature = INT16_MAX;      ///< cdegC (INT16_MAX: unknown)
  std::array<std::uint16_t, 10> voltages{};  ///< mV per cell (UINT16_MAX: no such cell)
  std::int16_t current_battery = -1;         ///< cA (-1: unknown)
  std::uint8_t id = 0;
  std::uint8_t battery_function = 0;            ///< MAV_BATTERY_FUNCTION (1 = all)
  std::uint8_t type = 0;                        ///< MAV_BATTERY_TYPE (1 = LiPo)
  std::int8_t battery_remaining = -1;           ///< % (-1: unknown)
  std::int32_t time_remaining = 0;              // extension, s (0: unknown)
  std::uint8_t charge_state = 0;                // extension, MAV_BATTERY_CHARGE_STATE
  std::array<std::uint16_t, 4> voltages_ext{};  // extension
  std::uint8_t mode = 0;                        // extension
  std::uint32_t fault_bitmask = 0;              // extension
  friend bool operator==(const BatteryStatus&, const BatteryStatus&) = default;
};

/// MAV_SEVERITY
enum MavSeverity : std::uint8_t {
  kSeverityEmergency = 0,
  kSeverityAlert = 1,
  kSeverityCritical = 2,
  kSeverityError = 3,
  kSeverityWarning = 4,
  kSeverityNotice = 5,
  kSeverityInfo = 6,
  kSeverityDebug = 7,
};

/// STATUSTEXT (253): up to 50 characters (not NUL-terminated when all 50 are used).
struct StatusText {
  static constexpr MessageInfo info{253, "STATUSTEXT", 83, 51, 54};
  std::uint8_t severity = kSeverityInfo;
  std::array<char, 50> text{};
  std::uint16_t id = 0;        // extension
  std::uint8_t chunk_seq = 0;  // extension
  /// The text up to the first NUL (or all 50 characters).
  [[nodiscard]] std::string_view str() const;
  /// A message with `text` (cut to 50 characters).
  static StatusText make(std::uint8_t severity, std::string_view text);
  friend bool operator==(const StatusText&, const StatusText&) = default;
};

using Message = std::variant<Heartbeat, MissionCount, MissionRequestInt, MissionRequest, MissionItemInt,
                             MissionAck, MissionClearAll, MissionCurrent, MissionItemReached, SysStatus,
                             GlobalPositionInt, CommandLong, CommandAck, BatteryStatus, StatusText>;

/// The messages this codec knows, or nullopt.
std::optional<MessageInfo> message_info(std::uint32_t msgid);
const MessageInfo& message_info(const Message& m);

inline constexpr std::size_t kMaxPayload = 255;
using PayloadBuffer = std::array<std::uint8_t, kMaxPayload>;

/// Writes the full (untruncated) payload into `out`; returns its length (info.max_length).
std::size_t encode_payload(const Message& m, PayloadBuffer& out);

/// Decodes a payload as received (possibly truncated by MAVLink 2, or longer than we know:
/// missing bytes read as zero, extra bytes are ignored). nullopt for an unknown msgid.
std::optional<Message> decode_payload(std::uint32_t msgid, std::span<const std::uint8_t> payload);

}  // namespace uavcover::mavlink
