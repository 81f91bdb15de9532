#include "mavlink/messages.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

namespace uavcover::mavlink {

namespace {

// Little-endian writers/readers at a byte offset.
class Writer {
 public:
  explicit Writer(PayloadBuffer& b) : b_(b) { b_.fill(0); }
  void u8(std::uint8_t v) { b_[pos_++] = v; }
  void u16(std::uint16_t v) {
    u8(static_cast<std::uint8_t>(v & 0xFF));
    u8(static_cast<std::uint8_t>(v >> 8));
  }
  void u32(std::uint32_t v) {
    u16(static_cast<std::uint16_t>(v & 0xFFFF));
    u16(static_cast<std::uint16_t>(v >> 16));
  }
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void i16(std::int16_t v) { u16(static_cast<std::uint16_t>(v)); }
  void i8(std::int8_t v) { u8(static_cast<std::uint8_t>(v)); }
  void f32(float v) { u32(std::bit_cast<std::uint32_t>(v)); }
  [[nodiscard]] std::size_t size() const { return pos_; }

 private:
  PayloadBuffer& b_;
  std::size_t pos_ = 0;
};

class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> p) : p_(p) {}
  std::uint8_t u8() {
    const std::uint8_t v = pos_ < p_.size() ? p_[pos_] : std::uint8_t{0};  // truncated bytes are zero
    ++pos_;
    return v;
  }
  std::uint16_t u16() {
    const std::uint16_t lo = u8();
    const std::uint16_t hi = u8();
    return static_cast<std::uint16_t>(lo | (hi << 8));
  }
  std::uint32_t u32() {
    const std::uint32_t lo = u16();
    const std::uint32_t hi = u16();
    return lo | (hi << 16);
  }
  std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
  std::int16_t i16() { return static_cast<std::int16_t>(u16()); }
  std::int8_t i8() { return static_cast<std::int8_t>(u8()); }
  float f32() { return std::bit_cast<float>(u32()); }

 private:
  std::span<const std::uint8_t> p_;
  std::size_t pos_ = 0;
};

// One encode/decode pair per message, fields in wire order.
void write(Writer& w, const Heartbeat& m) {
  w.u32(m.custom_mode);
  w.u8(m.type);
  w.u8(m.autopilot);
  w.u8(m.base_mode);
  w.u8(m.system_status);
  w.u8(m.mavlink_version);
}
void read(Reader& r, Heartbeat& m) {
  m.custom_mode = r.u32();
  m.type = r.u8();
  m.autopilot = r.u8();
  m.base_mode = r.u8();
  m.system_status = r.u8();
  m.mavlink_version = r.u8();
}

void write(Writer& w, const MissionCount& m) {
  w.u16(m.count);
  w.u8(m.target_system);
  w.u8(m.target_component);
  w.u8(m.mission_type);
  w.u32(m.opaque_id);
}
void read(Reader& r, MissionCount& m) {
  m.count = r.u16();
  m.target_system = r.u8();
  m.target_component = r.u8();
  m.mission_type = r.u8();
  m.opaque_id = r.u32();
}

void write(Writer& w, const MissionRequestInt& m) {
  w.u16(m.seq);
  w.u8(m.target_system);
  w.u8(m.target_component);
  w.u8(m.mission_type);
}
void read(Reader& r, MissionRequestInt& m) {
  m.seq = r.u16();
  m.target_system = r.u8();
  m.target_component = r.u8();
  m.mission_type = r.u8();
}

void write(Writer& w, const MissionRequest& m) {
  w.u16(m.seq);
  w.u8(m.target_system);
  w.u8(m.target_component);
  w.u8(m.mission_type);
}
void read(Reader& r, MissionRequest& m) {
  m.seq = r.u16();
  m.target_system = r.u8();
  m.target_component = r.u8();
  m.mission_type = r.u8();
}

