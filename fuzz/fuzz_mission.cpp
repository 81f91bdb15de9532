// libFuzzer target: the mission parser must refuse bad input with InputError, never crash or hang.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "uavcover/error.hpp"
#include "uavcover/mission.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  uavcover::ParseOptions opt;
  opt.max_cells = 200'000;
  try {
    const auto m = uavcover::parse_mission(std::string_view(reinterpret_cast<const char*>(data), size), opt);
    (void)uavcover::mission_to_json(m);
  } catch (const uavcover::InputError&) {
  }
  return 0;
}
