// What a finished plan gives an operator, as artifacts: paths.geojson, plan.json (with coverage and
// cost unless turned off), pictures and exports. The CLI writes them to a folder (io::write_artifacts);
// the server stores and serves the same bytes.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "evaluation/evaluate.hpp"
#include "trajectory/trajectory.hpp"
#include "uavcover/artifact.hpp"
#include "uavcover/context.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::usecases {

struct OutputOptions {
  bool evaluate = true;  ///< coverage simulation + time/cost model (eq. 15 and trajectories) into plan.json
  bool images = true;    ///< plan.png, plan.svg, heatmap.png, histogram.png
  /// with `images` and `evaluate`: also heatmap-overlay.png (the lattice alone) and heatmap_bounds
  bool heatmap_overlay = false;
  std::vector<std::string> exports;  ///< export formats (exporting::known_formats())
  bool kmz = false;                  ///< with "kml": also <id>.kmz
  bool per_sortie = false;           ///< exports per battery sortie (exporting::ExportOptions::per_sortie)
  /// trajectory export: 0 = the segment form, > 0 = sampled at this step (ExportOptions::trajectory_step_s)
  double trajectory_step_s = 0;
  /// trajectory and trajectory_plot exports: the method and its options (ExportOptions::trajectory)
  trajectory::Options trajectory;
  /// Export each format on its own and turn a format's refusal (InputError: altitude limits, a UAV id
  /// that is no file name, ...) into a warning instead of failing the whole output (the server's jobs).
  bool refused_exports_are_warnings = false;
};

struct PlanOutputs {
  Artifacts artifacts;
  /// When evaluated: the coverage, cost and cost_trajectory blocks that plan.json carries (else {}).
  nlohmann::json evaluation = nlohmann::json::object();
  std::vector<std::string> warnings;  ///< from the exporters (limits, skipped UAVs, separation hazards)
  double poc = -1, pooc = -1;         ///< when evaluated
  /// A structure scan, when evaluated: the wall's share seen by a photo and by three or more (its ground
  /// PoC says little: the photos look at the wall); -1 otherwise.
  double facade_poc = -1, facade_3plus = -1;
  double flight_time_min = -1, total_time_min = -1, cost_eur = -1;
  double trajectory_flight_time_min = -1;  ///< the same from the time-parameterised trajectories
  /// With heatmap_overlay: the WGS84 box heatmap-overlay.png spans, [[south, west], [north, east]] (the
  /// corners of its local-frame rectangle, enclosed); null otherwise.
  nlohmann::json heatmap_bounds;
  /// What the time limit left out after the planner ("evaluation", "pictures heatmap.png, ...",
  /// "exports qgc, kml"); a warning in `warnings` and in plan.json says the same. Empty when all fitted.
  std::vector<std::string> left_out;
};

/// Refuses, before any planning, what plan_outputs() would refuse after it (InputError naming the
/// field, the same message): unknown export formats, and with exports transition altitudes that cannot
/// fit under the export's ceiling (waypoints::resolve_altitudes) and trajectory options some UAV cannot
/// keep (trajectory::check_options). Call it before plan().
void check_outputs(const Mission& mission, const OutputOptions& options);

/// Everything the plan folder holds. Stops and the time limit land in every stage (docs/stops.md): a
/// stop request throws Cancelled (per UAV in the evaluation, per picture, per export format); when ctx's
/// deadline passes, the stages that have not finished are left out (PlanOutputs::left_out) and
/// paths.geojson and plan.json are still made. UAVCOVER_TEST_HOLD_STAGE can hold it at "evaluation",
/// "pictures" or "exports" (engine/test_hold.hpp).
PlanOutputs plan_outputs(const Plan& plan, const OutputOptions& options, const Context& ctx = {});

/// One export format of a stored plan, made on demand (the server's exports, docs/cache.md).
struct BuiltExport {
  /// Every flying UAV's files of the format, as a plan job made them eagerly before: names
  /// export/<id>.<ext> and trajectory/<id>.csv; with "kml" also <id>.kmz; a Litchi mission split in
  /// parts also comes as export/<id>.litchi.zip. Empty when refused.
  Artifacts files;
  std::vector<std::string> warnings;  ///< the exporter's (clamps, skipped UAVs, separation hazards)
  /// When the format refuses the plan (altitude limits, no-fly zones, ...): the field and the reason.
  std::string refused_field, refused;
};

