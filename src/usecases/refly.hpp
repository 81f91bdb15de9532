// Refly the gaps (issue 32, docs/refly.md): after a flight, what the UAVs did not scan, as polygons, and
// the mission that covers it: the same mission with the gaps as its area, flown by the UAVs available.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "flight/coverage.hpp"
#include "uavcover/context.hpp"
#include "uavcover/mission.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::usecases {

struct ReflyGaps {
  MultiPolygon local;            ///< the gaps in the plan's local frame (inside the free area)
  std::vector<GeoPolygon> area;  ///< the same in WGS84 (GeoJSON ring order)
  double area_m2 = 0.0;          ///< their area
  double flown_poc = 0.0;        ///< the flight's coverage of the free area (flight::flown_coverage)
  double planned_poc = 0.0;      ///< the plan's own
};

/// The free area's lattice samples the tracks did not scan (flight::flown_coverage), as polygons: runs of
/// unscanned samples become cells, united; pieces narrower than an eighth of the spacing are dropped (the
/// lattice's rounding between swaths, not a gap a UAV can fly), the rest grown by half the spacing so the
/// refly's sweeps reach their edges, and clipped to the free area. Empty when nothing is left to fly.
/// InputError as flown_coverage ("tracks[i].uav", ...). ctx: stops (Cancelled).
ReflyGaps coverage_gaps(const Plan& plan, const std::vector<flight::Track>& tracks, const Context& ctx = {});

/// The same gaps from any scan lattice over the plan's free area (the evaluator's: -1 outside the free
/// area, scan counts inside), e.g. the photos' footprints (usecases/photos.hpp). flown_poc and
/// planned_poc are left 0 for the caller.
ReflyGaps lattice_gaps(const Plan& plan, const evaluation::CoverageResult& lattice, const Context& ctx = {});

/// A GeoJSON Polygon's coordinates ([[lon, lat], ...] per ring) of `p`.
nlohmann::json polygon_coordinates(const GeoPolygon& p);

/// The refly mission: `plan.mission` with the gaps as its area (a corridor or structure becomes the
/// area it leaves to fly), named "<name> (refly)", flown by `uavs` (ids of the plan's UAVs; empty: all),
/// each from the start it used, their shares renormalised. InputError "uavs" for an unknown or repeated
/// id, "area" when there are no gaps.
Mission refly_mission(const Plan& plan, const ReflyGaps& gaps, const std::vector<std::string>& uavs);

/// Tracks from a flight log as the server gives it: GET /flights/{id}/log.geojson (a LineString per UAV,
/// properties.uav, coordinates [lon, lat, alt_m]) or /log.csv (telemetry rows: uav, lon, lat, alt_m).
/// InputError naming `field` and the feature or line at fault.
std::vector<flight::Track> parse_flight_log(std::string_view text, const std::string& field);

}  // namespace uavcover::usecases
