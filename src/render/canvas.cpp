// The canvas of the report pictures (Cairo): PNG and SVG surfaces, text, axes, the map view and its
// paths, scale bar, north arrow, and the colours of UAVs and scan counts.
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

namespace detail {

namespace {

void check_size(int width, int height) {
  if (width < 64 || height < 64 || width > 20000 || height > 20000)
    throw InputError("size",
                     fmt::format("picture size {}x{} must be within 64..20000 pixels", width, height));
}

}  // namespace

cairo_status_t append_bytes(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

/// Draws with `draw` on a PNG surface and returns the PNG bytes.
Artifact png(std::string name, int width, int height, const std::function<void(cairo_t*)>& draw) {
  check_size(width, height);
  SurfacePtr s(cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width, height), cairo_surface_destroy);
  if (cairo_surface_status(s.get()) != CAIRO_STATUS_SUCCESS) throw OperationError("cannot draw " + name);
  CairoPtr cr(cairo_create(s.get()), cairo_destroy);
  cairo_set_source_rgb(cr.get(), 1, 1, 1);
  cairo_paint(cr.get());
  draw(cr.get());
  cairo_surface_flush(s.get());
  Artifact out{std::move(name), "image/png", {}};
  if (cairo_surface_write_to_png_stream(s.get(), append_bytes, &out.bytes) != CAIRO_STATUS_SUCCESS)
    throw OperationError("cannot encode " + out.name);
  return out;
}

/// The same drawing as SVG bytes.
Artifact svg(std::string name, int width, int height, const std::function<void(cairo_t*)>& draw) {
  check_size(width, height);
  Artifact out{std::move(name), "image/svg+xml", {}};
  SurfacePtr s(cairo_svg_surface_create_for_stream(append_bytes, &out.bytes, width, height),
               cairo_surface_destroy);
  if (cairo_surface_status(s.get()) != CAIRO_STATUS_SUCCESS) throw OperationError("cannot draw " + out.name);
  {
    CairoPtr cr(cairo_create(s.get()), cairo_destroy);
    cairo_set_source_rgb(cr.get(), 1, 1, 1);
    cairo_paint(cr.get());
    draw(cr.get());
  }
  cairo_surface_finish(s.get());
  if (cairo_surface_status(s.get()) != CAIRO_STATUS_SUCCESS)
    throw OperationError("cannot encode " + out.name);
  return out;
}

void set(cairo_t* cr, Rgb c, double a) { cairo_set_source_rgba(cr, c.r, c.g, c.b, a); }

void text(cairo_t* cr, double x, double y, const std::string& s, double size, double align, bool bold,
          double valign) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  cairo_move_to(cr, x - align * e.x_advance, y + valign * size * 0.7);
  cairo_show_text(cr, s.c_str());
}

/// Nice number 1, 2 or 5 x 10^k not above v.
double nice_floor(double v) {
  if (!(v > 0)) return 1.0;
  const double p = std::pow(10.0, std::floor(std::log10(v)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * p <= v) return m * p;
  return p;
}

/// Nice axis step for a range shown with about `n` ticks.
double nice_step(double range, int n) {
  if (!(range > 0)) return 1.0;
  const double raw = range / n;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * p >= raw) return m * p;
  return 10 * p;
}

/// A chart's horizontal grid: a light line and a label left of the axis at every `step` from lo to hi.
void y_grid(cairo_t* cr, double left, double right, double lo, double hi, double step,
            const std::function<double(double)>& py) {
  cairo_set_line_width(cr, 1);
  for (double y = lo; y <= hi + 1e-9; y += step) {
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, left, py(y));
    cairo_line_to(cr, right, py(y));
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    text(cr, left - 8, py(y), fmt::format("{:g}", y), 12, 1.0, false, 0.5);
  }
}

View fit(const bg::model::box<Point>& box, double left, double top, double right, double bottom) {
  const double bw = std::max(box.max_corner().x() - box.min_corner().x(), 1e-6);
  const double bh = std::max(box.max_corner().y() - box.min_corner().y(), 1e-6);
  View v;
  v.scale = std::min((right - left) / bw, (bottom - top) / bh);
  const double cx = 0.5 * (box.min_corner().x() + box.max_corner().x());
  const double cy = 0.5 * (box.min_corner().y() + box.max_corner().y());
  v.ox = 0.5 * (left + right) - v.scale * cx;
  v.oy = 0.5 * (top + bottom) + v.scale * cy;
  return v;
}

