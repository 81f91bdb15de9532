// Rally points the planner proposes (issue 31, docs/fence-rally.md): one safe landing point per UAV on
// free ground inside its region, as far from the no-fly zones as the region allows.
#pragma once

#include <vector>

#include "geodesy/local_frame.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::engine {

/// Metres kept from every no-fly zone when the region allows it (else the farthest point found).
inline constexpr double kRallyClearanceM = 30.0;

/// One point per UAV with a region (in the plan's order, UAVs without one skipped): among the region's
/// centroid and a 16 x 16 grid over its bounding box, the points inside the region; of those at least
/// kRallyClearanceM from every no-fly zone (or, when none is, those farthest from them), the one nearest
/// the region's centroid. Deterministic. `no_fly`: the no-fly zones in `frame`.
std::vector<LonLat> propose_rally(const Plan& plan, const MultiPolygon& no_fly,
                                  const geodesy::LocalFrame& frame);

}  // namespace uavcover::engine