void write(Writer& w, const MissionItemInt& m) {
  w.f32(m.param1);
  w.f32(m.param2);
  w.f32(m.param3);
  w.f32(m.param4);
  w.i32(m.x);
  w.i32(m.y);
  w.f32(m.z);
  w.u16(m.seq);
  w.u16(m.command);
  w.u8(m.target_system);
  w.u8(m.target_component);
  w.u8(m.frame);
  w.u8(m.current);
  w.u8(m.autocontinue);
  w.u8(m.mission_type);
}
void read(Reader& r, MissionItemInt& m) {
  m.param1 = r.f32();
  m.param2 = r.f32();
  m.param3 = r.f32();
  m.param4 = r.f32();
  m.x = r.i32();
  m.y = r.i32();
  m.z = r.f32();
  m.seq = r.u16();
  m.command = r.u16();
  m.target_system = r.u8();
  m.target_component = r.u8();
  m.frame = r.u8();
  m.current = r.u8();
  m.autocontinue = r.u8();
  m.mission_type = r.u8();
}

void write(Writer& w, const MissionAck& m) {
  w.u8(m.target_system);
  w.u8(m.target_component);
  w.u8(m.type);
  w.u8(m.mission_type);
  w.u32(m.opaque_id);
}
void read(Reader& r, MissionAck& m) {
  m.target_system = r.u8();
  m.target_component = r.u8();
  m.type = r.u8();
  m.mission_type = r.u8();
  m.opaque_id = r.u32();
}

void write(Writer& w, const MissionClearAll& m) {
  w.u8(m.target_system);
  w.u8(m.target_component);
  w.u8(m.mission_type);
}
void read(Reader& r, MissionClearAll& m) {
  m.target_system = r.u8();
  m.target_component = r.u8();
  m.mission_type = r.u8();
}

void write(Writer& w, const MissionCurrent& m) {
  w.u16(m.seq);
  w.u16(m.total);
  w.u8(m.mission_state);
  w.u8(m.mission_mode);
  w.u32(m.mission_id);
  w.u32(m.fence_id);
  w.u32(m.rally_points_id);
}
void read(Reader& r, MissionCurrent& m) {
  m.seq = r.u16();
  m.total = r.u16();
  m.mission_state = r.u8();
  m.mission_mode = r.u8();
  m.mission_id = r.u32();
  m.fence_id = r.u32();
  m.rally_points_id = r.u32();
}

void write(Writer& w, const MissionItemReached& m) { w.u16(m.seq); }
void read(Reader& r, MissionItemReached& m) { m.seq = r.u16(); }

void write(Writer& w, const SysStatus& m) {
  w.u32(m.onboard_control_sensors_present);
  w.u32(m.onboard_control_sensors_enabled);
  w.u32(m.onboard_control_sensors_health);
  w.u16(m.load);
  w.u16(m.voltage_battery);
  w.i16(m.current_battery);
  w.u16(m.drop_rate_comm);
  w.u16(m.errors_comm);
  w.u16(m.errors_count1);
  w.u16(m.errors_count2);
  w.u16(m.errors_count3);
  w.u16(m.errors_count4);
  w.i8(m.battery_remaining);
  w.u32(m.onboard_control_sensors_present_extended);
  w.u32(m.onboard_control_sensors_enabled_extended);
  w.u32(m.onboard_control_sensors_health_extended);
}
void read(Reader& r, SysStatus& m) {
  m.onboard_control_sensors_present = r.u32();
  m.onboard_control_sensors_enabled = r.u32();
  m.onboard_control_sensors_health = r.u32();
  m.load = r.u16();
  m.voltage_battery = r.u16();
  m.current_battery = r.i16();
  m.drop_rate_comm = r.u16();
  m.errors_comm = r.u16();
  m.errors_count1 = r.u16();
  m.errors_count2 = r.u16();
  m.errors_count3 = r.u16();
  m.errors_count4 = r.u16();
  m.battery_remaining = r.i8();
  m.onboard_control_sensors_present_extended = r.u32();
  m.onboard_control_sensors_enabled_extended = r.u32();
  m.onboard_control_sensors_health_extended = r.u32();
}

void write(Writer& w, const GlobalPositionInt& m) {
  w.u32(m.time_boot_ms);
  w.i32(m.lat);
  w.i32(m.lon);
  w.i32(m.alt);
  w.i32(m.relative_alt);
  w.i16(m.vx);
  w.i16(m.vy);
  w.i16(m.vz);
  w.u16(m.hdg);
}
void read(Reader& r, GlobalPositionInt& m) {
  m.time_boot_ms = r.u32();
  m.lat = r.i32();
  m.lon = r.i32();
  m.alt = r.i32();
  m.relative_alt = r.i32();
  m.vx = r.i16();
  m.vy = r.i16();
  m.vz = r.i16();
  m.hdg = r.u16();
}

