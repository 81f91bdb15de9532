// Report pictures with Cairo: the plan (PNG and SVG), the coverage heatmap, the scan histogram
// and the multi-UAV study chart. All throw InputError("out", ...) when the file cannot be written.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "evaluation/coverage.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::render {

/// Area, no-fly zones, each UAV's region (Plan::grid owners) shaded and its path in its own colour,
/// starts marked, legend, scale bar and north arrow.
void write_plan_png(const Plan& plan, const std::filesystem::path& path, int width = 1600, int height = 1200);
void write_plan_svg(const Plan& plan, const std::filesystem::path& path, int width = 1600, int height = 1200);

/// Scans per lattice sample (CoverageResult::scans), discrete colours with a legend.
void write_heatmap_png(const evaluation::CoverageResult& coverage, const std::filesystem::path& path,
                       int width = 1200, int height = 900, const std::string& title = "Coverage heatmap");

/// The same with the free area's boundary (local metres, the frame of the evaluation) drawn over it.
void write_heatmap_png(const evaluation::CoverageResult& coverage, const MultiPolygon& free,
                       const std::filesystem::path& path, int width = 1200, int height = 900,
                       const std::string& title = "Coverage heatmap");

/// Normalised histogram of scans (0, 1, 2, ...).
void write_histogram_png(const evaluation::CoverageStats& stats, const std::filesystem::path& path,
                         int width = 900, int height = 600,
                         const std::string& title = "Histogram of coverage");

struct StudyPoint {
  int uavs = 0;
  double flight_time_min = 0.0;
  double total_time_min = 0.0;
  double cost_eur = 0.0;
};

/// Total time, flight time (min) and flight cost (EUR) against the UAV count; `recommended` (if
/// > 0) is marked.
void write_study_png(const std::vector<StudyPoint>& points, const std::filesystem::path& path,
                     int width = 1200, int height = 800, int recommended = 0,
                     const std::string& title = "Multi-UAV study");

/// The colour of UAV i (r, g, b in [0, 1]).
struct Rgb {
  double r, g, b;
};
Rgb uav_colour(std::size_t i);

}  // namespace uavcover::render
