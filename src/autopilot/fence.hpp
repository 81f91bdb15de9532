// The QGroundControl .plan geofence (PX4's rules): one convex inclusion polygon holding everything the
// UAV flies, the no-fly zones as exclusion polygons, and the check that no flown point lies inside one.
//
// PX4 (navigator/geofence.cpp, isInsidePolygonOrCircle) accepts a point when there are no inclusion
// areas or it lies inside at least one, and it lies inside no exclusion area; polygons are tested with
// PNPOLY on latitude/longitude. The mission feasibility check applies that to every positioned item,
// and the pre-arm check to the vehicle at home.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "mavlink/messages.hpp"
#include "uavcover/plan.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::autopilot {

/// The inclusion fence's default margin around everything flown (m): the .plan export's
/// (ExportOptions::geofence_margin_m, `--geofence-margin`), `uavcover upload`'s and server flights' fence.
inline constexpr double kFenceMarginM = 20.0;

/// PX4 keeps at most this many fence vertices (dataman DM_KEY_FENCE_POINTS_MAX).
inline constexpr std::size_t kPx4MaxFenceVertices = 64;

/// PNPOLY point-in-polygon on (lat, lon), as PX4's Geofence::insidePolygon (ring closed or open).
bool inside_ring(LonLat p, const GeoRing& ring);

/// The inclusion fence of UAV `index`: a convex polygon (at most 16 vertices, not closed, CCW) that
/// holds the mission area, the UAV's home and every positioned item at least `margin_m` metres from
/// its edge. Being convex it also holds every leg between them.
GeoRing inclusion_fence(const Plan& plan, std::size_t index, const std::vector<waypoints::MissionItem>& items,
                        double margin_m);

/// The places of UAV `index`'s flight that lie inside a no-fly zone: home, every positioned item and
/// points every `step_m` metres along the legs between them (home -> items -> home). One line each,
/// empty when none.
std::vector<std::string> no_fly_violations(const Plan& plan, std::size_t index,
                                           const std::vector<waypoints::MissionItem>& items,
                                           double step_m = 1.0);

/// MAV_CMD numbers of the fence and rally mission types (MAVLink common.xml).
enum FenceCmd : std::uint16_t {
  kFencePolygonVertexInclusion = 5001,  ///< param1 = the polygon's vertex count
  kFencePolygonVertexExclusion = 5002,
  kFenceCircleInclusion = 5003,  ///< param1 = radius (m)
  kFenceCircleExclusion = 5004,
  kRallyPoint = 5100,
};

/// The geofence uploaded with MAV_MISSION_TYPE_FENCE (issue 31, docs/fence-rally.md), as the .plan
/// geoFence holds it: the inclusion polygon of inclusion_fence() as FENCE_POLYGON_VERTEX_INCLUSION
/// items, then each no-fly zone's outer ring as FENCE_POLYGON_VERTEX_EXCLUSION items; param1 = the
/// polygon's vertex count, frame MAV_FRAME_GLOBAL, rings open (no repeated first vertex).
std::vector<waypoints::MissionItem> fence_items(const Plan& plan, std::size_t index,
                                                const std::vector<waypoints::MissionItem>& items,
                                                double margin_m);

/// The plan's rally points (Plan::rally) as MAV_CMD_NAV_RALLY_POINT items for MAV_MISSION_TYPE_RALLY,
/// frame MAV_FRAME_GLOBAL_RELATIVE_ALT at UAV `index`'s transition altitude (the height it returns at).
std::vector<waypoints::MissionItem> rally_items(const Plan& plan, std::size_t index);

/// A fence as a vehicle holds it: inclusion and exclusion polygons and circles.
struct Fence {
  struct Circle {
    LonLat centre;
    double radius_m = 0;
  };
  std::vector<GeoRing> inclusion, exclusion;
  std::vector<Circle> inclusion_circles, exclusion_circles;
  [[nodiscard]] bool empty() const {
    return inclusion.empty() && exclusion.empty() && inclusion_circles.empty() && exclusion_circles.empty();
  }
};

/// A fence from uploaded FENCE items (lat/lon * 1e7 in x/y), as PX4 and ArduPilot read them: polygon
/// vertices run in groups of param1 (at least 3, the same command and count in every vertex of a group).
/// Returns the reason when the items do not make a fence (the vehicle refuses the upload).
std::optional<std::string> read_fence(const std::vector<mavlink::MissionItemInt>& items, Fence& out);

/// PX4's rule (Geofence::isInsidePolygonOrCircle): inside at least one inclusion area when there are
/// any, and inside no exclusion area.
bool fence_allows(const Fence& fence, LonLat p);
/// The same with `slack_m` of position error: `p` passes when it, or one of 8 points `slack_m` around it,
/// passes (the simulator's breach test: a vehicle cutting a corner by a metre is not a breach).
bool fence_allows(const Fence& fence, LonLat p, double slack_m);

}  // namespace uavcover::autopilot
