#include <gtest/gtest.h>

#include "geodesy/local_frame.hpp"

using uavcover::LonLat;
using uavcover::Point;
using uavcover::geodesy::LocalFrame;

TEST(LocalFrame, RoundTripWithinOneMillimetreOver20Km) {
  for (const LonLat origin :
       {LonLat{22.9, 40.6}, LonLat{-70.6, -33.4}, LonLat{10.0, 69.5}, LonLat{179.9, 0.0}}) {
    const LocalFrame f(origin);
    for (double x = -20000; x <= 20000; x += 5000)
      for (double y = -20000; y <= 20000; y += 5000) {
        const Point p{x, y};
        const Point q = f.to_local(f.to_wgs84(p));
        EXPECT_NEAR(q.x(), x, 1e-3) << origin.lon << "," << origin.lat;
        EXPECT_NEAR(q.y(), y, 1e-3);
      }
  }
}

TEST(LocalFrame, OriginMapsToZeroAndAxesPointEastNorth) {
  const LocalFrame f({22.9, 40.6});
  const Point o = f.to_local({22.9, 40.6});
  EXPECT_NEAR(o.x(), 0, 1e-9);
  EXPECT_NEAR(o.y(), 0, 1e-9);
  const Point north = f.to_local({22.9, 40.61});
  EXPECT_NEAR(north.x(), 0, 1e-6);
  EXPECT_NEAR(north.y(), 1111.0, 5.0);  // ~1.11 km per 0.01 degree of latitude
  const Point east = f.to_local({22.91, 40.6});
  EXPECT_GT(east.x(), 800);
  EXPECT_NEAR(east.y(), 0, 0.1);
}
