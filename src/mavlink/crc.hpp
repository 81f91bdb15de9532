// CRC-16/MCRF4XX (the "X.25" checksum MAVLink uses): poly 0x1021 reflected, init 0xFFFF, no final xor.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace uavcover::mavlink {

inline constexpr std::uint16_t kCrcInit = 0xFFFF;

/// Folds one byte into the running checksum (MAVLink's crc_accumulate).
constexpr std::uint16_t crc_accumulate(std::uint8_t byte, std::uint16_t crc) {
  std::uint8_t tmp = static_cast<std::uint8_t>(byte ^ static_cast<std::uint8_t>(crc & 0xFF));
  tmp = static_cast<std::uint8_t>(tmp ^ static_cast<std::uint8_t>(tmp << 4));
  return static_cast<std::uint16_t>((crc >> 8) ^ (static_cast<std::uint16_t>(tmp) << 8) ^
                                    (static_cast<std::uint16_t>(tmp) << 3) ^ (tmp >> 4));
}

constexpr std::uint16_t crc_accumulate(std::span<const std::uint8_t> bytes, std::uint16_t crc = kCrcInit) {
  for (std::uint8_t b : bytes) crc = crc_accumulate(b, crc);
  return crc;
}

constexpr std::uint16_t crc_accumulate(std::string_view text, std::uint16_t crc = kCrcInit) {
  for (char c : text) crc = crc_accumulate(static_cast<std::uint8_t>(c), crc);
  return crc;
}

/// One field of a message definition as common.xml gives it (for deriving CRC_EXTRA).
struct FieldDef {
  std::string_view type;  ///< C type without array suffix, e.g. "uint16_t"
  std::string_view name;
  std::uint8_t array_length = 0;
};

/// CRC_EXTRA as mavgen derives it: the checksum over "NAME " and, for every non-extension field in
/// wire order, "type name " (plus the array length byte), folded to 8 bits.
/// `wire_order_fields` must already be sorted by type size (largest first, stable), extensions omitted.
template <typename Range>
constexpr std::uint8_t derive_crc_extra(std::string_view message_name, const Range& wire_order_fields) {
  std::uint16_t crc = crc_accumulate(message_name);
  crc = crc_accumulate(static_cast<std::uint8_t>(' '), crc);
  for (const FieldDef& f : wire_order_fields) {
    crc = crc_accumulate(f.type, crc);
    crc = crc_accumulate(static_cast<std::uint8_t>(' '), crc);
    crc = crc_accumulate(f.name, crc);
    crc = crc_accumulate(static_cast<std::uint8_t>(' '), crc);
    if (f.array_length != 0) crc = crc_accumulate(f.array_length, crc);
  }
  return static_cast<std::uint8_t>((crc & 0xFF) ^ (crc >> 8));
}

}  // namespace uavcover::mavlink
