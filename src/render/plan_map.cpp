// The plan map (PNG and SVG) and several plans side by side.
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

void draw_plan(cairo_t* cr, const Plan& plan, int width, int height) {
  const geodesy::LocalFrame frame(plan.origin);
  const MultiPolygon area = geometry::unite(geometry::to_local(plan.mission.area, frame));
  const MultiPolygon nfz = geometry::unite(geometry::to_local(plan.mission.no_fly_zones, frame));
  std::vector<Point> starts;
  std::vector<std::size_t> start_uav;
  for (std::size_t i = 0; i < plan.mission.uavs.size(); ++i) {
    const auto& u = plan.mission.uavs[i];
    if (u.start_resolved == LonLat{} && !u.start) continue;  // never resolved
    starts.push_back(frame.to_local(u.start_resolved));
    start_uav.push_back(i);
  }

  bg::model::box<Point> box;
  bg::envelope(area, box);
  auto extend = [&](Point p) { bg::expand(box, p); };
  for (const auto& u : plan.uavs)
    for (const auto& part : u.parts)
      for (const auto& p : part.local) extend(p);
  for (const auto& p : starts) extend(p);

  const double legend_w = std::min(300.0, width * 0.25);
  const double margin = 40;
  const View v = fit(box, margin, margin + 30, width - legend_w - margin, height - margin - 40);

  // title
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  const std::string title = plan.mission.name.empty() ? "Coverage plan" : plan.mission.name;
  text(cr, margin, margin, title, 20, 0.0, true);

  // area
  cairo_set_fill_rule(cr, CAIRO_FILL_RULE_EVEN_ODD);
  path_multipolygon(cr, v, area);
  cairo_set_source_rgb(cr, 0.95, 0.95, 0.93);
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
  cairo_set_line_width(cr, 2.0);
  cairo_stroke(cr);

  // regions: each UAV's polygons (inside the free area), shaded in its colour
  for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
    if (plan.uavs[i].region_local.empty()) continue;
    path_multipolygon(cr, v, plan.uavs[i].region_local);
    set(cr, uav_colour(i), 0.22);
    cairo_fill(cr);
  }

  // no-fly zones: hatched red
  if (!nfz.empty()) {
    path_multipolygon(cr, v, nfz);
    cairo_set_source_rgba(cr, 0.85, 0.2, 0.2, 0.25);
    cairo_fill_preserve(cr);
    cairo_save(cr);
    cairo_clip_preserve(cr);
    cairo_new_path(cr);
    cairo_set_source_rgba(cr, 0.75, 0.1, 0.1, 0.5);
    cairo_set_line_width(cr, 1.0);
    for (double d = -height; d < width + height; d += 10) {
      cairo_move_to(cr, d, 0);
      cairo_line_to(cr, d + height, height);
    }
    cairo_stroke(cr);
    cairo_restore(cr);
    path_multipolygon(cr, v, nfz);
    cairo_set_source_rgb(cr, 0.7, 0.1, 0.1);
    cairo_set_line_width(cr, 2.0);
    cairo_stroke(cr);
  }

  // paths
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
    const Rgb col = uav_colour(i);
    for (const auto& part : plan.uavs[i].parts) {
      if (part.local.size() < 2) continue;
      path_points(cr, v, part.local);
      if (part.kind == PartKind::Transit) {
        const double dash[] = {6.0, 4.0};
        cairo_set_dash(cr, dash, 2, 0);
        cairo_set_line_width(cr, 1.5);
      } else {
        cairo_set_dash(cr, nullptr, 0, 0);
        cairo_set_line_width(cr, 2.2);
      }
      set(cr, Rgb{col.r * 0.8, col.g * 0.8, col.b * 0.8});
      cairo_stroke(cr);
    }
  }
  cairo_set_dash(cr, nullptr, 0, 0);

  // starts
  for (std::size_t i = 0; i < starts.size(); ++i) {
    const double x = v.px(starts[i].x()), y = v.py(starts[i].y());
    cairo_new_path(cr);
    cairo_arc(cr, x, y, 7, 0, 2 * std::numbers::pi);
    set(cr, uav_colour(start_uav[i]));
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 2);
    cairo_stroke(cr);
  }

  // legend
  const double lx = width - legend_w - 10;
  double ly = margin + 30;
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  text(cr, lx, ly, "UAVs", 16, 0.0, true);
  ly += 12;
  const std::size_t shown = std::min<std::size_t>(plan.uavs.size(), 20);
  for (std::size_t i = 0; i < shown; ++i) {
    ly += 22;
    cairo_rectangle(cr, lx, ly - 12, 22, 14);
    set(cr, uav_colour(i), 0.4);
    cairo_fill_preserve(cr);
    set(cr, uav_colour(i));
    cairo_set_line_width(cr, 2);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    const auto& u = plan.uavs[i];
    double len = 0.0;
    for (const auto& part : u.parts) len += geometry::length(part.local);
    text(cr, lx + 30, ly, fmt::format("{}  {:.1f}%  {:.2f} km", u.id, 100 * u.share_actual, len / 1000), 13);
  }
  if (plan.uavs.size() > shown) {
    ly += 22;
    text(cr, lx, ly, fmt::format("... {} more", plan.uavs.size() - shown), 13);
  }
  ly += 34;
  cairo_set_line_width(cr, 2.2);
  cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
  cairo_move_to(cr, lx, ly - 5);
  cairo_line_to(cr, lx + 22, ly - 5);
  cairo_stroke(cr);
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  text(cr, lx + 30, ly, "coverage path", 13);
  ly += 22;
  const double dash[] = {6.0, 4.0};
  cairo_set_dash(cr, dash, 2, 0);
  cairo_set_line_width(cr, 1.5);
  cairo_move_to(cr, lx, ly - 5);
  cairo_line_to(cr, lx + 22, ly - 5);
  cairo_stroke(cr);
  cairo_set_dash(cr, nullptr, 0, 0);
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  text(cr, lx + 30, ly, "transit", 13);
  ly += 22;
  cairo_new_path(cr);
  cairo_arc(cr, lx + 11, ly - 5, 6, 0, 2 * std::numbers::pi);
  cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_stroke(cr);
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  text(cr, lx + 30, ly, "start / return", 13);
  if (!nfz.empty()) {
    ly += 22;
    cairo_rectangle(cr, lx, ly - 12, 22, 14);
    cairo_set_source_rgba(cr, 0.85, 0.2, 0.2, 0.4);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.7, 0.1, 0.1);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    text(cr, lx + 30, ly, "no-fly zone", 13);
  }
  ly += 34;
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  text(cr, lx, ly,
       fmt::format("spacing {:.1f} m, {} mode", plan.mission.spacing_m,
                   plan.mission.mode == Mode::Strict ? "strict" : "coverage"),
       13);
  ly += 20;
  text(cr, lx, ly, fmt::format("free area {:.3f} km\u00b2", plan.free_area_m2 / 1e6), 13);

  north_arrow(cr, width - legend_w - margin - 20, height - margin - 60, 22);
  scale_bar(cr, v, margin, height - margin - 10, (width - legend_w) * 0.25);
}

}  // namespace