/// One route of GET /plans/{id}/exports/{format}: a format of the table (exporting::formats()), or "kmz",
/// the .kmz a plan job's build of "kml" makes next to each .kml.
struct ExportRoute {
  std::string name;    ///< the route's {format}: "qgc", ..., "kmz"
  std::string format;  ///< the table's format whose build makes its files: "kml" for "kmz", else `name`
  std::string title;   ///< for people (the table's title): the web app's button
  /// The artifact names of the route's file for UAV "{}", in order of preference: "export/{}.plan";
  /// Litchi's zip of a split mission before its single CSV; the trajectory's "trajectory/{}.csv".
  std::vector<std::string> files;
};

/// The server's export routes, from the table and in its order, with "kmz" right after "kml". Every
/// list of them (the router's error text, GET /api/v1/formats, the OpenAPI enum's test) is this one.
const std::vector<ExportRoute>& export_routes();
/// The route of that name, or nullptr.
const ExportRoute* find_export_route(std::string_view name);
/// "geojson, qgc, ..., kml, kmz, ..." for error texts.
std::string export_route_list();
/// [{"name", "format", "title"}, ...] for GET /api/v1/formats.
nlohmann::json export_routes_json();

/// The export format that makes the API format `format` of GET /plans/{id}/exports/{format}: "kml" for
/// "kmz" (a .kmz comes with each .kml), else `format` itself (ExportRoute::format).
std::string export_source_format(const std::string& format);

/// The export options an API client may ask for (GET /plans/{id}/exports/{format}?autopilot=&terrain_frame=
/// &split_capacity=, issue 31; &method=&order=&v_mean=&v_min=&a_min=, issue 33): the CLI's `export
/// --autopilot`, `--terrain-frame`, `--split-capacity` and the trajectory method's options.
/// Each variant is its own cache entry (key()).
struct ExportVariant {
  std::string autopilot;        ///< "" = the mission's (ExportOptions::autopilot)
  bool terrain_frame = false;   ///< ArduPilot's MAV_FRAME_GLOBAL_TERRAIN_ALT (AltitudeOptions::terrain_frame)
  bool split_capacity = false;  ///< whole missions that fit the profile's capacity, zipped per UAV
  /// ?method=&order=&v_mean=&v_min=&a_min=: the trajectory and trajectory_plot exports' method
  /// (ExportOptions::trajectory: the CLI's --trajectory-method, --order, --v-mean, --v-min, --a-min)
  trajectory::Options trajectory;
  /// "" for the default, else "@autopilot=px4@terrain_frame@split_capacity@method=polynomial@order=5..."
  /// (the parts that are set).
  [[nodiscard]] std::string key() const;
  /// The variant as format `format` reads it: the trajectory options left out unless the format uses them
  /// (exporting::Format::trajectory_options), split_capacity unless it splits per sortie. Two variants
  /// that make the same files of a format have the same for_format(format).key() (one cache entry).
  [[nodiscard]] ExportVariant for_format(std::string_view format) const;
};

/// The artifact a split export (ExportVariant::split_capacity) serves for UAV `id` of a format whose
/// files end in `extension` (".plan", ".kmz"): "export/<id><extension>.zip", the zip of its missions
/// <id>.s<k><extension> in flight order.
std::string split_zip_name(const std::string& id, std::string_view extension);

/// Makes export format `format` (one of exporting::known_formats()) of the plan stored as plan.json and
/// paths.geojson (the texts a plan job stored), with the options of a plan job: the same bytes a plan
/// job's eager export of the same plan gave. A stop request throws Cancelled; OperationError when the
/// documents are not a plan.
/// `load_terrain`: sets the mission's ground heights when its terrain block names a source the caller
/// reads (the server's stored DEMs and tiles, issue 31); empty: a plan with terrain is refused.
/// `variant`: the client's export options; a split export's per-sortie files come as one zip per UAV
/// (split_zip_name()), and a format that has no such split (geojson, trajectory) ignores it as the CLI does.
BuiltExport build_export(const std::string& plan_json, const std::string& paths_geojson,
                         const std::string& format, double trajectory_step_s = 0, const Context& ctx = {},
                         const std::function<void(Mission&)>& load_terrain = {},
                         const ExportVariant& variant = {});

}  // namespace uavcover::usecases
