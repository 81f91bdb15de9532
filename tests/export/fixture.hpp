// Hand-built plans for the export and trajectory tests: a 200 m x 100 m rectangle split between two
// UAVs along x = 0, each flying one closed loop, with a no-fly zone in the east half.
#pragma once

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "export/export.hpp"
#include "geodesy/local_frame.hpp"
#include "io/plan_io.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::fixture {

inline PathPart make_part(const geodesy::LocalFrame& frame, PartKind kind, std::vector<Point> pts) {
  PathPart part{kind, std::move(pts), {}};
  for (const auto& p : part.local) part.wgs84.push_back(frame.to_wgs84(p));
  return part;
}

inline GeoRing geo_ring(const geodesy::LocalFrame& frame, const std::vector<Point>& pts) {
  GeoRing ring;
  for (const auto& p : pts) ring.push_back(frame.to_wgs84(p));
  ring.push_back(ring.front());
  return ring;
}

/// Two UAVs: "alpha" (west half) and "bravo" (east half). `camera` sets a camera block.
inline Plan two_uav_plan(bool camera = false) {
  Plan plan;
  plan.origin = {8.5455, 47.3977};
  const geodesy::LocalFrame frame(plan.origin);
  Mission& m = plan.mission;
  m.name = "fixture";
  // CCW exterior (RFC 7946 / normalised mission)
  m.area.push_back({geo_ring(frame, {{-100, -50}, {100, -50}, {100, 50}, {-100, 50}})});
  m.no_fly_zones.push_back({geo_ring(frame, {{60, -30}, {80, -30}, {80, -10}, {60, -10}})});
  m.spacing_m = 10.0;
  m.altitude_m = 40.0;
  m.altitude_source = "default";
  if (camera) {
    m.camera = Camera{};
    m.camera->altitude_m = 40.0;
    m.camera->hfov_deg = 60.0;
    m.camera->overlap = 0.2;
    m.altitude_source = "camera";
    // as the parser derives them: footprint 2 h tan(HFOV/2), 4:3 along track, 75 % front overlap
    m.footprint_m = 2.0 * 40.0 * std::tan(30.0 * std::numbers::pi / 180.0);
    m.along_track_footprint_m = *m.footprint_m * 0.75;
    m.trigger_distance_m = *m.along_track_footprint_m * (1.0 - m.camera->front_overlap);
  }
  Uav a;
  a.id = "alpha";
  a.start_resolved = frame.to_wgs84({-120, -60});
  a.start = a.start_resolved;
  a.share = 0.5;
  a.speed_mps = 5.0;
  a.max_accel_mps2 = 2.0;
  Uav b = a;
  b.id = "bravo";
  b.start_resolved = frame.to_wgs84({120, -60});
  b.start = b.start_resolved;
  b.speed_mps = 8.0;
  b.max_accel_mps2 = 3.0;
  m.uavs = {a, b};

  UavPlan pa;
  pa.id = "alpha";
  pa.share_requested = pa.share_actual = 0.5;
  const std::vector<Point> loop_a{{-90, -40}, {-10, -40}, {-10, 0},  {-50, 0},
                                  {-50, 40},  {-90, 40},  {-90, -40}};
  pa.parts.push_back(make_part(frame, PartKind::Transit, {{-120, -60}, {-90, -40}}));
  pa.parts.push_back(make_part(frame, PartKind::Coverage, loop_a));
  pa.parts.push_back(make_part(frame, PartKind::Transit, {{-90, -40}, {-120, -60}}));
  UavPlan pb;
  pb.id = "bravo";
  pb.share_requested = pb.share_actual = 0.5;
  const std::vector<Point> loop_b{{90, -40}, {90, 40}, {50, 40}, {50, 0}, {10, 0}, {10, -40}, {90, -40}};
  pb.parts.push_back(make_part(frame, PartKind::Transit, {{120, -60}, {90, -40}}));
  pb.parts.push_back(make_part(frame, PartKind::Coverage, loop_b));
  pb.parts.push_back(make_part(frame, PartKind::Transit, {{90, -40}, {120, -60}}));
  plan.uavs = {pa, pb};

  // regions: the west half is alpha's, the east half bravo's, less the no-fly cell (x 60..80, y -30..-10)
  bg::read_wkt("MULTIPOLYGON(((-100 -50,-100 50,0 50,0 -50,-100 -50)))", plan.uavs[0].region_local);
  bg::read_wkt("MULTIPOLYGON(((0 -50,0 50,100 50,100 -50,80 -50,80 -10,60 -10,60 -30,80 -30,80 -50,0 -50)))",
               plan.uavs[1].region_local);
  for (auto& u : plan.uavs) bg::correct(u.region_local);
  return plan;
}

/// The exports as files under `dir`, the way the CLI writes them (export_artifacts + write_artifacts).
inline std::vector<std::filesystem::path> export_to(const Plan& plan, const std::vector<std::string>& formats,
                                                    const std::filesystem::path& dir,
                                                    const exporting::ExportOptions& opt = {}) {
  return io::write_artifacts(dir, exporting::export_artifacts(plan, formats, opt));
}

}  // namespace uavcover::fixture
