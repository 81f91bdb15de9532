#include "geometry/millimetres.hpp"

#include <cmath>

namespace uavcover::geometry {

namespace {

/// The polygons with every point converted by `f`, corrected.
template <class To, class From, class F>
To convert(const From& mp, F f) {
  To out;
  for (const auto& poly : mp) {
    auto& q = out.emplace_back();
    for (const auto& p : poly.outer()) q.outer().push_back(f(p));
    for (const auto& inner : poly.inners()) {
      auto& ring = q.inners().emplace_back();
      for (const auto& p : inner) ring.push_back(f(p));
    }
  }
  bg::correct(out);
  return out;
}

}  // namespace

MmPoint to_mm(Point p) { return {std::llround(p.x() * kMmPerM), std::llround(p.y() * kMmPerM)}; }

Point from_mm(MmPoint p) {
  return {static_cast<double>(p.x()) / kMmPerM, static_cast<double>(p.y()) / kMmPerM};
}

MmMultiPolygon to_mm(const MultiPolygon& mp) {
  return convert<MmMultiPolygon>(mp, [](Point p) { return to_mm(p); });
}

MultiPolygon from_mm(const MmMultiPolygon& mp) {
  return convert<MultiPolygon>(mp, [](MmPoint p) { return from_mm(p); });
}

MultiPolygon intersection_mm(const MultiPolygon& a, const MultiPolygon& b) {
  MmMultiPolygon out;
  bg::intersection(to_mm(a), to_mm(b), out);
  return from_mm(out);
}

}  // namespace uavcover::geometry