void path_multipolygon(cairo_t* cr, const View& v, const MultiPolygon& mp) {
  for (const auto& poly : mp) {
    path_ring(cr, v, poly.outer());
    for (const auto& in : poly.inners()) path_ring(cr, v, in);
  }
}

void scale_bar(cairo_t* cr, const View& v, double x, double y, double max_px) {
  const double metres = nice_floor(max_px / v.scale);
  const double len = metres * v.scale;
  cairo_set_line_width(cr, 1.0);
  for (int k = 0; k < 4; ++k) {
    cairo_rectangle(cr, x + k * len / 4, y, len / 4, 8);
    if (k % 2 == 0)
      cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    else
      cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_stroke(cr);
  }
  const std::string label =
      metres >= 1000 ? fmt::format("{:g} km", metres / 1000) : fmt::format("{:g} m", metres);
  text(cr, x, y - 6, "0", 13, 0.5);
  text(cr, x + len, y - 6, label, 13, 0.5);
}

void north_arrow(cairo_t* cr, double x, double y, double size) {
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_move_to(cr, x, y - size);
  cairo_line_to(cr, x + size * 0.4, y + size * 0.5);
  cairo_line_to(cr, x, y + size * 0.2);
  cairo_close_path(cr);
  cairo_fill(cr);
  cairo_move_to(cr, x, y - size);
  cairo_line_to(cr, x - size * 0.4, y + size * 0.5);
  cairo_line_to(cr, x, y + size * 0.2);
  cairo_close_path(cr);
  cairo_set_line_width(cr, 1.5);
  cairo_stroke(cr);
  text(cr, x, y - size - 6, "N", 16, 0.5, true);
}

/// Colour of a scan count: 0 light red, 1.. a sequential blue-green-yellow scale.
Rgb scan_colour(int k, int max_k) {
  if (k <= 0) return {0.98, 0.80, 0.78};
  static const Rgb ramp[] = {
      {0.27, 0.00, 0.33}, {0.23, 0.32, 0.55}, {0.13, 0.57, 0.55}, {0.37, 0.79, 0.38}, {0.99, 0.91, 0.15}};
  const double t = max_k <= 1 ? 0.5 : static_cast<double>(k - 1) / (max_k - 1);
  const double x = t * 4.0;
  const int i = std::min(3, static_cast<int>(x));
  const double f = x - i;
  return {ramp[i].r + f * (ramp[i + 1].r - ramp[i].r), ramp[i].g + f * (ramp[i + 1].g - ramp[i].g),
          ramp[i].b + f * (ramp[i + 1].b - ramp[i].b)};
}

/// The left and bottom axes of a chart, with the x label centred at `xlabel_y` and the y label turned
/// upright at `ylabel_x`.
void axes(cairo_t* cr, double left, double top, double right, double bottom, const std::string& xlabel,
          double xlabel_y, const std::string& ylabel, double ylabel_x) {
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_set_line_width(cr, 1);
  cairo_move_to(cr, left, top);
  cairo_line_to(cr, left, bottom);
  cairo_line_to(cr, right, bottom);
  cairo_stroke(cr);
  text(cr, 0.5 * (left + right), xlabel_y, xlabel, 14, 0.5);
  cairo_save(cr);
  cairo_translate(cr, ylabel_x, 0.5 * (top + bottom));
  cairo_rotate(cr, -std::numbers::pi / 2);
  text(cr, 0, 0, ylabel, 14, 0.5);
  cairo_restore(cr);
}

}  // namespace detail

Rgb uav_colour(std::size_t i) {
  static const Rgb palette[] = {
      {0.12, 0.47, 0.71}, {1.00, 0.50, 0.05}, {0.17, 0.63, 0.17}, {0.84, 0.15, 0.16}, {0.58, 0.40, 0.74},
      {0.55, 0.34, 0.29}, {0.89, 0.47, 0.76}, {0.50, 0.50, 0.50}, {0.74, 0.74, 0.13}, {0.09, 0.75, 0.81}};
  const Rgb base = palette[i % 10];
  if (i < 10) return base;
  // later rounds: darker variants
  const double f = (i / 10) % 2 == 1 ? 0.6 : 0.8;
  return {base.r * f, base.g * f, base.b * f};
}

}  // namespace uavcover::render
