// Helpers shared by the MAVLink tests.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "mavlink/mission_protocol.hpp"

namespace mavtest {

inline std::string to_hex(const std::vector<std::uint8_t>& bytes) {
  static const char* digits = "0123456789abcdef";
  std::string s;
  for (std::uint8_t b : bytes) {
    s += digits[b >> 4];
    s += digits[b & 15];
  }
  return s;
}

inline std::vector<std::uint8_t> from_hex(std::string_view hex) {
  std::vector<std::uint8_t> out;
  auto nibble = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  int hi = -1;
  for (char c : hex) {
    const int v = nibble(c);
    if (v < 0) continue;
    if (hi < 0) {
      hi = v;
    } else {
      out.push_back(static_cast<std::uint8_t>(hi * 16 + v));
      hi = -1;
    }
  }
  return out;
}

// What the vehicle stored must be what we sent (seq, addressing and payload).
inline void expect_same_items(const std::vector<uavcover::mavlink::MissionItemInt>& got,
                              const std::vector<uavcover::mavlink::MissionItemInt>& sent,
                              std::uint8_t target_system) {
  ASSERT_EQ(got.size(), sent.size());
  for (std::size_t i = 0; i < sent.size(); ++i) {
    uavcover::mavlink::MissionItemInt want = sent[i];
    want.seq = static_cast<std::uint16_t>(i);
    want.target_system = target_system;
    want.target_component = 1;
    EXPECT_EQ(got[i], want) << "item " << i;
  }
}

}  // namespace mavtest
