#include "mavlink/frame.hpp"

#include <algorithm>

#include "mavlink/crc.hpp"

namespace uavcover::mavlink {

std::vector<std::uint8_t> encode_frame(const Header& header, std::uint32_t msgid, std::uint8_t crc_extra,
                                       std::span<const std::uint8_t> payload) {
  std::size_t len = std::min(payload.size(), kMaxPayload);
  while (len > 1 && payload[len - 1] == 0) --len;  // MAVLink 2 truncation; the first byte stays
  std::vector<std::uint8_t> out;
  out.reserve(10 + len + 2);
  out.push_back(kStxV2);
  out.push_back(static_cast<std::uint8_t>(len));
  out.push_back(static_cast<std::uint8_t>(header.incompat_flags & ~kIncompatSigned));  // we never sign
  out.push_back(header.compat_flags);
  out.push_back(header.seq);
  out.push_back(header.sysid);
  out.push_back(header.compid);
  out.push_back(static_cast<std::uint8_t>(msgid & 0xFF));
  out.push_back(static_cast<std::uint8_t>((msgid >> 8) & 0xFF));
  out.push_back(static_cast<std::uint8_t>((msgid >> 16) & 0xFF));
  out.insert(out.end(), payload.begin(), payload.begin() + static_cast<std::ptrdiff_t>(len));
  std::uint16_t crc = crc_accumulate(std::span<const std::uint8_t>(out).subspan(1));
  crc = crc_accumulate(crc_extra, crc);
  out.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  out.push_back(static_cast<std::uint8_t>(crc >> 8));
  return out;
}

std::vector<std::uint8_t> encode(const Message& message, const Header& header) {
  PayloadBuffer buf{};
  const std::size_t n = encode_payload(message, buf);
  const MessageInfo& info = message_info(message);
  return encode_frame(header, info.id, info.crc_extra, std::span<const std::uint8_t>(buf.data(), n));
}

std::optional<Message> decode(const Frame& frame) { return decode_payload(frame.msgid, frame.payload); }

void Parser::drop_front(std::size_t n, bool skipped) {
  start_ += n;
  if (skipped) stats_.bytes_skipped += n;
  if (start_ > 4096 && start_ * 2 > buf_.size()) {  // compact now and then
    buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(start_));
    start_ = 0;
  }
}

Parser::Step Parser::try_frame(std::vector<Frame>& out) {
  const std::uint8_t* p = buf_.data() + start_;
  const std::size_t avail = buf_.size() - start_;
  const bool v2 = p[0] == kStxV2;
  const std::size_t header_len = v2 ? 10 : 6;
  if (avail < header_len) return Step::NeedMore;
  const std::size_t len = p[1];
  std::size_t total = header_len + len + 2;
  Frame f;
  f.version = v2 ? 2 : 1;
  if (v2) {
    f.header.incompat_flags = p[2];
    f.header.compat_flags = p[3];
    f.header.seq = p[4];
    f.header.sysid = p[5];
    f.header.compid = p[6];
    f.msgid = static_cast<std::uint32_t>(p[7]) | (static_cast<std::uint32_t>(p[8]) << 8) |
              (static_cast<std::uint32_t>(p[9]) << 16);
    if ((f.header.incompat_flags & ~kIncompatSigned) != 0) {
      ++stats_.bad_flags;
      return Step::Rejected;
    }
    if (f.header.incompat_flags & kIncompatSigned) total += kSignatureLength;
  } else {
    f.header.seq = p[2];
    f.header.sysid = p[3];
    f.header.compid = p[4];
    f.msgid = p[5];
  }
  if (avail < total) return Step::NeedMore;
  const auto info = message_info(f.msgid);
  if (!info) {
    ++stats_.unknown_msgid;
    return Step::Rejected;
  }
  std::uint16_t crc = crc_accumulate(std::span<const std::uint8_t>(p + 1, header_len - 1 + len));
  crc = crc_accumulate(info->crc_extra, crc);
  const std::uint16_t got = static_cast<std::uint16_t>(p[header_len + len] | (p[header_len + len + 1] << 8));
  if (crc != got || (!v2 && len < info->min_length)) {
    ++stats_.crc_errors;
    return Step::Rejected;
  }
  f.payload.assign(p + header_len, p + header_len + len);
  out.push_back(std::move(f));
  ++stats_.frames;
  drop_front(total, false);
  return Step::Accepted;
}

namespace {

// The length of a complete frame at `p` with supported flags, a known msgid and a valid checksum; 0 if
// there is none (incomplete, or not a frame).
std::size_t valid_frame_length(const std::uint8_t* p, std::size_t avail) {
  const bool v2 = p[0] == kStxV2;
  const std::size_t header_len = v2 ? 10 : 6;
  if (avail < header_len) return 0;
  const std::size_t len = p[1];
  std::size_t total = header_len + len + 2;
  std::uint32_t msgid = p[5];
  if (v2) {
    if ((p[2] & ~kIncompatSigned) != 0) return 0;
    if (p[2] & kIncompatSigned) total += kSignatureLength;
    msgid = static_cast<std::uint32_t>(p[7]) | (static_cast<std::uint32_t>(p[8]) << 8) |
            (static_cast<std::uint32_t>(p[9]) << 16);
  }
  if (avail < total) return 0;
  const auto info = message_info(msgid);
  if (!info || (!v2 && len < info->min_length)) return 0;
  std::uint16_t crc = crc_accumulate(std::span<const std::uint8_t>(p + 1, header_len - 1 + len));
  crc = crc_accumulate(info->crc_extra, crc);
  const auto got = static_cast<std::uint16_t>(p[header_len + len] | (p[header_len + len + 1] << 8));
  return crc == got ? total : 0;
}

}  // namespace

std::size_t Parser::later_valid_frame() const {
  for (std::size_t pos = start_ + 1; pos < buf_.size(); ++pos)
    if ((buf_[pos] == kStxV2 || buf_[pos] == kStxV1) &&
        valid_frame_length(buf_.data() + pos, buf_.size() - pos) > 0)
      return pos;
  return 0;
}

void Parser::push(std::span<const std::uint8_t> bytes, std::vector<Frame>& out, bool end_of_input) {
  buf_.insert(buf_.end(), bytes.begin(), bytes.end());
  while (start_ < buf_.size()) {
    // skip to the next start byte
    const auto first = std::find_if(buf_.begin() + static_cast<std::ptrdiff_t>(start_), buf_.end(),
                                    [](std::uint8_t b) { return b == kStxV2 || b == kStxV1; });
    const auto skip = static_cast<std::size_t>(first - buf_.begin()) - start_;
    if (skip > 0) drop_front(skip, true);
    if (start_ >= buf_.size()) break;
    const Step step = try_frame(out);
    if (step == Step::Accepted) continue;
    if (step == Step::NeedMore && !end_of_input) {
      // On a byte stream a false start byte would hold back the frames behind it until its claimed
      // length has arrived (up to 280 bytes): when a complete, checksum-valid frame starts inside that
      // span, the candidate was garbage.
      const std::size_t next = later_valid_frame();
      if (next == 0) break;
      drop_front(next - start_, true);
      continue;
    }
    drop_front(1, true);  // rejected (or incomplete at the end of input): resume after the start byte
  }
  if (start_ == buf_.size()) {
    buf_.clear();
    start_ = 0;
  }
}

}  // namespace uavcover::mavlink
