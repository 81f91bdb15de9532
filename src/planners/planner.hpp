// The planner interface. A planner is a module in src/planners/<name>/ that turns a local problem
// (free area, starts, shares, spacing, mode) into an assignment: per UAV its region and its ordered
// coverage parts. Everything after that (transit legs around no-fly zones, WGS84, metrics,
// coverage, cost, transition altitudes, exports, pictures) is done once for every planner by
// src/engine/. See docs/planners.md for how to add one.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "uavcover/context.hpp"
#include "uavcover/geometry.hpp"
#include "uavcover/mission.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::planners {

/// One UAV's sensor on the ground (heterogeneous cameras, docs/mission-format.md): its own camera's, or
/// the mission's. Every UAV flies the mission's altitude.
struct UavFootprint {
  double width_m = 0.0;     ///< footprint across the flight direction (Problem::footprint_m by default)
  double along_m = 0.0;     ///< footprint along it (the camera's; width_m without a camera)
  bool own_camera = false;  ///< the UAV has its own camera (uavs[i].camera)
};

/// The mission in the local ENU frame (metres, origin at the area's centroid).
struct Problem {
  MultiPolygon area;             ///< union of the area polygons (holes kept)
  MultiPolygon no_fly;           ///< union of the no-fly zones (holes of the area included)
  MultiPolygon free;             ///< area minus no-fly zones (corrected)
  std::vector<Point> starts;     ///< one per UAV (given or drawn from the seed; may lie outside the area)
  std::vector<double> shares;    ///< one per UAV, sum 1
  std::vector<Uav> uavs;         ///< the mission's UAVs (speed, acceleration, endurance, ...)
  double spacing_m = 0.0;        ///< line spacing / scanning density ds
  double footprint_m = 0.0;      ///< sensor footprint width on the ground (1.5 ds without a camera)
  double altitude_m = 0.0;       ///< mission altitude
  std::optional<Camera> camera;  ///< the mission's camera, if it has one (footprint_m derives from it)
  /// One per UAV: its own footprint. Planners that plan every UAV at spacing_m may ignore it.
  std::vector<UavFootprint> uav_footprints;
  Mode mode = Mode::Strict;
  std::uint64_t seed = 0;
  /// A corridor mission (docs/patterns.md): its centre line in local metres and its width; `area` is
  /// the buffered line. Empty: an area mission.
  std::vector<Point> corridor_line = {};
  double corridor_width_m = 0.0;
  /// The mission's pattern block (the engine refuses the options the planner does not support).
  std::optional<Pattern> pattern = {};
  /// A structure scan (docs/patterns.md): the footprint in local metres (`area` is the ground the orbits
  /// fly over); empty for other missions.
  Polygon structure_footprint = {};
  std::optional<Structure> structure = {};
  std::optional<Wind> wind = {};  ///< the mission's wind (issue 32)
};

/// What a planner decides for one UAV.
struct UavAssignment {
  /// The UAV's region: exclusive (regions of different UAVs do not overlap) and inside
  /// Problem::free. Empty for a UAV without work.
  MultiPolygon region;
  /// Coverage parts in flight order, each a polyline of turning waypoints (a closed loop repeats its
  /// first vertex). The engine joins them with transit legs routed around the no-fly zones.
  std::vector<std::vector<Point>> coverage;
  /// Optional, parallel to `coverage`: per part, one flag per segment, 1 where the camera is off (turns,
  /// turnarounds); a missing or empty entry: camera on over the whole part (PathPart::camera_off).
  std::vector<std::vector<std::uint8_t>> camera_off = {};
  /// Optional, parallel to `coverage`: per part, how it is flown (structure layers, oblique passes);
  /// a missing or empty entry: the mission's defaults (PathPart::attitude).
  std::vector<Attitude> attitude = {};
  /// Battery sorties chosen by the planner (optional): the indices into `coverage` of the parts that
  /// begin a new sortie, strictly increasing, the first 0 (e.g. {0, 1, 2} for three routes that each
  /// start and end at the UAV's start). Each sortie flies out from the start, covers its parts in
  /// order (joined by transit legs) and returns to the start; the engine's path returns to the start
  /// between sorties too. Every sortie must fit one battery under the time model (eq. 15) with the
  /// mission's battery_reserve, or the UAV gets no sorties and the plan a warning, as for cut sorties.
  /// Empty: the engine cuts the coverage into sorties from the UAV's endurance (docs/sorties.md).
  /// Empty coverage parts count: a sortie that begins at one begins at the next non-empty part.
  std::vector<std::size_t> sortie_starts;
  /// The share the planner achieved by its own measure; empty: the engine uses region areas.
  std::optional<double> share_actual;
  nlohmann::json diagnostics = nlohmann::json::object();  ///< opaque to everything downstream
};

