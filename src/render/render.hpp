// Report pictures with Cairo: the plan (PNG and SVG), the coverage heatmap, the scan histogram,
// the multi-UAV study chart and the trajectory plot, as bytes (src/io writes them). A picture size
// outside 64..20000 pixels is an InputError ("size").
#pragma once

#include <string>
#include <vector>

#include "evaluation/coverage.hpp"
#include "trajectory/trajectory.hpp"
#include "uavcover/artifact.hpp"
#include "uavcover/plan.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::render {

/// Area, no-fly zones, each UAV's region (its polygons) shaded and its path in its own colour,
/// starts marked, legend, scale bar and north arrow. Geometry is drawn at pixel resolution, so the
/// size of the picture follows its pixels, not the mission's vertex count.
Artifact plan_png(const Plan& plan, std::string name = "plan.png", int width = 1600, int height = 1200);
Artifact plan_svg(const Plan& plan, std::string name = "plan.svg", int width = 1600, int height = 1200);

/// Several plans side by side (one panel each, titled), e.g. the planners of `uavcover compare`.
struct Panel {
  std::string title;
  const Plan* plan = nullptr;
};
Artifact plans_png(const std::vector<Panel>& panels, std::string name = "compare.png", int panel_width = 900,
                   int panel_height = 700);

/// Scans per lattice sample (CoverageResult::scans), discrete colours with a legend; `free` (local
/// metres, the frame of the evaluation), when given, is drawn over it as an outline.
Artifact heatmap_png(const evaluation::CoverageResult& coverage, const MultiPolygon* free = nullptr,
                     std::string name = "heatmap.png", int width = 1200, int height = 900,
                     const std::string& title = "Coverage heatmap");

/// The coverage lattice alone, to lay over a map: one pixel per sample, north up, the heatmap's colours,
/// transparent outside the area; sample (c, r) is pixel (c, rows-1-r), so the picture spans
/// [origin - lattice_m/2, origin + (cols or rows - 1/2) lattice_m] in the local frame.
/// Refused (InputError "size") when the lattice is empty or over 20000 samples on a side.
Artifact heatmap_overlay_png(const evaluation::CoverageResult& coverage,
                             std::string name = "heatmap-overlay.png");

/// Normalised histogram of scans (0, 1, 2, ...).
Artifact histogram_png(const evaluation::CoverageStats& stats, std::string name = "histogram.png",
                       int width = 900, int height = 600, const std::string& title = "Histogram of coverage");

struct StudyPoint {
  int uavs = 0;
  double flight_time_min = 0.0;
  double total_time_min = 0.0;
  double cost_eur = 0.0;
};

/// Total time, flight time (min) and flight cost (EUR) against the UAV count; `recommended` (if
/// > 0) is marked.
Artifact study_png(const std::vector<StudyPoint>& points, std::string name = "study.png", int width = 1200,
                   int height = 800, int recommended = 0, const std::string& title = "Multi-UAV study");

/// Ground (filled) and flight height along one coverage leg (waypoints::leg_profile): the waypoints
/// flown, the camera's height above the ground and the tolerance band around it.
Artifact terrain_profile_png(const waypoints::LegProfile& profile, std::string name = "terrain-profile.png",
                             int width = 1400, int height = 700);

/// Position, velocity and acceleration (x, y, z; |v| and |a| too) of one trajectory against time, three
/// stacked panels, the limits dashed (v_max, v_min, a_max, a_min: the polynomial method's bounds, else
/// +-v_max and +-a_max), each curve drawn per pixel column as the range it spans there. A side outside
/// 320..20000 pixels is an InputError ("size").
Artifact trajectory_png(const trajectory::Trajectory& trajectory, std::string name, const std::string& title,
                        int width = 1400, int height = 1000);

/// The colour of UAV i (r, g, b in [0, 1]).
struct Rgb {
  double r, g, b;
};
Rgb uav_colour(std::size_t i);

}  // namespace uavcover::render
