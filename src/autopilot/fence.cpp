#include "autopilot/fence.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include <boost/function_output_iterator.hpp>
#include <boost/geometry/index/rtree.hpp>

#include "geodesy/local_frame.hpp"

namespace uavcover::autopilot {

using namespace waypoints;  // the waypoint model the formats write

namespace {

constexpr int kFenceDirections = 16;

}  // namespace

bool inside_ring(LonLat p, const GeoRing& ring) {
  std::size_t n = ring.size();
  if (n >= 2 && ring.front().lat == ring.back().lat && ring.front().lon == ring.back().lon) --n;
  bool c = false;
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const LonLat& a = ring[i];
    const LonLat& b = ring[j];
    if ((a.lon >= p.lon) != (b.lon >= p.lon) &&
        p.lat <= (b.lat - a.lat) * (p.lon - a.lon) / (b.lon - a.lon) + a.lat)
      c = !c;
  }
  return c;
}

GeoRing inclusion_fence(const Plan& plan, std::size_t index, const std::vector<MissionItem>& items,
                        double margin_m) {
  const geodesy::LocalFrame frame(plan.origin);
  std::vector<Point> pts;
  for (const auto& poly : plan.mission.area)
    if (!poly.empty())
      for (const auto& p : poly.front()) pts.push_back(frame.to_local(p));
  pts.push_back(frame.to_local(plan.mission.uavs.at(index).start_resolved));
  for (const auto& it : items)
    if (has_position(it)) pts.push_back(frame.to_local({it.lon, it.lat}));
  // a discrete oriented polygon: the intersection of the half-planes n_k . x <= max_p n_k . p + margin
  // for 16 evenly spread normals n_k. Each is a supporting line of the points' hull pushed out by the
  // margin, so consecutive lines meet at the polygon's vertices.
  std::array<double, kFenceDirections> h{};
  std::array<Point, kFenceDirections> normal;
  for (int k = 0; k < kFenceDirections; ++k) {
    const double a = 2.0 * std::numbers::pi * k / kFenceDirections;
    normal[static_cast<std::size_t>(k)] = Point(std::cos(a), std::sin(a));
    double best = -std::numeric_limits<double>::infinity();
    for (const auto& p : pts) best = std::max(best, p.x() * std::cos(a) + p.y() * std::sin(a));
    h[static_cast<std::size_t>(k)] = best + margin_m;
  }
  std::vector<Point> verts;
  for (std::size_t k = 0; k < kFenceDirections; ++k) {
    const std::size_t l = (k + 1) % kFenceDirections;
    const Point& n1 = normal[k];
    const Point& n2 = normal[l];
    const double det = n1.x() * n2.y() - n1.y() * n2.x();
    const Point v((h[k] * n2.y() - h[l] * n1.y()) / det, (n1.x() * h[l] - n2.x() * h[k]) / det);
    if (verts.empty() || std::hypot(v.x() - verts.back().x(), v.y() - verts.back().y()) > 0.01)
      verts.push_back(v);
  }
  if (verts.size() > 1 &&
      std::hypot(verts.front().x() - verts.back().x(), verts.front().y() - verts.back().y()) <= 0.01)
    verts.pop_back();
  GeoRing ring;
  for (const auto& v : verts) ring.push_back(frame.to_wgs84(v));
  return ring;
}

