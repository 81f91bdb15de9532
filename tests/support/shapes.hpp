// Small geometry fixtures shared by the tests.
#pragma once

#include "uavcover/geometry.hpp"

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
