// MAVLink 2 framing (encoder) and a streaming parser for MAVLink 2 and 1 frames.
//
// MAVLink 2 frame: 0xFD, len, incompat_flags, compat_flags, seq, sysid, compid, msgid (24 bit LE),
// payload (trailing zero bytes truncated, at least one byte kept), checksum (CRC-16/MCRF4XX over
// everything after the start byte, then CRC_EXTRA), and 13 signature bytes when incompat bit 0 is set.
// MAVLink 1 frame: 0xFE, len, seq, sysid, compid, msgid (8 bit), payload, checksum.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "mavlink/messages.hpp"

namespace uavcover::mavlink {

inline constexpr std::uint8_t kStxV2 = 0xFD;
inline constexpr std::uint8_t kStxV1 = 0xFE;
inline constexpr std::uint8_t kIncompatSigned = 0x01;
inline constexpr std::size_t kSignatureLength = 13;

struct Header {
  std::uint8_t seq = 0;
  std::uint8_t sysid = 0;
  std::uint8_t compid = 0;
  std::uint8_t incompat_flags = 0;
  std::uint8_t compat_flags = 0;
};

/// A frame that passed the checksum test.
struct Frame {
  int version = 2;
  Header header;
  std::uint32_t msgid = 0;
  std::vector<std::uint8_t> payload;  ///< as received (maybe truncated)
};

/// Encodes a MAVLink 2 frame around `payload` (truncating trailing zeros, keeping one byte).
std::vector<std::uint8_t> encode_frame(const Header& header, std::uint32_t msgid, std::uint8_t crc_extra,
                                       std::span<const std::uint8_t> payload);

/// Encodes a message as a MAVLink 2 frame.
std::vector<std::uint8_t> encode(const Message& message, const Header& header);

/// Decodes a frame's payload into a message (nullopt for a message this codec does not know).
std::optional<Message> decode(const Frame& frame);

/// Streaming parser. Bytes may arrive in any split; garbage between frames is skipped. A candidate
/// frame whose checksum fails (or whose msgid is unknown, so it cannot be checked, or whose
/// incompatibility flags are not supported) is rejected and the search resumes one byte after its
/// start byte, so a real frame hidden behind a false start byte is still found. An incomplete candidate
/// is given up as soon as a complete frame with a valid checksum starts after its start byte (a TCP or
/// serial stream does not wait for a false start's claimed length to arrive).
class Parser {
 public:
  struct Stats {
    std::size_t frames = 0;         ///< accepted
    std::size_t crc_errors = 0;     ///< candidates with a known msgid and a wrong checksum
    std::size_t unknown_msgid = 0;  ///< candidates whose msgid is not in this codec
    std::size_t bad_flags = 0;      ///< unsupported incompatibility flags
    std::size_t bytes_skipped = 0;  ///< bytes discarded while resynchronising
  };

  /// Feeds bytes; appends every complete valid frame to `out`. With `end_of_input` (e.g. the end
  /// of a UDP datagram) a trailing incomplete candidate is treated as garbage instead of awaited.
  void push(std::span<const std::uint8_t> bytes, std::vector<Frame>& out, bool end_of_input = false);

  [[nodiscard]] const Stats& stats() const { return stats_; }
  [[nodiscard]] std::size_t buffered() const { return buf_.size() - start_; }

 private:
  enum class Step { NeedMore, Rejected, Accepted };
  Step try_frame(std::vector<Frame>& out);
  void drop_front(std::size_t n, bool skipped);
  /// Where a complete valid frame starts after start_ (0: nowhere).
  [[nodiscard]] std::size_t later_valid_frame() const;

  std::vector<std::uint8_t> buf_;
  std::size_t start_ = 0;
  Stats stats_;
};

}  // namespace uavcover::mavlink