std::vector<std::string> no_fly_violations(const Plan& plan, std::size_t index,
                                           const std::vector<MissionItem>& items, double step_m) {
  std::vector<std::string> out;
  const auto& zones = plan.mission.no_fly_zones;
  if (zones.empty()) return out;
  const std::string& id = plan.mission.uavs.at(index).id;
  const LonLat home = plan.mission.uavs.at(index).start_resolved;
  // an R-tree of the zones' lon/lat bounding boxes (x = lon, y = lat): a flight of 10^5 legs past 10^3
  // zones tests each point against the few zones around it only
  using Box = bg::model::box<Point>;
  using Entry = std::pair<Box, std::size_t>;
  std::vector<Entry> boxes;
  for (std::size_t z = 0; z < zones.size(); ++z) {
    if (zones[z].empty() || zones[z].front().size() < 4) continue;
    Box b(Point(zones[z].front()[0].lon, zones[z].front()[0].lat),
          Point(zones[z].front()[0].lon, zones[z].front()[0].lat));
    for (const auto& v : zones[z].front()) bg::expand(b, Point(v.lon, v.lat));
    boxes.emplace_back(b, z);
  }
  const bg::index::rtree<Entry, bg::index::rstar<16>> tree(boxes.begin(), boxes.end());
  auto zone_of = [&](LonLat p) -> int {
    int best = -1;  // the lowest index, as a scan in order would find
    for (auto it = tree.qbegin(bg::index::intersects(Point(p.lon, p.lat))); it != tree.qend(); ++it) {
      const std::size_t z = it->second;
      if ((best < 0 || static_cast<int>(z) < best) && inside_ring(p, zones[z].front()))
        best = static_cast<int>(z);
    }
    return best;
  };
  // the places flown, in order, with a description each
  std::vector<std::pair<LonLat, std::string>> places{{home, "home"}};
  for (std::size_t k = 0; k < items.size(); ++k)
    if (has_position(items[k]))
      places.emplace_back(LonLat{items[k].lon, items[k].lat},
                          fmt::format("mission item {} ({})", k + 1, items[k].role));
  places.emplace_back(home, "the return home");
  const geodesy::LocalFrame frame(plan.origin);
  // the zones' boxes in the plan's frame, each padded by far more than a straight lon/lat edge bends
  // away from the straight line between its projected ends (about extent^2 tan(lat) / 8R: 1.5 m for a
  // 10 km zone at 45 deg; the pad is 50 m + extent^2 / 1e5 m, 1 km for it): a point of a leg outside
  // all of them is outside every zone, so the lon/lat test (its inverse projection was 38 s of the 40 s
  // export of 1M mega-cells x 50 UAVs) is made only for the points inside one, and every answer is the
  // one the test of every point gives. Near a pole or across the antimeridian every point is tested.
  std::vector<Entry> local_boxes;
  for (const auto& [box, z] : boxes) {
    Box b;
    bg::assign_inverse(b);
    for (const auto& v : zones[z].front()) bg::expand(b, frame.to_local(v));
    const double extent = bg::distance(b.min_corner(), b.max_corner());
    const bool plain = box.max_corner().x() - box.min_corner().x() < 90 &&
                       std::abs(box.min_corner().y()) < 80 && std::abs(box.max_corner().y()) < 80 &&
                       std::abs(plan.origin.lat) < 80;
    const double pad = plain ? 50.0 + extent * extent / 1.0e5 : std::numeric_limits<double>::max() / 4;
    b = Box(Point(b.min_corner().x() - pad, b.min_corner().y() - pad),
            Point(b.max_corner().x() + pad, b.max_corner().y() + pad));
    local_boxes.emplace_back(b, z);
  }
  const bg::index::rtree<Entry, bg::index::rstar<16>> local_tree(local_boxes.begin(), local_boxes.end());
  std::vector<Box> near;  // the padded boxes around a leg
  for (std::size_t k = 0; k < places.size(); ++k) {
    const int z = zone_of(places[k].first);
    if (z >= 0) {
      out.push_back(fmt::format("uav '{}': {} lies inside no-fly zone {}", id, places[k].second, z));
      continue;
    }
    if (k == 0) continue;
    const Point a = frame.to_local(places[k - 1].first);
    const Point b = frame.to_local(places[k].first);
    const double len = std::hypot(b.x() - a.x(), b.y() - a.y());
    const int steps = static_cast<int>(std::ceil(len / std::max(step_m, 0.01)));
    near.clear();
    local_tree.query(bg::index::intersects(Box(Point(std::min(a.x(), b.x()), std::min(a.y(), b.y())),
                                               Point(std::max(a.x(), b.x()), std::max(a.y(), b.y())))),
                     boost::make_function_output_iterator([&](const Entry& e) { near.push_back(e.first); }));
    if (near.empty()) continue;  // no zone near the leg
    for (int s = 1; s < steps; ++s) {
      const double t = static_cast<double>(s) / steps;
      const Point q(a.x() + t * (b.x() - a.x()), a.y() + t * (b.y() - a.y()));
      if (std::none_of(near.begin(), near.end(), [&](const Box& bx) { return bg::covered_by(q, bx); }))
        continue;
      const LonLat p = frame.to_wgs84(q);
      const int zz = zone_of(p);
      if (zz >= 0) {
        out.push_back(
            fmt::format("uav '{}': the leg to {} crosses no-fly zone {}", id, places[k].second, zz));
        break;
      }
    }
  }
  return out;
}

namespace {

/// An open ring (the closing vertex dropped).
GeoRing open_ring(const GeoRing& ring) {
  GeoRing r = ring;
  if (r.size() >= 2 && r.front().lat == r.back().lat && r.front().lon == r.back().lon) r.pop_back();
  return r;
}

void push_polygon(std::vector<MissionItem>& out, const GeoRing& ring, std::uint16_t command) {
  const GeoRing r = open_ring(ring);
  if (r.size() < 3) return;
  for (const auto& v : r) {
    MissionItem it;
    it.command = command;
    it.frame = kFrameGlobal;
    it.param1 = static_cast<float>(r.size());
    it.param4 = 0.0f;
    it.lat = v.lat;
    it.lon = v.lon;
    it.alt = 0.0f;
    it.role = "fence";
    out.push_back(it);
  }
}

}  // namespace

