// libFuzzer target: the JSON side of the plan-folder loader (io::load_plan_dir). The input is
// plan.json, a NUL byte, then paths.geojson (a NUL never occurs in JSON text). Both go through the
// strict reader, the stored mission through parse_mission as load_plan_dir does; everything must
// end in a value or an InputError, never a crash, a hang or unbounded memory.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "json/strict.hpp"
#include "uavcover/error.hpp"
#include "uavcover/mission.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const std::size_t nul = input.find('\0');
  const std::string_view plan_text = input.substr(0, nul);
  const std::string_view paths_text =
      nul == std::string_view::npos ? std::string_view() : input.substr(nul + 1);
  try {
    const auto plan = uavcover::strict::parse_json(plan_text, "plan.json");
    if (plan.is_object() && plan.contains("mission")) {
      uavcover::ParseOptions opt;
      opt.max_cells = 200'000;
      const auto m = uavcover::parse_mission(plan["mission"].dump(), opt);
      (void)uavcover::mission_to_json(m);
    }
  } catch (const uavcover::InputError&) {
  }
  try {
    const auto paths = uavcover::strict::parse_json(paths_text, "paths.geojson");
    (void)paths.dump();  // a copy and a walk of the whole document: bounded by the depth limit
  } catch (const uavcover::InputError&) {
  }
  return 0;
}
