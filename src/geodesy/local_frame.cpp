#include "geodesy/local_frame.hpp"

#include <cmath>
#include <numbers>

namespace uavcover::geodesy {

LocalFrame::LocalFrame(LonLat origin)
    : origin_(origin), proj_(origin.lat, origin.lon, 0.0, GeographicLib::Geocentric::WGS84()) {}

Point LocalFrame::to_local(LonLat p) const {
  double x = 0, y = 0, z = 0;
  proj_.Forward(p.lat, p.lon, 0.0, x, y, z);
  return {x, y};
}

LonLat LocalFrame::to_wgs84(Point p) const {
  // The plane z = 0 of the ENU frame curves away from the ellipsoid; find the point of the
  // ellipsoid (h = 0) whose local x, y match, so that to_local(to_wgs84(p)) == p.
  double lat = 0, lon = 0, h = 0;
  double z = 0;
  for (int i = 0; i < 4; ++i) {
    proj_.Reverse(p.x(), p.y(), z, lat, lon, h);
    double x2 = 0, y2 = 0, z2 = 0;
    proj_.Forward(lat, lon, 0.0, x2, y2, z2);
    z = z2;
  }
  proj_.Reverse(p.x(), p.y(), z, lat, lon, h);
  return {lon, lat};
}

LonLat centroid(const std::vector<GeoPolygon>& area) {
  if (area.empty() || area.front().empty() || area.front().front().empty()) return {};
  const LonLat ref = area.front().front().front();
  const double kx = std::cos(ref.lat * std::numbers::pi / 180.0);
  double a_sum = 0, cx = 0, cy = 0;
  for (const auto& poly : area) {
    if (poly.empty()) continue;
    const auto& ring = poly.front();
    for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
      const double x0 = (ring[i].lon - ref.lon) * kx, y0 = ring[i].lat - ref.lat;
      const double x1 = (ring[i + 1].lon - ref.lon) * kx, y1 = ring[i + 1].lat - ref.lat;
      const double c = x0 * y1 - x1 * y0;
      a_sum += c;
      cx += (x0 + x1) * c;
      cy += (y0 + y1) * c;
    }
  }
  if (std::abs(a_sum) < 1e-18) return ref;
  return {ref.lon + cx / (3.0 * a_sum) / kx, ref.lat + cy / (3.0 * a_sum)};
}

}  // namespace uavcover::geodesy
