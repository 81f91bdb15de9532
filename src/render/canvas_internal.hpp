// Internal to src/render: the canvas the pictures draw on (canvas.cpp): PNG and SVG surfaces, text,
// nice axis steps, the map view, paths, scale bar, north arrow, chart axes and the scan colours. The
// pictures are in plan_map.cpp, heatmap.cpp and charts.cpp.
#pragma once

#include <cairo.h>

#include <cmath>
#include <functional>
#include <memory>
#include <string>

#include "geometry/geometry.hpp"
#include "render/render.hpp"

namespace uavcover::render::detail {

using SurfacePtr = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using CairoPtr = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

/// A cairo write function appending to a std::string (`closure`).
cairo_status_t append_bytes(void* closure, const unsigned char* data, unsigned int length);
/// Draws with `draw` on a PNG surface and returns the PNG bytes.
Artifact png(std::string name, int width, int height, const std::function<void(cairo_t*)>& draw);
/// The same drawing as SVG bytes.
Artifact svg(std::string name, int width, int height, const std::function<void(cairo_t*)>& draw);

void set(cairo_t* cr, Rgb c, double a = 1.0);
void text(cairo_t* cr, double x, double y, const std::string& s, double size, double align = 0.0,
          bool bold = false, double valign = 0.0);

/// Nice number 1, 2 or 5 x 10^k not above v.
double nice_floor(double v);
/// Nice axis step for a range shown with about `n` ticks.
double nice_step(double range, int n);
/// A chart's horizontal grid: a light line and a label left of the axis at every `step` from lo to hi.
void y_grid(cairo_t* cr, double left, double right, double lo, double hi, double step,
            const std::function<double(double)>& py);
/// The left and bottom axes of a chart, with the x label centred at `xlabel_y` and the y label turned
/// upright at `ylabel_x`.
void axes(cairo_t* cr, double left, double top, double right, double bottom, const std::string& xlabel,
          double xlabel_y, const std::string& ylabel, double ylabel_x);

struct View {
  double scale = 1.0, ox = 0.0, oy = 0.0;  // pixel = (ox + scale*x, oy - scale*y)
  [[nodiscard]] double px(double x) const { return ox + scale * x; }
  [[nodiscard]] double py(double y) const { return oy - scale * y; }
};

/// The view that fits `box` into the pixel rectangle (left, top)-(right, bottom).
View fit(const bg::model::box<Point>& box, double left, double top, double right, double bottom);

/// Moves along the points in pixels, skipping points within a quarter pixel of the last one drawn,
/// so that a picture's size follows its pixels, not the geometry's vertex count.
void path_points(cairo_t* cr, const View& v, const auto& pts) {
  bool first = true;
  double lx = 0, ly = 0;
  std::size_t k = 0;
  for (const auto& p : pts) {
    const double x = v.px(p.x()), y = v.py(p.y());
    const bool last = ++k == pts.size();
    if (first) {
      cairo_move_to(cr, x, y);
    } else if (last || std::fabs(x - lx) + std::fabs(y - ly) >= 0.25) {
      cairo_line_to(cr, x, y);
    } else {
      continue;
    }
    lx = x, ly = y, first = false;
  }
}

void path_ring(cairo_t* cr, const View& v, const auto& ring) {
  path_points(cr, v, ring);
  cairo_close_path(cr);
}

void path_multipolygon(cairo_t* cr, const View& v, const MultiPolygon& mp);
void scale_bar(cairo_t* cr, const View& v, double x, double y, double max_px);
void north_arrow(cairo_t* cr, double x, double y, double size);

/// Colour of a scan count: 0 light red, 1.. a sequential blue-green-yellow scale.
Rgb scan_colour(int k, int max_k);

}  // namespace uavcover::render::detail
