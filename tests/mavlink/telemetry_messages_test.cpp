// The telemetry and command messages (SYS_STATUS, GLOBAL_POSITION_INT, COMMAND_LONG, COMMAND_ACK,
// BATTERY_STATUS, STATUSTEXT): CRC_EXTRA re-derived from the common.xml field definitions, the
// published values, payload layout and round trips. node-mavlink decodes them in tests/sim.
#include <gtest/gtest.h>

#include <array>

#include "mavlink/crc.hpp"
#include "mavlink/frame.hpp"
#include "mavlink/messages.hpp"

using namespace uavcover::mavlink;

TEST(MavlinkTelemetry, CrcExtraDerivedFromFieldDefinitions) {
  // common.xml base fields in wire order (sorted by element size, stable); extensions left out.
  using F = FieldDef;
  const std::array sys_status{F{"uint32_t", "onboard_control_sensors_present"},
                              F{"uint32_t", "onboard_control_sensors_enabled"},
                              F{"uint32_t", "onboard_control_sensors_health"},
                              F{"uint16_t", "load"},
                              F{"uint16_t", "voltage_battery"},
                              F{"int16_t", "current_battery"},
                              F{"uint16_t", "drop_rate_comm"},
                              F{"uint16_t", "errors_comm"},
                              F{"uint16_t", "errors_count1"},
                              F{"uint16_t", "errors_count2"},
                              F{"uint16_t", "errors_count3"},
                              F{"uint16_t", "errors_count4"},
                              F{"int8_t", "battery_remaining"}};
  const std::array global_position{
      F{"uint32_t", "time_boot_ms"}, F{"int32_t", "lat"}, F{"int32_t", "lon"}, F{"int32_t", "alt"},
      F{"int32_t", "relative_alt"},  F{"int16_t", "vx"},  F{"int16_t", "vy"},  F{"int16_t", "vz"},
      F{"uint16_t", "hdg"}};
  const std::array command_long{F{"float", "param1"},          F{"float", "param2"},
                                F{"float", "param3"},          F{"float", "param4"},
                                F{"float", "param5"},          F{"float", "param6"},
                                F{"float", "param7"},          F{"uint16_t", "command"},
                                F{"uint8_t", "target_system"}, F{"uint8_t", "target_component"},
                                F{"uint8_t", "confirmation"}};
  const std::array command_ack{F{"uint16_t", "command"}, F{"uint8_t", "result"}};
  const std::array battery{F{"int32_t", "current_consumed"}, F{"int32_t", "energy_consumed"},
                           F{"int16_t", "temperature"},      F{"uint16_t", "voltages", 10},
                           F{"int16_t", "current_battery"},  F{"uint8_t", "id"},
                           F{"uint8_t", "battery_function"}, F{"uint8_t", "type"},
                           F{"int8_t", "battery_remaining"}};
  const std::array statustext{F{"uint8_t", "severity"}, F{"char", "text", 50}};
  EXPECT_EQ(derive_crc_extra("SYS_STATUS", sys_status), SysStatus::info.crc_extra);
  EXPECT_EQ(derive_crc_extra("GLOBAL_POSITION_INT", global_position), GlobalPositionInt::info.crc_extra);
  EXPECT_EQ(derive_crc_extra("COMMAND_LONG", command_long), CommandLong::info.crc_extra);
  EXPECT_EQ(derive_crc_extra("COMMAND_ACK", command_ack), CommandAck::info.crc_extra);
  EXPECT_EQ(derive_crc_extra("BATTERY_STATUS", battery), BatteryStatus::info.crc_extra);
  EXPECT_EQ(derive_crc_extra("STATUSTEXT", statustext), StatusText::info.crc_extra);
  // the published values (c_library_v2 MAVLINK_MESSAGE_CRCS, node-mavlink's MAGIC_NUMBER)
  EXPECT_EQ(SysStatus::info.crc_extra, 124);
  EXPECT_EQ(GlobalPositionInt::info.crc_extra, 104);
  EXPECT_EQ(CommandLong::info.crc_extra, 152);
  EXPECT_EQ(CommandAck::info.crc_extra, 143);
  EXPECT_EQ(BatteryStatus::info.crc_extra, 154);
  EXPECT_EQ(StatusText::info.crc_extra, 83);
}

TEST(MavlinkTelemetry, PayloadLengths) {
  PayloadBuffer buf{};
  EXPECT_EQ(encode_payload(SysStatus{}, buf), 43U);
  EXPECT_EQ(encode_payload(GlobalPositionInt{}, buf), 28U);
  EXPECT_EQ(encode_payload(CommandLong{}, buf), 33U);
  EXPECT_EQ(encode_payload(CommandAck{}, buf), 10U);
  EXPECT_EQ(encode_payload(BatteryStatus{}, buf), 54U);
  EXPECT_EQ(encode_payload(StatusText{}, buf), 54U);
  // GLOBAL_POSITION_INT: hdg is the last two bytes, lat the bytes 4..7
  GlobalPositionInt g;
  g.lat = 0x01020304;
  g.hdg = 0xA1B2;
  ASSERT_EQ(encode_payload(g, buf), 28U);
  EXPECT_EQ(buf[4], 0x04);
  EXPECT_EQ(buf[7], 0x01);
  EXPECT_EQ(buf[26], 0xB2);
  EXPECT_EQ(buf[27], 0xA1);
  // BATTERY_STATUS: battery_remaining at 35 (after the ten cell voltages), signed
  BatteryStatus b;
  b.battery_remaining = -1;
  b.voltages.fill(0);
  ASSERT_EQ(encode_payload(b, buf), 54U);
  EXPECT_EQ(buf[35], 0xFF);
}

TEST(MavlinkTelemetry, RoundTrips) {
  SysStatus s;
  s.onboard_control_sensors_present = 0x12345678;
  s.voltage_battery = 15800;
  s.current_battery = -1;
  s.battery_remaining = 87;
  s.onboard_control_sensors_health_extended = 7;
  GlobalPositionInt g{123456, -335000123, 1511234567, 45000, -250, -321, 1234, -5, 35999};
  CommandLong c{1.0F, 21196.0F, 0, 0, 0, 0, -7.5F, kCmdComponentArmDisarm, 3, 1, 2};
  CommandAck a{kCmdMissionStart, kResultDenied, 50, -9, 255, 190};
  BatteryStatus b;
  b.current_consumed = 1234;
  b.temperature = -500;
  b.voltages = {4200, 4190, 4180, 4170, 65535, 65535, 65535, 65535, 65535, 65535};
  b.battery_remaining = 42;
  b.time_remaining = 600;
  b.charge_state = 2;
  b.voltages_ext = {1, 2, 3, 4};
  b.fault_bitmask = 0x80000001;
  const StatusText t = StatusText::make(kSeverityWarning, "battery low: 20 %");
  EXPECT_EQ(t.str(), "battery low: 20 %");
  const StatusText full = StatusText::make(kSeverityInfo, std::string(60, 'x'));
  EXPECT_EQ(full.str().size(), 50U);
  std::uint8_t seq = 0;
  for (const Message& m : std::vector<Message>{s, g, c, a, b, t, full, SysStatus{}, BatteryStatus{}}) {
    SCOPED_TRACE(std::string(message_info(m).name));
    const auto bytes = encode(m, Header{seq++, 7, 1, 0, 0});
    Parser p;
    std::vector<Frame> frames;
    p.push(bytes, frames, true);
    ASSERT_EQ(frames.size(), 1U);
    const auto back = decode(frames[0]);
    ASSERT_TRUE(back);
    EXPECT_EQ(*back, m);
  }
}
