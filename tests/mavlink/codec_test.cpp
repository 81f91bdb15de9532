// MAVLink 2 codec: golden frame, CRC, CRC_EXTRA derivation, round trips, truncation, parser resync.
#include <gtest/gtest.h>

#include <array>
#include <random>

#include "mavlink/crc.hpp"
#include "mavlink/frame.hpp"
#include "mavlink/messages.hpp"
#include "mavlink/test_util.hpp"

using namespace uavcover::mavlink;

namespace {

// The golden frame (made by node-mavlink).
constexpr std::string_view kGolden =
    "fd25000007ffbe490000000000000000000000000000000000004c52401c44f417050000a041010010000101030001f298";

MissionItemInt golden_item() {
  MissionItemInt m;
  m.seq = 1;
  m.frame = 3;
  m.command = 16;
  m.x = 473977420;
  m.y = 85455940;
  m.z = 20.0F;
  m.target_system = 1;
  m.target_component = 1;
  m.autocontinue = 1;
  return m;
}

Header golden_header() { return Header{7, 255, 190, 0, 0}; }

std::vector<Frame> parse_all(const std::vector<std::uint8_t>& bytes, Parser* parser_out = nullptr) {
  Parser p;
  std::vector<Frame> frames;
  p.push(bytes, frames, true);
  if (parser_out) *parser_out = p;
  return frames;
}

// One non-trivial instance of every message (extension fields set too).
std::vector<Message> samples() {
  MissionItemInt item = golden_item();
  item.param1 = 1.5F;
  item.param2 = -2.25F;
  item.param3 = 3.0e6F;
  item.param4 = -0.0F;
  item.current = 1;
  item.mission_type = 2;
  item.x = -473977420;
  item.y = 2147483647;
  item.z = -12.5F;
  return {
      Heartbeat{0xDEADBEEF, 2, 3, 0x81, 4, 3},
      MissionCount{1, 1, 0xBEEF, 1, 0x01020304},
      MissionRequestInt{255, 190, 65535, 2},
      MissionRequest{255, 190, 258, 1},
      item,
      MissionAck{255, 190, kMissionNoSpace, 1, 0xCAFEBABE},
      MissionClearAll{1, 1, 2},
      MissionCurrent{17, 42, 3, 1, 0x11223344, 0x55667788, 0x99AABBCC},
      MissionItemReached{0x1234},
  };
}

}  // namespace

TEST(MavlinkCrc, Mcrf4xxCheckValue) {
  // CRC-16/MCRF4XX catalogue check value over "123456789".
  EXPECT_EQ(crc_accumulate(std::string_view("123456789")), 0x6F91);
}