struct Assignment {
  std::vector<UavAssignment> uavs;  ///< one per UAV, in the problem's order
  std::vector<std::string> warnings;
  nlohmann::json diagnostics = nlohmann::json::object();  ///< opaque to everything downstream
  /// False when the planner stopped early (time limit) and returns its best complete result so far.
  bool complete = true;
};

/// One planner parameter (mission field `planner_params.<name>`).
struct ParamSpec {
  enum class Type { Number, Integer, Boolean, String };
  std::string name;
  Type type = Type::Number;
  nlohmann::json default_value;      ///< null: optional, absent unless given
  std::optional<double> min, max;    ///< inclusive bounds for numbers
  std::vector<std::string> choices;  ///< allowed strings (String)
  std::string description;
};

/// A parameter's schema in one call (for the planners' PlannerInfo).
ParamSpec param(std::string name, ParamSpec::Type type, nlohmann::json default_value,
                std::optional<double> min, std::optional<double> max, std::string description,
                std::vector<std::string> choices = {});

/// What a planner can do; the engine refuses (or warns about) missions asking for more.
struct Capabilities {
  bool shares = true;        ///< honours unequal shares (false: refused when shares differ)
  bool no_fly_zones = true;  ///< plans around no-fly zones (false: refused when there are any)
  bool strict_mode = true;
  bool coverage_mode = true;
  bool multiple_areas = true;  ///< plans areas made of several polygons
  bool best_so_far = false;    ///< returns its best complete plan when the time limit is reached
  // the patterns (docs/patterns.md): mission field `corridor` and the `pattern.*` options
  bool corridor = false;
  bool crosshatch = false;
  bool turnaround = false;  ///< pattern.turnaround_m > 0
  bool entry = false;       ///< pattern.entry other than "auto"
  bool alternate_transects = false;
  bool capture_in_turnaround = false;
  bool structure = false;  ///< mission field `structure`: facade orbits (src/planners/structure/)
  bool oblique = false;    ///< pattern.oblique: nadir grid and fixed-heading oblique passes (areas)
};

class Planner {
 public:
  virtual ~Planner() = default;
  /// Plans `problem` with validated `params` (every ParamSpec present, defaults filled in).
  /// Must be deterministic for a given problem (seed included). Calls ctx.report() for progress and
  /// ctx.check() (or ctx.should_stop() when it can return a best-so-far result) often enough that a
  /// stop lands within 0.5 s. Throws InputError for problems it cannot plan.
  [[nodiscard]] virtual Assignment plan(const Problem& problem, const nlohmann::json& params,
                                        const Context& ctx) const = 0;
};

struct PlannerInfo {
  std::string name;     ///< mission field "planner"
  std::string summary;  ///< one line for listings
  std::vector<ParamSpec> params;
  Capabilities supports;
  std::function<std::unique_ptr<Planner>()> create;
};

/// Every planner built into this binary, in a fixed order (darp first).
const std::vector<PlannerInfo>& registry();
/// The planner called `name`, or nullptr.
const PlannerInfo* find(std::string_view name);
/// The planner called `name`; InputError naming `field` and listing the available planners otherwise.
const PlannerInfo& require(std::string_view name, const std::string& field = "planner");

/// Checks `params` (a JSON object or null) against the planner's schema and returns it with every
/// default filled in. Throws InputError naming the field, e.g.
/// "planner_params.lloyd_iterations: must be >= 0, got -1", and for unknown parameters.
nlohmann::json validate_params(const PlannerInfo& planner, const nlohmann::json& params);

/// The schema as JSON (for `uavcover planners` and the server's API).
nlohmann::json describe(const PlannerInfo& planner);

}  // namespace uavcover::planners
