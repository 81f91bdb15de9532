// Terrain following over a HeightGrid (include/uavcover/terrain.hpp): ground profiles along legs, the
// waypoints that keep a constant height above ground within a tolerance, and the flight heights the
// exports and the evaluation share (docs/photogrammetry.md, "Terrain following").
#pragma once

#include <vector>

#include "geodesy/local_frame.hpp"
#include "uavcover/mission.hpp"

namespace uavcover::terrain {

/// The mission's ground grid; nullptr without a terrain block. Throws InputError naming terrain.dem
/// when the block is there but its DEM has not been read (io::load_terrain()).
const HeightGrid* grid(const Mission& mission);

struct Sample {
  double s = 0.0;  ///< distance from the leg's start, metres
  Point p;         ///< local position
  double ground = 0.0;
};

/// Samples of the ground along a-b (local metres), both ends included, spaced at most a quarter of the
/// grid's step (at most 20 000 samples: very long legs are sampled more sparsely).
std::vector<Sample> profile(const HeightGrid& grid, const geodesy::LocalFrame& frame, Point a, Point b);

/// Terrain following along a-b: the samples where waypoints go (a and b included, in order) so that a
/// flight at a constant height above each of them, straight between them, stays within `tolerance_m`
/// of that height above the ground of every profile sample (Douglas-Peucker on the profile).
std::vector<Sample> follow_points(const HeightGrid& grid, const geodesy::LocalFrame& frame, Point a, Point b,
                                  double tolerance_m);

/// The ground height under the UAV's take-off (its start).
double home_ground(const Mission& mission, std::size_t uav);

}  // namespace uavcover::terrain