TEST(MavlinkCrc, CrcExtraDerivedFromFieldDefinitions) {
  // Field lists transcribed from minimal.xml/common.xml, already in wire order (sorted by size,
  // stable), extensions left out: CRC_EXTRA covers base fields only.
  using F = FieldDef;
  const std::array heartbeat{F{"uint32_t", "custom_mode"},  F{"uint8_t", "type"},
                             F{"uint8_t", "autopilot"},     F{"uint8_t", "base_mode"},
                             F{"uint8_t", "system_status"}, F{"uint8_t", "mavlink_version"}};
  const std::array count{F{"uint16_t", "count"}, F{"uint8_t", "target_system"},
                         F{"uint8_t", "target_component"}};
  const std::array request{F{"uint16_t", "seq"}, F{"uint8_t", "target_system"},
                           F{"uint8_t", "target_component"}};
  const std::array item{F{"float", "param1"},
                        F{"float", "param2"},
                        F{"float", "param3"},
                        F{"float", "param4"},
                        F{"int32_t", "x"},
                        F{"int32_t", "y"},
                        F{"float", "z"},
                        F{"uint16_t", "seq"},
                        F{"uint16_t", "command"},
                        F{"uint8_t", "target_system"},
                        F{"uint8_t", "target_component"},
                        F{"uint8_t", "frame"},
                        F{"uint8_t", "current"},
                        F{"uint8_t", "autocontinue"}};
  const std::array ack{F{"uint8_t", "target_system"}, F{"uint8_t", "target_component"}, F{"uint8_t", "type"}};
  const std::array clear{F{"uint8_t", "target_system"}, F{"uint8_t", "target_component"}};
  const std::array seq_only{F{"uint16_t", "seq"}};

  EXPECT_EQ(derive_crc_extra("HEARTBEAT", heartbeat), Heartbeat::info.crc_extra);
  EXPECT_EQ(derive_crc_extra("MISSION_COUNT", count), MissionCount::info.crc_extra);
  EXPECT_EQ(derive_crc_extra("MISSION_REQUEST_INT", request), MissionRequestInt::info.crc_extra);
  EXPECT_EQ(derive_crc_extra("MISSION_REQUEST", request), MissionRequest::info.crc_extra);
  EXPECT_EQ(derive_crc_extra("MISSION_ITEM_INT", item), MissionItemInt::info.crc_extra);
  EXPECT_EQ(derive_crc_extra("MISSION_ACK", ack), MissionAck::info.crc_extra);
  EXPECT_EQ(derive_crc_extra("MISSION_CLEAR_ALL", clear), MissionClearAll::info.crc_extra);
  EXPECT_EQ(derive_crc_extra("MISSION_CURRENT", seq_only), MissionCurrent::info.crc_extra);
  EXPECT_EQ(derive_crc_extra("MISSION_ITEM_REACHED", seq_only), MissionItemReached::info.crc_extra);
  // and the published values (c_library_v2 MAVLINK_MESSAGE_CRCS)
  EXPECT_EQ(Heartbeat::info.crc_extra, 50);
  EXPECT_EQ(MissionCurrent::info.crc_extra, 28);
  EXPECT_EQ(MissionCount::info.crc_extra, 221);
  EXPECT_EQ(MissionClearAll::info.crc_extra, 232);
  EXPECT_EQ(MissionItemReached::info.crc_extra, 11);
  EXPECT_EQ(MissionAck::info.crc_extra, 153);
  EXPECT_EQ(MissionRequestInt::info.crc_extra, 196);
  EXPECT_EQ(MissionRequest::info.crc_extra, 230);
  EXPECT_EQ(MissionItemInt::info.crc_extra, 38);
}

TEST(MavlinkCodec, GoldenMissionItemIntFrame) {
  const auto frame = encode(golden_item(), golden_header());
  EXPECT_EQ(mavtest::to_hex(frame), kGolden);
}

TEST(MavlinkCodec, GoldenFrameDecodes) {
  Parser p;
  const auto frames = parse_all(mavtest::from_hex(kGolden), &p);
  ASSERT_EQ(frames.size(), 1U);
  EXPECT_EQ(frames[0].version, 2);
  EXPECT_EQ(frames[0].header.seq, 7);
  EXPECT_EQ(frames[0].header.sysid, 255);
  EXPECT_EQ(frames[0].header.compid, 190);
  EXPECT_EQ(frames[0].msgid, 73U);
  EXPECT_EQ(frames[0].payload.size(), 37U);  // mission_type = 0 truncated
  const auto msg = decode(frames[0]);
  ASSERT_TRUE(msg);
  ASSERT_TRUE(std::holds_alternative<MissionItemInt>(*msg));
  EXPECT_EQ(std::get<MissionItemInt>(*msg), golden_item());
  EXPECT_EQ(p.stats().crc_errors, 0U);
}

TEST(MavlinkCodec, PayloadLayoutIsSortedBySize) {
  PayloadBuffer buf{};
  ASSERT_EQ(encode_payload(MissionCount{0x11, 0x22, 0x3344, 0x55, 0x66778899}, buf), 9U);
  const std::vector<std::uint8_t> want{0x44, 0x33, 0x11, 0x22, 0x55, 0x99, 0x88, 0x77, 0x66};
  EXPECT_EQ(std::vector<std::uint8_t>(buf.begin(), buf.begin() + 9), want);
  ASSERT_EQ(encode_payload(Heartbeat{0x01020304, 5, 6, 7, 8, 3}, buf), 9U);
  const std::vector<std::uint8_t> hb{0x04, 0x03, 0x02, 0x01, 5, 6, 7, 8, 3};
  EXPECT_EQ(std::vector<std::uint8_t>(buf.begin(), buf.begin() + 9), hb);
}

