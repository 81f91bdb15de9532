// The QGroundControl .plan geofence (PX4's rules): one convex inclusion polygon holding everything the
// UAV flies, the no-fly zones as exclusion polygons, and the check that no flown point lies inside one.
//
// PX4 (navigator/geofence.cpp, isInsidePolygonOrCircle) accepts a point when there are no inclusion
// areas or it lies inside at least one, and it lies inside no exclusion area; polygons are tested with
// PNPOLY on latitude/longitude. The mission feasibility check applies that to every positioned item,
// and the pre-arm check to the vehicle at home.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "uavcover/plan.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::exporting {

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

}  // namespace uavcover::exporting
