// SHA-256 (FIPS 180-4): the keys of the content-addressed artifact blobs.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace uavcover::store {

/// The 32-byte digest of `bytes`.
std::array<std::uint8_t, 32> sha256(std::string_view bytes);
/// The digest as 64 lower-case hex digits.
std::string sha256_hex(std::string_view bytes);

}  // namespace uavcover::store
