// Battery sorties (docs/sorties.md): each UAV's coverage cut at turning waypoints into flights that
// each fit one battery under the evaluator's time model (eq. 15), every sortie flying out from take-off
// at the UAV's transition altitude around the no-fly zones, covering its piece and returning; and the
// resume of a UAV's coverage from the last waypoint it reached.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "geometry/geometry.hpp"
#include "uavcover/context.hpp"
#include "uavcover/plan.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::sorties {

struct Options {
  /// Share of the endurance kept in reserve, in [0, 0.9]; empty = the mission's battery_reserve.
  std::optional<double> reserve;
  /// Sortie boundaries chosen by the planner (planners::UavAssignment::sortie_starts), per UAV in the
  /// plan's order; a missing or empty entry: that UAV's sorties are cut from its endurance. An entry
  /// lists the indices of the UAV's coverage parts (its PathParts of kind Coverage, counted in flight
  /// order) that begin a sortie: strictly increasing, the first 0. Each sortie then flies out from
  /// take-off, covers its parts with the plan's transits between them, and returns; it must fit one
  /// battery like a cut sortie.
  std::vector<std::vector<std::size_t>> sortie_starts;
};

/// Where global coverage waypoint g of a UAV lies: parts[part].local[vertex].
struct WaypointRef {
  std::size_t part = 0;
  std::size_t vertex = 0;
};

/// The UAV's coverage waypoints in flight order (the vertices of its coverage parts).
std::vector<WaypointRef> coverage_waypoints(const UavPlan& uav);

/// How far before its first waypoint a resume, or a battery sortie after the first, starts flying its
/// coverage (issue 31): the mission's resume_backoff_m, else one photo base (the UAV's camera trigger
/// distance, else the mission's), else 0. The stretch is the sortie's lead-in (PathPart::lead_in),
/// clipped at the start of the coverage part.
double resume_backoff_m(const Plan& plan, std::size_t index);

/// The battery budget of UAV `index` in minutes: endurance_min * (1 - reserve).
double budget_min(const Plan& plan, std::size_t index, const Options& options = {});

/// The minutes the climbs and descents of sortie `s` of UAV `index` take beyond its horizontal flight
/// (issue 32, docs/wind.md#the-whole-flight): waypoints::vertical_time_s() of the sortie's own mission
/// (take-off, transit at the UAV's transition altitude, coverage, landing) at
/// waypoints::whole_flight_altitudes(). A sortie fits one battery when duration_min + this <= budget_min().
double vertical_min(const Plan& plan, std::size_t index, const Sortie& s);

/// The sorties of UAV `index` (empty when it has no coverage): the planner's boundaries when `options`
/// has them for this UAV, else cut from its endurance. Throws InputError naming the UAV when one
/// coverage leg with the transit out and back, or one sortie given by the planner, does not fit one
/// battery, and naming `sortie_starts[index]` when the boundaries are not valid.
std::vector<Sortie> cut_sorties(const Plan& plan, std::size_t index, const Options& options = {});

/// Fills every UAV's sorties (plan() calls it for every planner). A UAV with a leg that does not fit
/// one battery throws cut_sorties()'s InputError, or, when `warnings` is given, keeps no sorties and
/// gets a warning there (plan() does so: the plan stays usable, the time/cost model falls back to
/// eq. 16 for that UAV, and per-sortie exports refuse it).
/// `router`: the no-fly zones' router in the plan's local frame when the caller has one (the engine).
/// `ctx`: progress per UAV ("sorties") and a stop between sorties (Cancelled).
void fill_sorties(Plan& plan, const Options& options = {}, std::vector<std::string>* warnings = nullptr,
                  const geometry::Router* router = nullptr, const Context* ctx = nullptr);

/// The item count of one mission (a sortie's plan, UAV `index`) as the vehicle would store it.
using ItemCount = std::function<std::size_t(const Plan& sortie_plan, std::size_t index)>;

/// Missions that fit a vehicle storing at most `capacity` items (issue 31, docs/vehicle-limits.md): the
/// UAV's sorties (or its whole coverage as one), each cut further at coverage waypoints where `count`
/// of its mission exceeds the capacity, as few pieces as bisection finds; every piece a whole mission
/// (take-off, transit out, its coverage with the lead-in of resume_backoff_m, back). Indices run 0, 1,
/// ... over the result. Throws InputError naming "max_mission_items" when one coverage leg's mission
/// alone does not fit.
/// `base`: the sorties to cut instead of the UAV's own (a resume's, sorties::resume_sorties()).
std::vector<Sortie> capacity_sorties(const Plan& plan, std::size_t index, std::size_t capacity,
                                     const ItemCount& count, const std::vector<Sortie>* base = nullptr);

/// Checks sorties read from a file against the UAV's coverage: consecutive, from the first coverage
/// waypoint to the last, boundaries shared inside a coverage part; and rebuilds their coverage parts
/// from the UAV's parts with the transit out and back given (`parts` holding only those two, either
/// possibly empty: [out, back]). No sorties are accepted (a UAV whose leg did not fit one battery).
/// Throws InputError naming `field`.
void rebuild_sorties(const Plan& plan, std::size_t index, std::vector<Sortie>& sorties,
                     const std::string& field);

/// A copy of `plan` in which UAV `index` flies only `sortie` (its parts; length, turns as the sortie's):
/// what the exporters write as one sortie's mission.
Plan sortie_plan(const Plan& plan, std::size_t index, const Sortie& sortie);

/// Resume of UAV `index` after it reached coverage waypoint `last_reached` (global index; -1 = none):
/// the rest of its current sortie, flown out from take-off at the transition altitude to the waypoint
/// where coverage stopped, then the following sorties unchanged, in order. Indices of the result stay
/// global (the first resumed sortie starts at last_reached, or at the next coverage part's first
/// waypoint when last_reached ends a coverage part). Empty when nothing is left. Throws InputError
/// naming "last_reached_waypoint" when it is out of range.
std::vector<Sortie> resume_sorties(const Plan& plan, std::size_t index, int last_reached);

/// The mission items of resume_sorties(), one mission per sortie (take-off, transit at the UAV's
/// transition altitude, coverage, return), as the exports build them.
std::vector<std::vector<waypoints::MissionItem>> resume_items(
    const Plan& plan, std::size_t index, int last_reached, const waypoints::AltitudeOptions& altitude = {});

}  // namespace uavcover::sorties
