#include "darp/darp_planner.hpp"

#include <stdexcept>

namespace uavcover::darp {

Output run(const Input&, const PlanOptions&, const Progress&) {
  throw std::runtime_error("planner not available: the DARP planner has not landed yet");
}

}  // namespace uavcover::darp