void write(Writer& w, const CommandLong& m) {
  w.f32(m.param1);
  w.f32(m.param2);
  w.f32(m.param3);
  w.f32(m.param4);
  w.f32(m.param5);
  w.f32(m.param6);
  w.f32(m.param7);
  w.u16(m.command);
  w.u8(m.target_system);
  w.u8(m.target_component);
  w.u8(m.confirmation);
}
void read(Reader& r, CommandLong& m) {
  m.param1 = r.f32();
  m.param2 = r.f32();
  m.param3 = r.f32();
  m.param4 = r.f32();
  m.param5 = r.f32();
  m.param6 = r.f32();
  m.param7 = r.f32();
  m.command = r.u16();
  m.target_system = r.u8();
  m.target_component = r.u8();
  m.confirmation = r.u8();
}

void write(Writer& w, const CommandAck& m) {
  w.u16(m.command);
  w.u8(m.result);
  w.u8(m.progress);
  w.i32(m.result_param2);
  w.u8(m.target_system);
  w.u8(m.target_component);
}
void read(Reader& r, CommandAck& m) {
  m.command = r.u16();
  m.result = r.u8();
  m.progress = r.u8();
  m.result_param2 = r.i32();
  m.target_system = r.u8();
  m.target_component = r.u8();
}

void write(Writer& w, const BatteryStatus& m) {
  w.i32(m.current_consumed);
  w.i32(m.energy_consumed);
  w.i16(m.temperature);
  for (std::uint16_t v : m.voltages) w.u16(v);
  w.i16(m.current_battery);
  w.u8(m.id);
  w.u8(m.battery_function);
  w.u8(m.type);
  w.i8(m.battery_remaining);
  w.i32(m.time_remaining);
  w.u8(m.charge_state);
  for (std::uint16_t v : m.voltages_ext) w.u16(v);
  w.u8(m.mode);
  w.u32(m.fault_bitmask);
}
void read(Reader& r, BatteryStatus& m) {
  m.current_consumed = r.i32();
  m.energy_consumed = r.i32();
  m.temperature = r.i16();
  for (std::uint16_t& v : m.voltages) v = r.u16();
  m.current_battery = r.i16();
  m.id = r.u8();
  m.battery_function = r.u8();
  m.type = r.u8();
  m.battery_remaining = r.i8();
  m.time_remaining = r.i32();
  m.charge_state = r.u8();
  for (std::uint16_t& v : m.voltages_ext) v = r.u16();
  m.mode = r.u8();
  m.fault_bitmask = r.u32();
}

void write(Writer& w, const StatusText& m) {
  w.u8(m.severity);
  for (char c : m.text) w.u8(static_cast<std::uint8_t>(c));
  w.u16(m.id);
  w.u8(m.chunk_seq);
}
void read(Reader& r, StatusText& m) {
  m.severity = r.u8();
  for (char& c : m.text) c = static_cast<char>(r.u8());
  m.id = r.u16();
  m.chunk_seq = r.u8();
}

template <typename M>
std::optional<Message> decode_as(std::span<const std::uint8_t> payload) {
  M m{};
  Reader r(payload);
  read(r, m);
  return Message{m};
}

}  // namespace

std::string_view StatusText::str() const {
  std::size_t n = 0;
  while (n < text.size() && text[n] != '\0') ++n;
  return {text.data(), n};
}

StatusText StatusText::make(std::uint8_t severity, std::string_view text) {
  StatusText m;
  m.severity = severity;
  const std::size_t n = std::min(text.size(), m.text.size());
  std::copy_n(text.begin(), n, m.text.begin());
  return m;
}

