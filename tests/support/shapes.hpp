// Small geometry fixtures shared by the tests.
#pragma once

#include <cmath>

#include "uavcover/geometry.hpp"
#include "uavcover/mission.hpp"

namespace uavcover::testing {

/// Axis-aligned rectangle in local metres, corrected (clockwise, closed).
inline Polygon rect(double x0, double y0, double x1, double y1) {
  Polygon p;
  bg::append(p.outer(), Point{x0, y0});
  bg::append(p.outer(), Point{x0, y1});
  bg::append(p.outer(), Point{x1, y1});
  bg::append(p.outer(), Point{x1, y0});
  bg::append(p.outer(), Point{x0, y0});
  bg::correct(p);
  return p;
}

}  // namespace uavcover::testing

namespace uavcover::testing {

/// A square field of `side_m` at (45° N, 9° E) strewn with an n x n lattice of square no-fly zones of
/// `zone_m` every `pitch_m` (each centred in its pitch cell), spacing `spacing_m`, no UAVs yet.
inline Mission zone_lattice_mission(double side_m, int n, double pitch_m, double zone_m, double spacing_m) {
  Mission m;
  m.spacing_m = spacing_m;
  const double lat0 = 45.0, lon0 = 9.0, mlat = 1.0 / 111320.0, mlon = mlat / std::cos(lat0 * M_PI / 180);
  auto geo_rect = [&](double x0, double y0, double x1, double y1) {
    return GeoPolygon{GeoRing{{lon0 + x0 * mlon, lat0 + y0 * mlat},
                              {lon0 + x1 * mlon, lat0 + y0 * mlat},
                              {lon0 + x1 * mlon, lat0 + y1 * mlat},
                              {lon0 + x0 * mlon, lat0 + y1 * mlat},
                              {lon0 + x0 * mlon, lat0 + y0 * mlat}}};
  };
  m.area.push_back(geo_rect(0, 0, side_m, side_m));
  const double lo = (pitch_m - zone_m) / 2, hi = (pitch_m + zone_m) / 2;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      m.no_fly_zones.push_back(
          geo_rect(i * pitch_m + lo, j * pitch_m + lo, i * pitch_m + hi, j * pitch_m + hi));
  return m;
}

/// The point `x_m` east and `y_m` north of zone_lattice_mission()'s south-west corner.
inline LonLat zone_lattice_point(double x_m, double y_m) {
  const double lat0 = 45.0, lon0 = 9.0, mlat = 1.0 / 111320.0, mlon = mlat / std::cos(lat0 * M_PI / 180);
  return LonLat{lon0 + x_m * mlon, lat0 + y_m * mlat};
}

}  // namespace uavcover::testing
