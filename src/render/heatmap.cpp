// The coverage heatmap and its overlay for a map.
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

}  // namespace

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

}  // namespace uavcover::render
