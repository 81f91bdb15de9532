// The charts: the histogram of scans, the multi-UAV study and the terrain profile of a leg.
#include <cairo-svg.h>
#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <numbers>

#include "evaluation/evaluate.hpp"
#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "render/canvas_internal.hpp"
#include "render/render.hpp"
#include "uavcover/error.hpp"

namespace uavcover::render {

using namespace detail;

namespace {

void draw_histogram(cairo_t* cr, const evaluation::CoverageStats& st, int width, int height,
                    const std::string& title) {
  const double margin = 40;
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  text(cr, margin, margin, title, 20, 0.0, true);
  const double left = margin + 50, right = width - margin, top = margin + 30, bottom = height - margin - 40;
  const std::size_t n = std::max<std::size_t>(st.histogram.size(), 1);
  // axes and grid
  cairo_set_line_width(cr, 1);
  for (int k = 0; k <= 5; ++k) {
    const double y = bottom - (bottom - top) * k / 5.0;
    cairo_set_source_rgb(cr, 0.85, 0.85, 0.85);
    cairo_move_to(cr, left, y);
    cairo_line_to(cr, right, y);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    text(cr, left - 8, y, fmt::format("{:.1f}", k / 5.0), 13, 1.0, false, 0.5);
  }
  const double slot = (right - left) / static_cast<double>(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double v = k < st.histogram.size() ? st.histogram[k] : 0.0;
    const double x = left + slot * static_cast<double>(k) + slot * 0.15;
    const double h = (bottom - top) * std::clamp(v, 0.0, 1.0);
    cairo_rectangle(cr, x, bottom - h, slot * 0.7, h);
    set(cr, scan_colour(static_cast<int>(k), std::max(static_cast<int>(n) - 1, 1)));
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    text(cr, x + slot * 0.35, bottom + 20, std::to_string(k), 13, 0.5);
    if (v > 0) text(cr, x + slot * 0.35, bottom - h - 6, fmt::format("{:.3f}", v), 12, 0.5);
  }
  axes(cr, left, top, right, bottom, "number of scans", height - margin + 5, "share of samples", margin - 10);
  text(cr, right, margin, fmt::format("PoC {:.2f}%  PoOC {:.2f}%", 100 * st.poc, 100 * st.pooc), 14, 1.0);
}

struct Series {
  std::string name;
  Rgb colour;
  std::vector<double> values;
};

void draw_chart(cairo_t* cr, const std::vector<int>& xs, const std::vector<Series>& series, double left,
                double top, double right, double bottom, const std::string& ylabel, int recommended) {
  double ymax = 0;
  for (const auto& s : series)
    for (double v : s.values) ymax = std::max(ymax, v);
  const double step = nice_step(ymax > 0 ? ymax : 1, 5);
  ymax = step * std::ceil((ymax > 0 ? ymax : 1) / step);
  const int xmin = xs.empty() ? 0 : *std::min_element(xs.begin(), xs.end());
  int xmax = xs.empty() ? 1 : *std::max_element(xs.begin(), xs.end());
  if (xmax == xmin) xmax = xmin + 1;
  auto px = [&](double x) { return left + (right - left) * (x - xmin) / (xmax - xmin); };
  auto py = [&](double y) { return bottom - (bottom - top) * y / ymax; };
  y_grid(cr, left, right, 0.0, ymax, step, py);
  for (int x : xs) text(cr, px(x), bottom + 18, std::to_string(x), 12, 0.5);
  if (recommended > 0) {
    const double dash[] = {5.0, 4.0};
    cairo_set_dash(cr, dash, 2, 0);
    cairo_set_source_rgb(cr, 0.4, 0.4, 0.4);
    cairo_move_to(cr, px(recommended), top);
    cairo_line_to(cr, px(recommended), bottom);
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0);
    const bool right_half = px(recommended) > 0.5 * (left + right);
    text(cr, px(recommended) + (right_half ? -4 : 4), bottom - 8, fmt::format("recommended: {}", recommended),
         12, right_half ? 1.0 : 0.0);
  }
  for (const auto& s : series) {
    set(cr, s.colour);
    cairo_set_line_width(cr, 2.5);
    for (std::size_t i = 0; i < xs.size() && i < s.values.size(); ++i) {
      if (i == 0)
        cairo_move_to(cr, px(xs[i]), py(s.values[i]));
      else
        cairo_line_to(cr, px(xs[i]), py(s.values[i]));
    }
    cairo_stroke(cr);
    for (std::size_t i = 0; i < xs.size() && i < s.values.size(); ++i) {
      cairo_arc(cr, px(xs[i]), py(s.values[i]), 4, 0, 2 * std::numbers::pi);
      cairo_fill(cr);
    }
  }
  axes(cr, left, top, right, bottom, "", bottom, ylabel, left - 52);  // the caller labels the x axis
  // legend, top right
  double ly = top + 14;
  for (const auto& s : series) {
    set(cr, s.colour);
    cairo_set_line_width(cr, 2.5);
    cairo_move_to(cr, right - 170, ly - 5);
    cairo_line_to(cr, right - 145, ly - 5);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    text(cr, right - 138, ly, s.name, 13);
    ly += 20;
  }
}

void draw_study(cairo_t* cr, const std::vector<StudyPoint>& pts, int width, int height, int recommended,
                const std::string& title) {
  const double margin = 40;
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  text(cr, margin, margin, title, 20, 0.0, true);
  std::vector<int> xs;
  Series total{"total time", {0.84, 0.15, 0.16}, {}}, flight{"flight time", {0.12, 0.47, 0.71}, {}},
      cost{"flight cost", {0.17, 0.63, 0.17}, {}};
  for (const auto& p : pts) {
    xs.push_back(p.uavs);
    total.values.push_back(p.total_time_min);
    flight.values.push_back(p.flight_time_min);
    cost.values.push_back(p.cost_eur);
  }
  const double left = margin + 70, right = width - margin - 20;
  const double mid = margin + 30 + (height - 2 * margin - 30) * 0.62;
  draw_chart(cr, xs, {total, flight}, left, margin + 30, right, mid - 30, "time (min)", recommended);
  draw_chart(cr, xs, {cost}, left, mid + 20, right, height - margin - 30, "cost (EUR)", recommended);
  text(cr, 0.5 * (left + right), height - margin + 15, "number of UAVs", 14, 0.5);
}

void draw_profile(cairo_t* cr, const waypoints::LegProfile& lp, int width, int height) {
  const double margin = 40;
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  text(cr, margin, margin,
       fmt::format("Terrain following: uav {}, coverage leg from waypoint {} ({:.0f} m)", lp.uav,
                   lp.first_waypoint, lp.length_m),
       20, 0.0, true);
  const double left = margin + 70, right = width - margin - 20, top = margin + 40,
               bottom = height - margin - 40;
  double lo = 1e300, hi = -1e300;
  for (const auto& [s, g] : lp.ground)
    lo = std::min(lo, g), hi = std::max(hi, g + lp.altitude_m + lp.tolerance_m);
  for (const auto& [s, z] : lp.flight) lo = std::min(lo, z), hi = std::max(hi, z);
  if (!(hi > lo)) hi = lo + 1;
  const double step = nice_step(hi - lo, 6);
  lo = step * std::floor(lo / step) - step;
  hi = step * std::ceil(hi / step);
  const double len = std::max(lp.length_m, 1e-6);
  auto px = [&](double s) { return left + (right - left) * s / len; };
  auto py = [&](double z) { return bottom - (bottom - top) * (z - lo) / (hi - lo); };
  y_grid(cr, left, right, lo, hi, step, py);
  const double sstep = nice_step(len, 8);
  for (double s = 0; s <= len + 1e-9; s += sstep)
    text(cr, px(s), bottom + 18, fmt::format("{:g}", s), 12, 0.5);
  if (lp.ground.empty()) return;
  // ground, filled
  cairo_move_to(cr, px(lp.ground.front().first), py(lo));
  for (const auto& [s, g] : lp.ground) cairo_line_to(cr, px(s), py(g));
  cairo_line_to(cr, px(lp.ground.back().first), py(lo));
  cairo_close_path(cr);
  cairo_set_source_rgb(cr, 0.72, 0.6, 0.42);
  cairo_fill(cr);
  // the band the camera should fly in: ground + altitude +- tolerance
  if (lp.tolerance_m > 0) {
    for (std::size_t k = 0; k < lp.ground.size(); ++k)
      (k == 0 ? cairo_move_to : cairo_line_to)(cr, px(lp.ground[k].first),
                                               py(lp.ground[k].second + lp.altitude_m + lp.tolerance_m));
    for (std::size_t k = lp.ground.size(); k-- > 0;)
      cairo_line_to(cr, px(lp.ground[k].first), py(lp.ground[k].second + lp.altitude_m - lp.tolerance_m));
    cairo_close_path(cr);
    cairo_set_source_rgba(cr, 0.17, 0.63, 0.17, 0.3);
    cairo_fill(cr);
  }
  // ground + altitude, dashed
  const double dash[] = {6.0, 4.0};
  cairo_set_dash(cr, dash, 2, 0);
  cairo_set_source_rgb(cr, 0.17, 0.5, 0.17);
  cairo_set_line_width(cr, 1.5);
  for (std::size_t k = 0; k < lp.ground.size(); ++k)
    (k == 0 ? cairo_move_to : cairo_line_to)(cr, px(lp.ground[k].first),
                                             py(lp.ground[k].second + lp.altitude_m));
  cairo_stroke(cr);
  cairo_set_dash(cr, nullptr, 0, 0);
  // the flight: straight between the waypoints, which are marked
  cairo_set_source_rgb(cr, 0.12, 0.47, 0.71);
  cairo_set_line_width(cr, 2.5);
  for (std::size_t k = 0; k < lp.flight.size(); ++k)
    (k == 0 ? cairo_move_to : cairo_line_to)(cr, px(lp.flight[k].first), py(lp.flight[k].second));
  cairo_stroke(cr);
  for (const auto& [s, z] : lp.flight) {
    cairo_arc(cr, px(s), py(z), 4, 0, 2 * std::numbers::pi);
    cairo_fill(cr);
  }
  axes(cr, left, top, right, bottom, "distance along the leg (m)", height - margin + 15,
       "height above mean sea level (m)", left - 55);
  // legend
  double ly = top + 16;
  auto entry = [&](Rgb c, const std::string& label) {
    set(cr, c);
    cairo_rectangle(cr, right - 330, ly - 10, 22, 10);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    text(cr, right - 300, ly, label, 13);
    ly += 20;
  };
  entry({0.12, 0.47, 0.71},
        fmt::format("flight ({} waypoints, {} added for terrain)", lp.flight.size(), lp.terrain_waypoints));
  entry({0.17, 0.5, 0.17}, fmt::format("ground + {:g} m (camera altitude)", lp.altitude_m));
  if (lp.tolerance_m > 0) entry({0.55, 0.8, 0.55}, fmt::format("tolerance +-{:g} m", lp.tolerance_m));
  entry({0.72, 0.6, 0.42}, "ground (DEM, bilinear)");
}

}  // namespace

Artifact terrain_profile_png(const waypoints::LegProfile& profile, std::string name, int width, int height) {
  return png(std::move(name), width, height, [&](cairo_t* cr) { draw_profile(cr, profile, width, height); });
}

Artifact histogram_png(const evaluation::CoverageStats& stats, std::string name, int width, int height,
                       const std::string& title) {
  return png(std::move(name), width, height,
             [&](cairo_t* cr) { draw_histogram(cr, stats, width, height, title); });
}

Artifact study_png(const std::vector<StudyPoint>& points, std::string name, int width, int height,
                   int recommended, const std::string& title) {
  return png(std::move(name), width, height,
             [&](cairo_t* cr) { draw_study(cr, points, width, height, recommended, title); });
}

}  // namespace uavcover::render
