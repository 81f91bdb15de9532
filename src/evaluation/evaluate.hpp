// Plan evaluation: coverage simulation + time/cost model, JSON output, and reading other tools'
// paths (GeoJSON LineStrings per UAV) for `uavcover evaluate`.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "evaluation/cost.hpp"
#include "evaluation/coverage.hpp"
#include "evaluation/facade.hpp"
#include "geodesy/local_frame.hpp"
#include "photo/photo.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::evaluation {

struct EvaluateOptions {
  CoverageOptions coverage;  ///< footprint_m 0 = footprint_for(mission)
  CostOptions cost;
  bool compute_coverage = true;  ///< false: lengths/turns/cost only (no lattice)
};

struct Evaluation {
  MultiPolygon free;  ///< the free area evaluated (local metres), e.g. for the heatmap's outline
  double footprint_m = 0.0;
  CoverageResult coverage;
  CostResult cost;
  std::vector<std::string> uav_ids;
  std::optional<photo::Estimate> images;  ///< the camera's trigger plan (evaluate_plan, with a camera)
  /// With a DEM (evaluate_plan): each coverage footprint sized by the height above the ground under it,
  /// w = footprint_m * height / mission altitude; the extremes over all coverage legs.
  struct TerrainFootprints {
    double footprint_min_m = 0.0, footprint_max_m = 0.0;
    double height_min_m = 0.0, height_max_m = 0.0;  ///< flight height above ground
  };
  std::optional<TerrainFootprints> terrain;
  /// A structure scan (evaluate_plan, docs/patterns.md): the wall's coverage by the photos.
  std::optional<FacadeCoverage> facade;
};

/// Footprint width w: mission.footprint_m, else 2*h*tan(HFOV/2) from the camera, else 1.5*ds.
double footprint_for(const Mission& mission);
/// Footprint width of UAV `uav` (heterogeneous cameras): its own camera's, else footprint_for(mission).
double footprint_for(const Mission& mission, std::size_t uav);
/// Heterogeneous cameras: unless `coverage` sweeps one width for all (footprint_m > 0, `--footprint`) or
/// already has per-UAV widths, sets coverage.uav_footprint_m to footprint_for(mission, i) of the
/// mission's first `uavs` UAVs, left empty when every one of them sees `w`.
void set_uav_footprints(const Mission& mission, std::size_t uavs, double w, CoverageOptions& coverage);

/// Free area (area - no-fly zones) of the mission in the local frame centred at `origin`.
MultiPolygon free_area(const Mission& mission, const geodesy::LocalFrame& frame);

/// A WGS84 box, e.g. the one a coverage lattice's picture spans.
struct GeoBounds {
  double south = 0.0, west = 0.0, north = 0.0, east = 0.0;
};

/// The WGS84 box render::heatmap_overlay_png's picture of `coverage` spans: each pixel is one sample's
/// cell, centred on the sample; the corners of that local-frame rectangle (`frame`: the evaluation's),
/// enclosed.
GeoBounds lattice_bounds(const CoverageResult& coverage, const geodesy::LocalFrame& frame);

/// Evaluates flights over `free` with the UAVs' speed/turn constants/endurance (uavs.size() ==
/// flights.size()).
Evaluation evaluate_flights(const MultiPolygon& free, const std::vector<Flight>& flights,
                            const std::vector<Uav>& uavs, double footprint_m,
                            const EvaluateOptions& options = {});

/// Flight heights above the ground along UAV `uav`'s coverage leg a-b (local metres) of `plan`, at the
/// middles of `pieces` equal pieces: in follow mode between the waypoints terrain following puts there,
/// in off mode at the mission altitude above the take-off's ground. Needs the plan's DEM.
std::vector<double> heights_above_ground(const Plan& plan, std::size_t uav, Point a, Point b,
                                         std::size_t pieces);

/// Coverage + cost of a plan (coverage parts and in/out transit legs). With a DEM, every coverage
/// footprint is sized by the height above the ground under it (Evaluation::terrain).
Evaluation evaluate_plan(const Plan& plan, const EvaluateOptions& options = {});

nlohmann::json to_json(const CoverageStats& stats);
/// Coverage block for plan.json: lattice, footprint, totals and per-UAV stats.
nlohmann::json to_json(const CoverageResult& coverage, double footprint_m = 0.0);
nlohmann::json to_json(const CostResult& cost);
/// {"coverage": ..., "cost": ...}
nlohmann::json to_json(const Evaluation& evaluation);

/// evaluation.json of `uavcover evaluate`: totals at top level (poc, pooc, max_scans, turns,
/// length_m, flight_time_min, total_time_min, cost_eur, ...) and per-UAV figures under "uavs".
nlohmann::json evaluation_json(const Evaluation& evaluation);

/// Paths read from GeoJSON.
struct GeoPaths {
  std::vector<std::string> uav_ids;
  std::vector<Flight> flights;  ///< local coordinates filled from `frame`, WGS84 kept
};

/// A WGS84 position from a GeoJSON coordinate array [longitude, latitude, ...], checked as untrusted
/// input (InputError naming `field`).
LonLat read_position(const nlohmann::json& c, const std::string& field);

/// Converts a WGS84 position of an input file to local metres, or throws InputError naming `field`.
using ToLocal = std::function<Point(const LonLat&, const std::string& field)>;

/// How a line's camera works, from its paths.geojson properties (docs/exports.md), read as untrusted
/// input into `part` (its points set): `attitude` (altitude_m, heading_deg one per vertex,
/// gimbal_pitch_deg, roi, trigger_distance_m; known fields only, each in range) and `camera_off` (the
/// indices of the segments flown with the camera off). Throws InputError naming the field under `field`
/// (the feature's "….properties").
void read_camera_properties(const nlohmann::json& props, const std::string& field, PathPart& part,
                            const ToLocal& to_local);

/// The oblique parts' camera (docs/patterns.md "Obliques"): the fields of view of the mission's camera
/// at its altitude, unless `coverage` has its own. Nothing without a camera.
void set_oblique_camera(const Mission& mission, CoverageOptions& coverage);

/// Reads a FeatureCollection (or a single Feature / geometry) of LineStrings or MultiLineStrings.
/// properties.uav names the UAV (lines with the same name form one flight); without it every
/// line is its own UAV. properties.kind "transit" marks transit legs; properties.attitude and
/// camera_off as read_camera_properties (plan's own paths.geojson keep their obliques and camera
/// gaps; a MultiLineString's attitude holds for each of its lines). Polygon and Point features
/// are ignored. Throws InputError naming the field (e.g. "features[2].geometry.coordinates").
GeoPaths parse_paths_geojson(std::string_view text, const geodesy::LocalFrame& frame);

}  // namespace uavcover::evaluation
