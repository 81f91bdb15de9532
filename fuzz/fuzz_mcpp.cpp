// libFuzzer target: the mission parser on the mCPP-optimized-DARP input format (the input is
// prefixed with its detection key so that the fuzzer stays on that path).
#include <cstddef>
#include <cstdint>
#include <string>

#include "uavcover/error.hpp"
#include "uavcover/mission.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string text = "{\"droneNo\":";
  text.append(reinterpret_cast<const char*>(data), size);
  uavcover::ParseOptions opt;
  opt.max_cells = 200'000;
  try {
    (void)uavcover::parse_mission(text, opt);
  } catch (const uavcover::InputError&) {
  }
  return 0;
}
