// Shares the division can meet (issue 26, section 2), done once in the engine for every planner:
// - starts the engine chooses when a mission gives none: spread over the free area, weighted by share;
// - a free area in several parts: each UAV gets area in as many parts as its share needs, every part is
//   divided by the planner among the UAVs with a piece of it, and each UAV's pieces are joined in
//   flight order (the engine's transit legs route between them around the no-fly zones).
// See docs/planners.md ("Starts and parts").
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <vector>

#include "planners/planner.hpp"
#include "uavcover/context.hpp"
#include "uavcover/geometry.hpp"

namespace uavcover::engine {

/// The direction (radians from +x) of the principal axis of `mp`'s area (its longest extent), from the
/// second moments of area. 0 for an empty or isotropic area.
double principal_axis(const MultiPolygon& mp);

/// One start per share: `free` is cut across its principal axis into slabs of area proportional to the
/// shares (in order), and start i is a point of slab i's free area drawn from `rng` in the middle half
/// of the slab along the axis and its middle fifth across it (else anywhere across it; the slab's point
/// on surface when the draw finds none). Deterministic for a given rng state.
std::vector<Point> spread_starts(const MultiPolygon& free, const std::vector<double>& shares,
                                 std::mt19937_64& rng);

/// One UAV's pieces: (part index, area in m^2), in the order the allocation made them.
struct PartPiece {
  std::size_t part = 0;
  double area_m2 = 0.0;
};

/// The allocation of every UAV's share over the parts of the free area (parts[i] = polygon i of
/// `free`): UAVs ordered by their start along the axis through the parts' centroids, parts in the
/// same order, each UAV takes the next stretch of area of its share (so a UAV has pieces in few,
/// consecutive parts near its start); a cut within `snap` (a fraction of the free area) of a part's
/// edge moves to the edge, so that no UAV gets a sliver of a part.
std::vector<std::vector<PartPiece>> allocate_parts(const MultiPolygon& free, const std::vector<Point>& starts,
                                                   const std::vector<double>& shares, double snap = 0.004);

/// Plans a free area made of several parts: the allocation above, the planner on each part with the
/// UAVs that have a piece of it (their sub-share the piece's fraction of the part; their start their
/// own when the part is their nearest, else a spread start in the part), and each UAV's pieces joined
/// nearest first from its start. Nothing (nullopt) when the free area is one part, there is one UAV, or
/// the planner does not honour unequal shares: the planner then plans the whole problem itself.
std::optional<planners::Assignment> plan_by_parts(const planners::PlannerInfo& info,
                                                  const planners::Problem& problem,
                                                  const nlohmann::json& params, const Context& ctx);

}  // namespace uavcover::engine
