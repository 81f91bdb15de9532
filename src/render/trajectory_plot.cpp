// The trajectory plot: position, velocity and acceleration of one UAV against time, three stacked
// panels, the limits as dashed lines (docs/trajectory.md).
#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "render/canvas_internal.hpp"
#include "render/render.hpp"
#include "uavcover/error.hpp"

namespace uavcover::render {

using namespace detail;

namespace {

struct Curve {
  std::string name;
  Rgb colour;
  std::vector<double> lo, hi;  // per pixel column: the least and the largest value sampled there
};

struct Bound {
  std::string name;
  double value;
};

/// One panel: the curves as per-column envelopes (the picture's size follows its pixels, not the
/// flight's length), the bounds dashed, a legend.
void draw_panel(cairo_t* cr, const std::vector<Curve>& curves, const std::vector<Bound>& bounds, double left,
                double top, double right, double bottom, double duration, const std::string& ylabel,
                double ylabel_x) {
  double lo = 0, hi = 0;
  for (const auto& c : curves)
    for (std::size_t k = 0; k < c.lo.size(); ++k) lo = std::min(lo, c.lo[k]), hi = std::max(hi, c.hi[k]);
  for (const auto& b : bounds) lo = std::min(lo, b.value), hi = std::max(hi, b.value);
  if (!(hi > lo)) hi = lo + 1;
  const double step = nice_step(hi - lo, 5);
  lo = step * std::floor(lo / step);
  hi = step * std::ceil(hi / step);
  auto py = [&](double y) { return bottom - (bottom - top) * (y - lo) / (hi - lo); };
  y_grid(cr, left, right, lo, hi, step, py);
  const double tstep = nice_step(std::max(duration, 1e-6), 10);
  for (double t = 0; t <= duration + 1e-9; t += tstep) {
    const double x = left + (right - left) * t / std::max(duration, 1e-6);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    text(cr, x, bottom + 16, fmt::format("{:g}", t), 11, 0.5);
  }
  const double dash[] = {7.0, 4.0};
  cairo_set_line_width(cr, 1.5);
  for (const auto& b : bounds) {
    cairo_set_dash(cr, dash, 2, 0);
    cairo_set_source_rgb(cr, 0.75, 0.1, 0.1);
    cairo_move_to(cr, left, py(b.value));
    cairo_line_to(cr, right, py(b.value));
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0);
    text(cr, right - 4, py(b.value) - 4, fmt::format("{} {:g}", b.name, b.value), 11, 1.0);
  }
  for (const auto& c : curves) {
    set(cr, c.colour);
    cairo_set_line_width(cr, 1.2);
    for (std::size_t k = 0; k < c.lo.size(); ++k) {
      const double x = left + static_cast<double>(k) + 0.5;
      (k == 0 ? cairo_move_to : cairo_line_to)(cr, x, py(c.lo[k]));
      if (c.hi[k] != c.lo[k]) cairo_line_to(cr, x, py(c.hi[k]));
    }
    cairo_stroke(cr);
  }
  axes(cr, left, top, right, bottom, "", bottom, ylabel, ylabel_x);
  double lx = left + 10;
  for (const auto& c : curves) {
    set(cr, c.colour);
    cairo_rectangle(cr, lx, top + 6, 18, 4);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    text(cr, lx + 24, top + 8, c.name, 12, 0.0, false, 0.5);
    lx += 70;
  }
}

}  // namespace

Artifact trajectory_png(const trajectory::Trajectory& t, std::string name, const std::string& title,
                        int width, int height) {
  if (width < 320 || height < 320 || width > 20000 || height > 20000)
    throw InputError(
        "size",
        fmt::format("a trajectory plot of {} x {} pixels: each side must be in 320..20000", width, height));
  const double margin = 30, left = margin + 70, right = width - margin, top0 = margin + 36;
  const double gap = 36, panel = (height - top0 - margin - 40 - 2 * gap) / 3.0;
  const auto columns = static_cast<std::size_t>(std::max(1.0, right - left));
  const double duration = t.duration();
  // sampled finely enough for every column (a fillet's acceleration step is narrower than a pixel)
  const double dt =
      std::max({duration / 1e6, std::min(0.05, duration / (4.0 * static_cast<double>(columns))), 1e-6});
  const auto samples = t.sample(dt);
  const Rgb red{0.84, 0.15, 0.16}, blue{0.12, 0.47, 0.71}, green{0.17, 0.63, 0.17}, black{0.1, 0.1, 0.1};
  auto curves = [&](auto&& value, bool with_norm) {
    std::vector<Curve> cs{{"x", red, {}, {}}, {"y", blue, {}, {}}, {"z", green, {}, {}}};
    if (with_norm) cs.push_back({"|.|", black, {}, {}});
    for (auto& c : cs) c.lo.assign(columns, 1e300), c.hi.assign(columns, -1e300);
    for (const auto& s : samples) {
      const auto col = std::min(columns - 1, static_cast<std::size_t>(static_cast<double>(columns) * s.t /
                                                                      std::max(duration, 1e-9)));
      const trajectory::Vec3 v = value(s);
      for (std::size_t k = 0; k < cs.size(); ++k) {
        const double y = k < 3 ? v[k] : std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        cs[k].lo[col] = std::min(cs[k].lo[col], y);
        cs[k].hi[col] = std::max(cs[k].hi[col], y);
      }
    }
    for (auto& c : cs)  // a column no sample fell in (a short flight) takes its left neighbour's values
      for (std::size_t k = 0; k < columns; ++k)
        if (c.lo[k] > c.hi[k]) c.lo[k] = c.hi[k] = k > 0 ? c.hi[k - 1] : 0.0;
    return cs;
  };
  const auto& lim = t.limits();
  const bool poly = t.method() == trajectory::Method::Polynomial;
  const double v_min = poly ? t.report().v_min : -lim.v_max, a_min = poly ? t.report().a_min : -lim.a_max;
  const auto pos = curves([](const trajectory::Sample& s) { return s.p; }, false);
  const auto vel = curves([](const trajectory::Sample& s) { return s.v; }, true);
  const auto acc = curves([](const trajectory::Sample& s) { return s.a; }, true);
  return png(std::move(name), width, height, [&](cairo_t* cr) {
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    text(cr, margin, margin + 4, title, 18, 0.0, true);
    text(cr, right, margin + 4,
         fmt::format("{}: {:.1f} s, {} waypoints", trajectory::method_name(t.method()), duration,
                     t.waypoints().size()),
         13, 1.0);
    double top = top0;
    draw_panel(cr, pos, {}, left, top, right, top + panel, duration, "position (m)", left - 55);
    top += panel + gap;
    draw_panel(cr, vel, {{"v_max", lim.v_max}, {"v_min", v_min}}, left, top, right, top + panel, duration,
               "velocity (m/s)", left - 55);
    top += panel + gap;
    draw_panel(cr, acc, {{"a_max", lim.a_max}, {"a_min", a_min}}, left, top, right, top + panel, duration,
               "acceleration (m/s²)", left - 55);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    text(cr, 0.5 * (left + right), height - margin + 6, "time (s)", 14, 0.5);
  });
}

}  // namespace uavcover::render
