// The plan: what uavcover gives back for a mission.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "uavcover/geometry.hpp"
#include "uavcover/mission.hpp"

namespace uavcover {

enum class PartKind { Coverage, Transit };

/// One piece of a UAV's flight, in flight order. Coverage parts are closed loops of
/// turning waypoints (last vertex == first). Transit parts connect start, loops and return.
struct PathPart {
  PartKind kind = PartKind::Coverage;
  std::vector<Point> local;   ///< ENU metres
  std::vector<LonLat> wgs84;  ///< the same vertices in WGS84
};

/// Result of the grid placement optimisation (paper §2.2, eq. 7-10).
struct Placement {
  double shift_x_m = 0.0;
  double shift_y_m = 0.0;
  double rotation_deg = 0.0;
  double J = 0.0, J1 = 0.0, J2 = 0.0, J3 = 0.0;
  long evaluations = 0;
};

/// The grid actually used (mega-cells of size 2*ds), for rendering and evaluation.
struct GridInfo {
  double cell_m = 0.0;  ///< mega-cell size dn = 2*ds
  double rotation_deg = 0.0;
  Point origin;  ///< local ENU position of mega-cell (0,0)'s lower-left corner
  int rows = 0, cols = 0;
  std::vector<int> owner;  ///< rows*cols; -1 blocked, else UAV index
};

struct UavPlan {
  std::string id;
  double share_requested = 0.0;
  double share_actual = 0.0;       ///< by mega-cells assigned
  int cells = 0;                   ///< mega-cells assigned
  int regions = 0;                 ///< connected regions flown (several when free space is split)
  std::vector<PathPart> parts;     ///< in flight order
  double coverage_length_m = 0.0;  ///< length of the coverage loops
  double length_m = 0.0;           ///< total, with transit
  int turns = 0;                   ///< turning waypoints of the coverage loops
};

struct Plan {
  Mission mission;
  LonLat origin;  ///< the local frame's origin (area centroid)
  Placement placement;
  GridInfo grid;
  std::vector<UavPlan> uavs;
  std::vector<std::string> warnings;
  bool darp_converged = true;
  int darp_iterations = 0;
  double compute_time_s = 0.0;
  double free_area_m2 = 0.0;
};

}  // namespace uavcover