std::string_view mission_result_name(std::uint8_t result) {
  switch (result) {
    case kMissionAccepted:
      return "MAV_MISSION_ACCEPTED";
    case kMissionError:
      return "MAV_MISSION_ERROR";
    case kMissionUnsupportedFrame:
      return "MAV_MISSION_UNSUPPORTED_FRAME";
    case kMissionUnsupported:
      return "MAV_MISSION_UNSUPPORTED";
    case kMissionNoSpace:
      return "MAV_MISSION_NO_SPACE";
    case kMissionInvalid:
      return "MAV_MISSION_INVALID";
    case 6:
      return "MAV_MISSION_INVALID_PARAM1";
    case 7:
      return "MAV_MISSION_INVALID_PARAM2";
    case 8:
      return "MAV_MISSION_INVALID_PARAM3";
    case 9:
      return "MAV_MISSION_INVALID_PARAM4";
    case 10:
      return "MAV_MISSION_INVALID_PARAM5_X";
    case 11:
      return "MAV_MISSION_INVALID_PARAM6_Y";
    case 12:
      return "MAV_MISSION_INVALID_PARAM7";
    case kMissionInvalidSequence:
      return "MAV_MISSION_INVALID_SEQUENCE";
    case kMissionDenied:
      return "MAV_MISSION_DENIED";
    case kMissionOperationCancelled:
      return "MAV_MISSION_OPERATION_CANCELLED";
    default:
      return "MAV_MISSION_RESULT(unknown)";
  }
}

std::optional<MessageInfo> message_info(std::uint32_t msgid) {
  switch (msgid) {
    case Heartbeat::info.id:
      return Heartbeat::info;
    case MissionCount::info.id:
      return MissionCount::info;
    case MissionRequestInt::info.id:
      return MissionRequestInt::info;
    case MissionRequest::info.id:
      return MissionRequest::info;
    case MissionItemInt::info.id:
      return MissionItemInt::info;
    case MissionAck::info.id:
      return MissionAck::info;
    case MissionClearAll::info.id:
      return MissionClearAll::info;
    case MissionCurrent::info.id:
      return MissionCurrent::info;
    case MissionItemReached::info.id:
      return MissionItemReached::info;
    case SysStatus::info.id:
      return SysStatus::info;
    case GlobalPositionInt::info.id:
      return GlobalPositionInt::info;
    case CommandLong::info.id:
      return CommandLong::info;
    case CommandAck::info.id:
      return CommandAck::info;
    case BatteryStatus::info.id:
      return BatteryStatus::info;
    case StatusText::info.id:
      return StatusText::info;
    default:
      return std::nullopt;
  }
}

const MessageInfo& message_info(const Message& m) {
  return std::visit([](const auto& msg) -> const MessageInfo& { return std::decay_t<decltype(msg)>::info; },
                    m);
}

std::size_t encode_payload(const Message& m, PayloadBuffer& out) {
  Writer w(out);
  std::visit([&](const auto& msg) { write(w, msg); }, m);
  return w.size();
}

std::optional<Message> decode_payload(std::uint32_t msgid, std::span<const std::uint8_t> payload) {
  switch (msgid) {
    case Heartbeat::info.id:
      return decode_as<Heartbeat>(payload);
    case MissionCount::info.id:
      return decode_as<MissionCount>(payload);
    case MissionRequestInt::info.id:
      return decode_as<MissionRequestInt>(payload);
    case MissionRequest::info.id:
      return decode_as<MissionRequest>(payload);
    case MissionItemInt::info.id:
      return decode_as<MissionItemInt>(payload);
    case MissionAck::info.id:
      return decode_as<MissionAck>(payload);
    case MissionClearAll::info.id:
      return decode_as<MissionClearAll>(payload);
    case MissionCurrent::info.id:
      return decode_as<MissionCurrent>(payload);
    case MissionItemReached::info.id:
      return decode_as<MissionItemReached>(payload);
    case SysStatus::info.id:
      return decode_as<SysStatus>(payload);
    case GlobalPositionInt::info.id:
      return decode_as<GlobalPositionInt>(payload);
    case CommandLong::info.id:
      return decode_as<CommandLong>(payload);
    case CommandAck::info.id:
      return decode_as<CommandAck>(payload);
    case BatteryStatus::info.id:
      return decode_as<BatteryStatus>(payload);
    case StatusText::info.id:
      return decode_as<StatusText>(payload);
    default:
      return std::nullopt;
  }
}

}  // namespace uavcover::mavlink