Artifact plan_png(const Plan& plan, std::string name, int width, int height) {
  return png(std::move(name), width, height, [&](cairo_t* cr) { draw_plan(cr, plan, width, height); });
}

Artifact plan_svg(const Plan& plan, std::string name, int width, int height) {
  return svg(std::move(name), width, height, [&](cairo_t* cr) { draw_plan(cr, plan, width, height); });
}

Artifact plans_png(const std::vector<Panel>& panels, std::string name, int panel_width, int panel_height) {
  const int n = static_cast<int>(panels.size());
  const int cols = n <= 3 ? std::max(1, n) : static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  const int rows = std::max(1, (n + cols - 1) / cols);
  const int width = cols * panel_width, height = rows * panel_height;
  return png(std::move(name), width, height, [&](cairo_t* cr) {
    for (int k = 0; k < n; ++k) {
      cairo_save(cr);
      cairo_translate(cr, (k % cols) * panel_width, (k / cols) * panel_height);
      cairo_rectangle(cr, 0, 0, panel_width, panel_height);
      cairo_clip(cr);
      Plan titled = *panels[static_cast<std::size_t>(k)].plan;
      titled.mission.name = panels[static_cast<std::size_t>(k)].title;
      draw_plan(cr, titled, panel_width, panel_height);
      cairo_restore(cr);
      if (k % cols != 0) {  // a thin rule between panels
        cairo_set_source_rgb(cr, 0.8, 0.8, 0.8);
        cairo_set_line_width(cr, 1.0);
        cairo_move_to(cr, (k % cols) * panel_width + 0.5, (k / cols) * panel_height);
        cairo_line_to(cr, (k % cols) * panel_width + 0.5, (k / cols + 1) * panel_height);
        cairo_stroke(cr);
      }
    }
  });
}

}  // namespace uavcover::render
