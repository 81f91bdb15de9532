#include "mavlink/messages.hpp"

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

template <typename M>
std::optional<Message> decode_as(std::span<const std::uint8_t> payload) {
  M m{};
  Reader r(payload);
  read(r, m);
  return Message{m};
}

}  // namespace

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
    default:
      return std::nullopt;
  }
}

}  // namespace uavcover::mavlink
