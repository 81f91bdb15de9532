#include "render/render.hpp"

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
#include "uavcover/error.hpp"

namespace uavcover::render {

namespace {

using SurfacePtr = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using CairoPtr = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

void check_size(int width, int height) {
  if (width < 64 || height < 64 || width > 20000 || height > 20000)
    throw InputError("size",
                     fmt::format("picture size {}x{} must be within 64..20000 pixels", width, height));
}

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

void set(cairo_t* cr, Rgb c, double a = 1.0) { cairo_set_source_rgba(cr, c.r, c.g, c.b, a); }

void text(cairo_t* cr, double x, double y, const std::string& s, double size, double align = 0.0,
          bool bold = false, double valign = 0.0) {
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

struct View {
  double scale = 1.0, ox = 0.0, oy = 0.0;  // pixel = (ox + scale*x, oy - scale*y)
  [[nodiscard]] double px(double x) const { return ox + scale * x; }
  [[nodiscard]] double py(double y) const { return oy - scale * y; }
};

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

/// The lattice as an image: one pixel per sample, north up, transparent where k < 0.
SurfacePtr lattice_surface(const evaluation::CoverageResult& cov) {
  const int max_k = std::max(cov.total.max_scans, 1);
  SurfacePtr img(cairo_image_surface_create(CAIRO_FORMAT_ARGB32, cov.lattice_cols, cov.lattice_rows),
                 cairo_surface_destroy);
  cairo_surface_flush(img.get());
  unsigned char* data = cairo_image_surface_get_data(img.get());
  const int stride = cairo_image_surface_get_stride(img.get());
  for (int r = 0; r < cov.lattice_rows; ++r) {
    // image row 0 is the northernmost lattice row
    auto* row = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(stride) *
                                                            (cov.lattice_rows - 1 - r));
    for (int c = 0; c < cov.lattice_cols; ++c) {
      const int k = cov.scans[static_cast<std::size_t>(r) * static_cast<std::size_t>(cov.lattice_cols) +
                              static_cast<std::size_t>(c)];
      if (k < 0) {
        row[c] = 0;  // transparent
        continue;
      }
      const Rgb col = scan_colour(k, max_k);
      row[c] = 0xff000000u | (static_cast<std::uint32_t>(col.r * 255) << 16) |
               (static_cast<std::uint32_t>(col.g * 255) << 8) | static_cast<std::uint32_t>(col.b * 255);
    }
  }
  cairo_surface_mark_dirty(img.get());
  return img;
}

void draw_heatmap(cairo_t* cr, const evaluation::CoverageResult& cov, int width, int height,
                  const std::string& title, const MultiPolygon* outline = nullptr) {
  const double margin = 40;
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  text(cr, margin, margin, title, 20, 0.0, true);
  text(cr, margin, margin + 22,
       fmt::format("PoC {:.2f}%   PoOC {:.2f}%   max scans {}   lattice {:.2f} m", 100 * cov.total.poc,
                   100 * cov.total.pooc, cov.total.max_scans, cov.lattice_m),
       14);
  if (cov.lattice_cols <= 0 || cov.lattice_rows <= 0) return;
  const int max_k = std::max(cov.total.max_scans, 1);
  SurfacePtr img = lattice_surface(cov);
  const double legend_w = 150;
  const double left = margin, top = margin + 40, right = width - legend_w - margin,
               bottom = height - margin - 30;
  const double sx = (right - left) / cov.lattice_cols, sy = (bottom - top) / cov.lattice_rows;
  const double s = std::min(sx, sy);
  const double ox = left + 0.5 * (right - left - s * cov.lattice_cols);
  const double oy = top + 0.5 * (bottom - top - s * cov.lattice_rows);
  cairo_save(cr);
  cairo_translate(cr, ox, oy);
  cairo_scale(cr, s, s);
  cairo_set_source_surface(cr, img.get(), 0, 0);
  cairo_pattern_set_filter(cairo_get_source(cr), s >= 1 ? CAIRO_FILTER_NEAREST : CAIRO_FILTER_GOOD);
  cairo_paint(cr);
  cairo_restore(cr);
  if (outline && !outline->empty()) {
    // sample (c, r) is image pixel (c, rows-1-r): local x = x0 + c*L maps to ox + (c + 0.5)*s
    View ov;
    const double L = std::max(cov.lattice_m, 1e-9);
    ov.scale = s / L;
    ov.ox = ox + 0.5 * s - ov.scale * cov.lattice_origin.x();
    ov.oy = oy + (cov.lattice_rows - 0.5) * s + ov.scale * cov.lattice_origin.y();
    path_multipolygon(cr, ov, *outline);
    cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
    cairo_set_line_width(cr, 1.5);
    cairo_stroke(cr);
  }

  // legend: one box per count (or a ramp beyond 12)
  const double lx = width - legend_w - 10;
  double ly = top + 10;
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  text(cr, lx, ly, "scans", 15, 0.0, true);
  const int shown = std::min(max_k, 12);
  for (int k = 0; k <= shown; ++k) {
    const int kk = shown == max_k ? k : static_cast<int>(std::round(static_cast<double>(k) * max_k / shown));
    ly += 24;
    cairo_rectangle(cr, lx, ly - 14, 26, 18);
    set(cr, scan_colour(kk, max_k));
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
    cairo_set_line_width(cr, 1);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    const double share = static_cast<std::size_t>(kk) < cov.total.histogram.size()
                             ? cov.total.histogram[static_cast<std::size_t>(kk)]
                             : 0.0;
    text(cr, lx + 34, ly, fmt::format("{}  ({:.1f}%)", kk, 100 * share), 13);
  }
  // scale bar in metres: one sample is lattice_m
  View v;
  v.scale = s / std::max(cov.lattice_m, 1e-9);
  scale_bar(cr, v, margin, height - margin - 5, (width - legend_w) * 0.25);
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

Artifact heatmap_png(const evaluation::CoverageResult& coverage, const MultiPolygon* free, std::string name,
                     int width, int height, const std::string& title) {
  return png(std::move(name), width, height,
             [&](cairo_t* cr) { draw_heatmap(cr, coverage, width, height, title, free); });
}

Artifact heatmap_overlay_png(const evaluation::CoverageResult& coverage, std::string name) {
  if (coverage.lattice_cols <= 0 || coverage.lattice_rows <= 0 || coverage.lattice_cols > 20000 ||
      coverage.lattice_rows > 20000)
    throw InputError("size", fmt::format("coverage lattice {}x{} cannot be drawn as an overlay",
                                         coverage.lattice_cols, coverage.lattice_rows));
  SurfacePtr img = lattice_surface(coverage);
  if (cairo_surface_status(img.get()) != CAIRO_STATUS_SUCCESS) throw OperationError("cannot draw " + name);
  Artifact out{std::move(name), "image/png", {}};
  if (cairo_surface_write_to_png_stream(img.get(), append_bytes, &out.bytes) != CAIRO_STATUS_SUCCESS)
    throw OperationError("cannot encode " + out.name);
  return out;
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