TEST(MavlinkCodec, RoundTripEveryMessage) {
  std::uint8_t seq = 0;
  for (const Message& m : samples()) {
    const MessageInfo& info = message_info(m);
    SCOPED_TRACE(std::string(info.name));
    const Header h{seq++, 42, 99, 0, 0};
    const auto bytes = encode(m, h);
    EXPECT_EQ(bytes[0], kStxV2);
    EXPECT_LE(bytes[1], info.max_length);
    EXPECT_EQ(bytes.size(), 12U + bytes[1]);
    const auto frames = parse_all(bytes);
    ASSERT_EQ(frames.size(), 1U);
    EXPECT_EQ(frames[0].msgid, info.id);
    EXPECT_EQ(frames[0].header.seq, h.seq);
    EXPECT_EQ(frames[0].header.sysid, 42);
    EXPECT_EQ(frames[0].header.compid, 99);
    const auto back = decode(frames[0]);
    ASSERT_TRUE(back);
    EXPECT_EQ(*back, m);
  }
}

TEST(MavlinkCodec, RoundTripDefaultsAndTruncation) {
  // All-zero payloads keep one byte (MAVLink 2 never truncates the first payload byte).
  for (const Message& m :
       std::vector<Message>{Heartbeat{0, 0, 0, 0, 0, 0}, MissionCount{}, MissionRequestInt{},
                            MissionRequest{}, MissionItemInt{0, 0, 0, 0, 0, 0, 0}, MissionAck{},
                            MissionClearAll{}, MissionCurrent{}, MissionItemReached{}}) {
    const MessageInfo& info = message_info(m);
    SCOPED_TRACE(std::string(info.name));
    const auto bytes = encode(m, Header{});
    EXPECT_EQ(bytes[1], 1U);
    const auto frames = parse_all(bytes);
    ASSERT_EQ(frames.size(), 1U);
    EXPECT_EQ(*decode(frames[0]), m);
  }
  // Only trailing zeros go: a zero in the middle stays.
  MissionCurrent cur{5, 0, 0, 0, 0, 0, 7};
  EXPECT_EQ(encode(cur, Header{})[1], 15U);  // rally_points_id = 7 is byte 14; 15..17 are zero
  cur.rally_points_id = 0;
  EXPECT_EQ(encode(cur, Header{})[1], 1U);
}

TEST(MavlinkCodec, LongerPayloadFromNewerDialectDecodes) {
  // A peer knowing more extension fields may send more bytes: they are ignored, checksum still holds.
  PayloadBuffer buf{};
  const std::size_t n = encode_payload(MissionRequestInt{1, 2, 300, 0}, buf);
  buf[n] = 0xAB;  // an unknown extension byte
  const auto bytes = encode_frame(Header{}, MissionRequestInt::info.id, MissionRequestInt::info.crc_extra,
                                  std::span<const std::uint8_t>(buf.data(), n + 1));
  const auto frames = parse_all(bytes);
  ASSERT_EQ(frames.size(), 1U);
  EXPECT_EQ(std::get<MissionRequestInt>(*decode(frames[0])), (MissionRequestInt{1, 2, 300, 0}));
}

TEST(MavlinkParser, RejectsBadCrcAndCorruptedBytes) {
  auto bytes = mavtest::from_hex(kGolden);
  for (std::size_t i = 1; i < bytes.size(); ++i) {
    auto bad = bytes;
    bad[i] ^= 0x10;
    Parser p;
    std::vector<Frame> frames;
    p.push(bad, frames, true);
    // A flipped length byte may make the frame look incomplete; anything else fails the checksum.
    EXPECT_TRUE(frames.empty()) << "flipped byte " << i;
  }
  auto bad = bytes;
  bad.back() ^= 0x01;
  Parser p;
  std::vector<Frame> frames;
  p.push(bad, frames, true);
  EXPECT_TRUE(frames.empty());
  EXPECT_EQ(p.stats().crc_errors, 1U);
}

