// WGS84 <-> local East-North-Up metres, GeographicLib::LocalCartesian on the ellipsoid.
#pragma once

#include <GeographicLib/LocalCartesian.hpp>

#include "uavcover/geometry.hpp"

namespace uavcover::geodesy {

class LocalFrame {
 public:
  explicit LocalFrame(LonLat origin);
  [[nodiscard]] Point to_local(LonLat p) const;
  [[nodiscard]] LonLat to_wgs84(Point p) const;
  [[nodiscard]] LonLat origin() const { return origin_; }

 private:
  LonLat origin_;
  GeographicLib::LocalCartesian proj_;
};

/// Area-weighted centroid of the outer rings, computed on an equirectangular
/// approximation around the first vertex (good enough for choosing an origin).
LonLat centroid(const std::vector<GeoPolygon>& area);

}  // namespace uavcover::geodesy
