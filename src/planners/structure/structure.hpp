// Structure (facade) scans (docs/patterns.md, issue 30), shared by the planners that support them
// (boustrophedon, milp): orbit layers at standoff_m from the footprint (its buffer, round at convex
// corners), each layer a coverage part at its own height with the camera horizontal and facing the wall,
// the layer spacing from the photo's height on the wall and the side overlap, the photo spacing along the
// orbit from its width and the front overlap; `top` adds a nadir pass over the roof. Several UAVs share
// the layers (contiguous blocks, so UAVs on the same orbit are separated vertically) or angular sectors
// of the orbit, whichever finishes sooner under the time model.
#pragma once

#include "planners/planner.hpp"

namespace uavcover::planners::structure {

/// The layers of a structure with a camera (every height above the take-off's ground).
struct Layout {
  double photo_width_m = 0.0;     ///< a photo's width on the wall at the standoff (along the orbit)
  double photo_height_m = 0.0;    ///< its height on the wall
  double layer_spacing_m = 0.0;   ///< photo height * (1 - side overlap)
  double trigger_m = 0.0;         ///< photo width * (1 - front overlap)
  std::vector<double> heights_m;  ///< bottom to top
  double roof_altitude_m = 0.0;   ///< the nadir pass (top): height_m + the camera's altitude_m
};

/// Bottom layer at max(safe_height_m, spacing / 2), then one every spacing until the top layer is at most
/// half a spacing below height_m (a layer's photo reaches half a photo height above and below it).
Layout layout(const Structure& structure, const Camera& camera);

/// The no-fly zones with the footprint grown by half the standoff (round corners): transit keeps clear.
MultiPolygon keep_out(const Polygon& footprint, const Structure& structure, const MultiPolygon& no_fly);

/// The orbit: the footprint's buffer by standoff_m (5 degree arcs at convex corners), counter-clockwise,
/// closed (last == first).
std::vector<Point> orbit(const Polygon& footprint, double standoff_m);

/// Where the camera at `p` faces the wall: the bearing (degrees clockwise from north) to the nearest
/// point of the footprint's outline (the bisector where two walls are equally near).
double facing_bearing(const Polygon& footprint, Point p);

/// Plans a structure mission (Problem::structure set). Needs the mission's camera.
Assignment plan(const Problem& problem, const Context& ctx);

}  // namespace uavcover::planners::structure