TEST(MavlinkParser, ResyncsOnGarbageAndFalseStartBytes) {
  const auto good = encode(golden_item(), golden_header());
  const auto ack = encode(MissionAck{255, 190, 0, 0, 0}, Header{3, 1, 1, 0, 0});
  std::vector<std::uint8_t> stream{0x00, 0x13, 0x37, 0xFD, 0x05, 0x00};  // garbage with a false v2 start
  stream.insert(stream.end(), good.begin(), good.end());
  stream.insert(stream.end(), {0xFE, 0xFE, 0x99});  // false v1 starts
  stream.insert(stream.end(), ack.begin(), ack.end());
  // A false start whose length swallows the next real frame: found again after rewinding.
  stream.insert(stream.end(), {0xFD, 0xF0, 0x00, 0x00, 0x00, 0x01, 0x01, 0x49, 0x00, 0x00});
  stream.insert(stream.end(), good.begin(), good.end());
  stream.insert(stream.end(), ack.begin(), ack.end());
  for (std::size_t i = 0; i < 250; ++i) stream.push_back(static_cast<std::uint8_t>(i * 7));
  stream.insert(stream.end(), ack.begin(), ack.end());

  // Whole stream, then the same stream split at every position.
  std::vector<std::size_t> splits{stream.size()};
  for (std::size_t s = 1; s < stream.size(); s += 3) splits.push_back(s);
  for (std::size_t split : splits) {
    Parser p;
    std::vector<Frame> frames;
    p.push(std::span(stream).first(split), frames, false);
    p.push(std::span(stream).subspan(split), frames, true);
    ASSERT_EQ(frames.size(), 5U) << "split " << split;
    EXPECT_EQ(frames[0].msgid, 73U);
    EXPECT_EQ(frames[1].msgid, 47U);
    EXPECT_EQ(frames[2].msgid, 73U);
    EXPECT_EQ(frames[3].msgid, 47U);
    EXPECT_EQ(frames[4].msgid, 47U);
    EXPECT_EQ(std::get<MissionItemInt>(*decode(frames[2])), golden_item());
    EXPECT_EQ(p.buffered(), 0U);
  }
}

// Issue 34 (TCP, serial): a false start byte whose claimed length swallows the frames behind it does not
// hold them back until that many bytes have arrived: they come out of the same push.
TEST(MavlinkParser, AFalseStartDoesNotHoldBackTheFramesBehindItOnAStream) {
  const auto ack = encode(MissionAck{255, 190, 0, 0, 0}, Header{3, 1, 1, 0, 0});
  const auto good = encode(golden_item(), golden_header());
  for (const std::vector<std::uint8_t>& false_start :
       {std::vector<std::uint8_t>{0xFE, 0xFD}, std::vector<std::uint8_t>{0xFD, 0xF0, 0x00, 0x00}}) {
    std::vector<std::uint8_t> stream = false_start;  // v1 start claiming 253 bytes; v2 claiming 240
    stream.insert(stream.end(), ack.begin(), ack.end());
    stream.insert(stream.end(), good.begin(), good.end());
    Parser p;
    std::vector<Frame> frames;
    p.push(stream, frames, false);  // not the end of the input: more bytes may come
    ASSERT_EQ(frames.size(), 2U);
    EXPECT_EQ(frames[0].msgid, 47U);
    EXPECT_EQ(frames[1].msgid, 73U);
    EXPECT_EQ(p.buffered(), 0U);
    EXPECT_EQ(p.stats().bytes_skipped, false_start.size());
  }
  // a real frame split across pushes is still awaited (nothing valid follows its start)
  Parser p;
  std::vector<Frame> frames;
  p.push(std::span(good).first(good.size() - 1), frames, false);
  EXPECT_TRUE(frames.empty());
  EXPECT_EQ(p.buffered(), good.size() - 1);
  p.push(std::span(good).last(1), frames, false);
  ASSERT_EQ(frames.size(), 1U);
  EXPECT_EQ(std::get<MissionItemInt>(*decode(frames[0])), golden_item());
}

TEST(MavlinkParser, RandomGarbageBetweenFrames) {
  std::mt19937 rng(12345);
  std::vector<std::uint8_t> stream;
  std::vector<Message> sent;
  const auto msgs = samples();
  for (int i = 0; i < 300; ++i) {
    const std::size_t garbage = rng() % 40;
    for (std::size_t g = 0; g < garbage; ++g) {
      // plenty of start bytes among the garbage
      const std::uint32_t r = rng();
      stream.push_back(r % 5 == 0 ? kStxV2 : r % 7 == 0 ? kStxV1 : static_cast<std::uint8_t>(r >> 8));
    }
    const Message& m = msgs[rng() % msgs.size()];
    const auto f = encode(m, Header{static_cast<std::uint8_t>(i), 1, 1, 0, 0});
    stream.insert(stream.end(), f.begin(), f.end());
    sent.push_back(m);
  }
  Parser p;
  std::vector<Frame> frames;
  for (std::size_t pos = 0; pos < stream.size();) {  // random chunking
    const std::size_t n = std::min<std::size_t>(1 + rng() % 64, stream.size() - pos);
    p.push(std::span(stream).subspan(pos, n), frames, false);
    pos += n;
  }
  p.push({}, frames, true);
  // Every frame sent is found, in order (a garbage-made frame would need a valid checksum).
  std::vector<Message> got;
  for (const auto& f : frames) got.push_back(*decode(f));
  ASSERT_EQ(got.size(), sent.size());
  EXPECT_EQ(got, sent);
  EXPECT_GT(p.stats().bytes_skipped, 0U);
}

