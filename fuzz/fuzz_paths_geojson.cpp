// libFuzzer target: the GeoJSON paths reader behind `uavcover evaluate` (any tool's plan).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "evaluation/evaluate.hpp"
#include "uavcover/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const uavcover::geodesy::LocalFrame frame({24.41, 40.93});
  try {
    (void)uavcover::evaluation::parse_paths_geojson(
        std::string_view(reinterpret_cast<const char*>(data), size), frame);
  } catch (const uavcover::InputError&) {
  }
  return 0;
}
