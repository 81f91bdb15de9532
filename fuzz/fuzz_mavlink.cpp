// libFuzzer target: the MAVLink stream parser must resynchronise on any bytes, never crash, and
// every frame it accepts must decode or be refused cleanly.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "mavlink/frame.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  uavcover::mavlink::Parser parser;
  std::vector<uavcover::mavlink::Frame> frames;
  // feed in two pieces to exercise partial frames, then as one datagram
  const std::size_t half = size / 2;
  parser.push(std::span<const std::uint8_t>(data, half), frames);
  parser.push(std::span<const std::uint8_t>(data + half, size - half), frames, true);
  uavcover::mavlink::Parser whole;
  whole.push(std::span<const std::uint8_t>(data, size), frames, true);
  return 0;
}