TEST(MavlinkParser, AcceptsMavlink1AndSignedFramesRejectsUnknownFlags) {
  // MAVLink 1 MISSION_ACK built by hand: FE len seq sys comp msgid payload crc
  std::vector<std::uint8_t> v1{kStxV1, 3, 9, 1, 1, 47, 255, 190, kMissionInvalidSequence};
  std::uint16_t crc = crc_accumulate(std::span<const std::uint8_t>(v1).subspan(1));
  crc = crc_accumulate(MissionAck::info.crc_extra, crc);
  v1.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  v1.push_back(static_cast<std::uint8_t>(crc >> 8));
  auto frames = parse_all(v1);
  ASSERT_EQ(frames.size(), 1U);
  EXPECT_EQ(frames[0].version, 1);
  EXPECT_EQ(std::get<MissionAck>(*decode(frames[0])).type, kMissionInvalidSequence);

  // Signed v2 frame: flag set, checksum over the flagged header, 13 signature bytes after it.
  auto signed_frame = encode(MissionItemReached{77}, Header{1, 1, 1, 0, 0});
  signed_frame[2] = kIncompatSigned;
  signed_frame.resize(signed_frame.size() - 2);
  crc = crc_accumulate(std::span<const std::uint8_t>(signed_frame).subspan(1));
  crc = crc_accumulate(MissionItemReached::info.crc_extra, crc);
  signed_frame.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  signed_frame.push_back(static_cast<std::uint8_t>(crc >> 8));
  for (int i = 0; i < 13; ++i) signed_frame.push_back(static_cast<std::uint8_t>(0xA0 + i));
  const auto after = encode(MissionItemReached{78}, Header{2, 1, 1, 0, 0});
  signed_frame.insert(signed_frame.end(), after.begin(), after.end());
  frames = parse_all(signed_frame);
  ASSERT_EQ(frames.size(), 2U);
  EXPECT_EQ(std::get<MissionItemReached>(*decode(frames[0])).seq, 77);
  EXPECT_EQ(std::get<MissionItemReached>(*decode(frames[1])).seq, 78);

  // Unknown incompatibility flag: must be dropped.
  auto weird = encode(MissionItemReached{79}, Header{});
  weird[2] = 0x02;
  Parser p;
  frames = parse_all(weird, &p);
  EXPECT_TRUE(frames.empty());
  EXPECT_EQ(p.stats().bad_flags, 1U);

  // Unknown message id: skipped, the next frame still found.
  auto unknown = encode_frame(Header{}, 30, 39, std::vector<std::uint8_t>(28, 1));  // ATTITUDE
  unknown.insert(unknown.end(), after.begin(), after.end());
  frames = parse_all(unknown, &p);
  ASSERT_EQ(frames.size(), 1U);
  EXPECT_EQ(frames[0].msgid, MissionItemReached::info.id);
  EXPECT_GE(p.stats().unknown_msgid, 1U);
}

TEST(MavlinkParser, RandomBytesYieldNoFrames) {
  // 1 MB of noise rich in start bytes: every candidate fails its checksum (or is unknown), nothing
  // is accepted, and nothing stays buffered at the end of input.
  std::mt19937_64 rng(99);
  std::vector<std::uint8_t> noise(1 << 20);
  for (auto& b : noise) {
    const auto r = rng();
    b = r % 9 == 0 ? kStxV2 : r % 11 == 0 ? kStxV1 : static_cast<std::uint8_t>(r >> 32);
  }
  Parser p;
  std::vector<Frame> frames;
  for (std::size_t pos = 0; pos < noise.size(); pos += 1000)
    p.push(std::span(noise).subspan(pos, std::min<std::size_t>(1000, noise.size() - pos)), frames, false);
  p.push({}, frames, true);
  EXPECT_TRUE(frames.empty());
  EXPECT_EQ(p.buffered(), 0U);
  EXPECT_EQ(p.stats().bytes_skipped, noise.size());
  EXPECT_GT(p.stats().crc_errors, 0U);
}