std::vector<MissionItem> fence_items(const Plan& plan, std::size_t index,
                                     const std::vector<MissionItem>& items, double margin_m) {
  std::vector<MissionItem> out;
  push_polygon(out, inclusion_fence(plan, index, items, margin_m), kFencePolygonVertexInclusion);
  for (const auto& poly : plan.mission.no_fly_zones)
    if (!poly.empty()) push_polygon(out, poly.front(), kFencePolygonVertexExclusion);
  return out;
}

std::vector<MissionItem> rally_items(const Plan& plan, std::size_t index) {
  std::vector<MissionItem> out;
  const double alt = plan.uavs.at(index).transition_altitude_m;
  for (const auto& p : plan.rally) {
    MissionItem it;
    it.command = kRallyPoint;
    it.frame = kFrameGlobalRelativeAlt;
    it.param1 = 0.0f;  // RALLY_FLAGS: none
    it.param4 = 0.0f;
    it.lat = p.lat;
    it.lon = p.lon;
    it.alt = static_cast<float>(alt);
    it.role = "rally";
    out.push_back(it);
  }
  return out;
}

std::optional<std::string> read_fence(const std::vector<mavlink::MissionItemInt>& items, Fence& out) {
  out = Fence{};
  std::size_t i = 0;
  while (i < items.size()) {
    const auto& it = items[i];
    const LonLat at{it.y / 1e7, it.x / 1e7};
    if (!(std::abs(at.lat) <= 90.0 && std::abs(at.lon) <= 180.0))
      return fmt::format("fence item {}: latitude or longitude out of range", i);
    if (it.command == kFenceCircleInclusion || it.command == kFenceCircleExclusion) {
      if (!(std::isfinite(it.param1) && it.param1 > 0.0f))
        return fmt::format("fence item {}: a circle needs a positive radius in param1", i);
      (it.command == kFenceCircleInclusion ? out.inclusion_circles : out.exclusion_circles)
          .push_back({at, static_cast<double>(it.param1)});
      ++i;
      continue;
    }
    if (it.command != kFencePolygonVertexInclusion && it.command != kFencePolygonVertexExclusion)
      return fmt::format("fence item {}: command {} is not a fence command", i, it.command);
    if (!(std::isfinite(it.param1) && it.param1 >= 3.0f && it.param1 <= 65535.0f &&
          std::floor(it.param1) == it.param1))
      return fmt::format("fence item {}: a polygon vertex needs the vertex count (at least 3) in param1", i);
    const auto n = static_cast<std::size_t>(it.param1);
    if (i + n > items.size())
      return fmt::format("fence item {}: the polygon's {} vertices run past the end", i, n);
    GeoRing ring;
    for (std::size_t k = i; k < i + n; ++k) {
      if (items[k].command != it.command || items[k].param1 != it.param1)
        return fmt::format("fence item {}: not a vertex of the polygon that starts at item {}", k, i);
      ring.push_back({items[k].y / 1e7, items[k].x / 1e7});
    }
    (it.command == kFencePolygonVertexInclusion ? out.inclusion : out.exclusion).push_back(std::move(ring));
    i += n;
  }
  return std::nullopt;
}

bool fence_allows(const Fence& fence, LonLat p) {
  auto in_circle = [&](const Fence::Circle& c) {
    const geodesy::LocalFrame frame(c.centre);
    const Point q = frame.to_local(p);
    return std::hypot(q.x(), q.y()) <= c.radius_m;
  };
  const bool any_inclusion = !fence.inclusion.empty() || !fence.inclusion_circles.empty();
  bool inside = !any_inclusion;
  for (const auto& r : fence.inclusion) inside = inside || inside_ring(p, r);
  for (const auto& c : fence.inclusion_circles) inside = inside || in_circle(c);
  if (!inside) return false;
  for (const auto& r : fence.exclusion)
    if (inside_ring(p, r)) return false;
  for (const auto& c : fence.exclusion_circles)
    if (in_circle(c)) return false;
  return true;
}

bool fence_allows(const Fence& fence, LonLat p, double slack_m) {
  if (fence_allows(fence, p)) return true;
  if (!(slack_m > 0)) return false;
  const geodesy::LocalFrame frame(p);
  for (int k = 0; k < 8; ++k) {
    const double a = k * std::numbers::pi / 4;
    if (fence_allows(fence, frame.to_wgs84(Point(slack_m * std::cos(a), slack_m * std::sin(a))))) return true;
  }
  return false;
}

}  // namespace uavcover::autopilot
