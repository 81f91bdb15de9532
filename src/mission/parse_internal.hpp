// Internal to src/mission: the pieces of parse_mission (parse.cpp) shared by its files: the field
// readers (fields.cpp), the camera block and its ground geometry (camera.cpp), and the two input
// formats (input_v1.cpp, input_mcpp.cpp). Every refusal is an InputError naming the field.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "geodesy/local_frame.hpp"
#include "uavcover/mission.hpp"

namespace uavcover::mission::detail {

using nlohmann::json;

// ---- field readers (fields.cpp) ----

std::string idx(const std::string& base, std::size_t i);
/// A large non-negative count for a message: digits up to 10^15, else like 3.2e+21.
std::string count_text(double v);
const char* type_name(const json& j);
/// The "type" member of a GeoJSON object, or "" when it is missing or not a string.
std::string geojson_type(const json& j);
double number(const json& j, const std::string& field);
double positive(const json& j, const std::string& field);
double in_range(const json& j, const std::string& field, double lo, double hi, bool hi_open = false);
std::string str(const json& j, const std::string& field);
LonLat position(const json& j, const std::string& field);
LonLat latlong_object(const json& j, const std::string& field);
/// Accepts a Polygon or MultiPolygon geometry (or a Feature wrapping one).
std::vector<GeoPolygon> polygons_of(const json& j, const std::string& field);
/// UAV ids name output files: [A-Za-z0-9_-][A-Za-z0-9_.-]{0,63} (so never "." or "..").
void check_id(const std::string& id, const std::string& field);
/// Free-text names: at most 256 bytes, no control characters.
std::string checked_name(const std::string& name, const std::string& field);
void reject_unknown(const json& obj, const std::set<std::string>& known, const std::string& prefix);

struct NamedPolygon {
  GeoPolygon poly;
  std::string field;  // JSON path of its coordinates
};

/// Normalises every ring and checks it (>= 3 distinct vertices, no edge spanning more than 180° of
/// longitude, not all on one line).
void normalise_polygon(NamedPolygon& np);
/// Every vertex within 500 km of the area's centre: beyond, the local flat frame distorts.
void check_extent(const NamedPolygon& np, LonLat centre);
void check_valid(const NamedPolygon& np, const geodesy::LocalFrame& frame);

// ---- the camera block (camera.cpp) ----

/// A camera block at `field` ("camera", or "uavs[i].camera" for a UAV's own).
Camera parse_camera(const json& j, const std::string& field);
/// The ground geometry of camera `c` at `field` (paper eq. 14, or QGroundControl's formulas).
CameraGeometry camera_geometry(const Camera& c, const std::string& field);

// ---- the input formats (input_v1.cpp, input_mcpp.cpp) ----

struct Raw {
  std::string name = "mission";
  std::vector<NamedPolygon> area;
  std::vector<NamedPolygon> nfz;
  std::optional<double> spacing;
  std::optional<Camera> camera;
  std::optional<double> altitude;
  std::vector<Uav> uavs;
  std::vector<std::optional<double>> shares;
  std::size_t uav_count = 0;
  Mode mode = Mode::Strict;
  std::string planner = "darp";
  std::string objective = "time";             ///< "planner": "auto" only
  std::string transition_altitudes = "hong";  ///< "hong" | "layers"
  json planner_params;                        ///< as given; validated against the planner's schema at the end
  std::uint64_t seed = 1;
  double battery_reserve = kDefaultBatteryReserve;
  std::string format = "uavcover-v1";
  std::optional<Terrain> terrain;
  std::optional<Wind> wind;          ///< issue 32
  std::optional<Corridor> corridor;  ///< docs/patterns.md: its buffer is `area`
  std::optional<Pattern> pattern;
  std::optional<Structure> structure;  ///< docs/patterns.md: its footprint buffered by standoff_m is `area`
  std::vector<LonLat> rally;           ///< issue 31, checked against the no-fly zones in parse.cpp
  bool propose_rally = false;
  std::optional<double> resume_backoff;
  std::string autopilot;  ///< "" or a vehicle profile's name
  std::optional<int> max_mission_items;
};

/// `structure`: {"footprint": Polygon, "height_m", "standoff_m", "top", "safe_height_m"} (input_v1.cpp).
/// Throws InputError naming the field (footprint self-intersecting, height or standoff <= 0, ...).
Structure parse_structure(const json& j);
/// The ground the orbits fly over: the footprint buffered by standoff_m, round convex corners.
GeoPolygon structure_area(const Structure& s);

/// uavcover v1 (GeoJSON conventions).
Raw parse_v1(const json& j);
/// mCPP-optimized-DARP input (droneNo, scanningDensity, polygon [{lat,long}], obstacles,
/// pathsStrictlyInPoly, initialPos, rPortions).
Raw parse_mcpp(const json& j);
/// The "uavs" member (a count or an array), or mCPP's droneNo.
void parse_uavs(const json& j, Raw& raw);

}  // namespace uavcover::mission::detail
