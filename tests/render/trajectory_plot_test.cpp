// The trajectory plot (issue 33): a PNG of the requested size, three panels each with its curves drawn,
// for both methods, and the trajectory_plot export of every flying UAV.
#include <cairo.h>
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "export/export.hpp"
#include "export/fixture.hpp"
#include "render/render.hpp"
#include "trajectory/trajectory.hpp"
#include "uavcover/error.hpp"

using namespace uavcover;

namespace {

struct Decoded {
  int width = 0, height = 0;
  /// per third of the plot area (below the title): pixels in a curve's colour (saturated), and not white
  std::array<long, 3> coloured{}, drawn{};
};

Decoded decode(const std::string& png) {
  struct Reader {
    const std::string* bytes;
    std::size_t at = 0;
  } reader{&png};
  auto read = [](void* closure, unsigned char* data, unsigned int length) {
    auto* r = static_cast<Reader*>(closure);
    if (r->at + length > r->bytes->size()) return CAIRO_STATUS_READ_ERROR;
    std::memcpy(data, r->bytes->data() + r->at, length);
    r->at += length;
    return CAIRO_STATUS_SUCCESS;
  };
  cairo_surface_t* s = cairo_image_surface_create_from_png_stream(read, &reader);
  Decoded d;
  if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
    cairo_surface_destroy(s);
    ADD_FAILURE() << "not a PNG";
    return d;
  }
  d.width = cairo_image_surface_get_width(s);
  d.height = cairo_image_surface_get_height(s);
  const int stride = cairo_image_surface_get_stride(s);
  const unsigned char* px = cairo_image_surface_get_data(s);
  const int top = 70, bottom = d.height - 50;
  for (int y = top; y < bottom; ++y)
    for (int x = 0; x < d.width; ++x) {
      const unsigned char* p = px + y * stride + 4 * x;  // native-endian ARGB32: B, G, R, A
      const int b = p[0], g = p[1], r = p[2];
      const auto third = static_cast<std::size_t>(std::min(2, 3 * (y - top) / (bottom - top)));
      if (r < 245 || g < 245 || b < 245) ++d.drawn[third];
      if (std::max({r, g, b}) - std::min({r, g, b}) > 80) ++d.coloured[third];
    }
  cairo_surface_destroy(s);
  return d;
}

}  // namespace

TEST(TrajectoryPlot, APngOfTheRequestedSizeWithEveryPanelDrawn) {
  const Plan plan = fixture::two_uav_plan();
  for (const auto method : {trajectory::Method::FilletLines, trajectory::Method::Polynomial}) {
    trajectory::Options o;
    o.method = method;
    const auto t = trajectory::uav_trajectory(plan, 0, o);
    const Artifact a = render::trajectory_png(t, "alpha.png", "alpha", 1200, 900);
    EXPECT_EQ(a.name, "alpha.png");
    EXPECT_EQ(a.media_type, "image/png");
    const Decoded d = decode(a.bytes);
    EXPECT_EQ(d.width, 1200);
    EXPECT_EQ(d.height, 900);
    const long area = 1200L * (900 - 120) / 3;
    for (std::size_t k = 0; k < 3; ++k) {
      SCOPED_TRACE(std::string(trajectory::method_name(method)) + " panel " + std::to_string(k));
      // curves in their colours (x red, y blue, z green; the dashed limits red) and grid, labels, axes
      EXPECT_GT(d.coloured[k], area / 200);
      EXPECT_GT(d.drawn[k], area / 50);
      EXPECT_LT(d.drawn[k], area / 2);  // not a smear: most of the panel is background
    }
  }
  // the same trajectory, the same bytes
  const auto t = trajectory::uav_trajectory(plan, 1);
  EXPECT_EQ(render::trajectory_png(t, "b.png", "bravo").bytes,
            render::trajectory_png(t, "b.png", "bravo").bytes);
}

TEST(TrajectoryPlot, RefusesBadSizes) {
  const auto t = trajectory::uav_trajectory(fixture::two_uav_plan(), 0);
  try {
    (void)render::trajectory_png(t, "x.png", "x", 100, 900);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "size");
  }
}

TEST(TrajectoryPlot, IsAnExportOfEveryFlyingUav) {
  const Plan plan = fixture::two_uav_plan();
  exporting::ExportOptions opt;
  opt.trajectory.method = trajectory::Method::Polynomial;
  const Artifacts a = exporting::export_artifacts(plan, {"trajectory_plot"}, opt);
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].name, "export/alpha.trajectory.png");
  EXPECT_EQ(a[1].name, "export/bravo.trajectory.png");
  for (const auto& f : a) {
    EXPECT_EQ(f.media_type, "image/png");
    const Decoded d = decode(f.bytes);
    EXPECT_EQ(d.width, 1400);
    EXPECT_EQ(d.height, 1000);
  }
}
