// What the photos really saw (issue 32, docs/photos.md): each photo's footprint on the ground from its
// geotag, height and camera attitude, the plan's free area covered by them, and the gaps left, as the
// refly plans them (usecases/refly.hpp).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "evaluation/coverage.hpp"
#include "evaluation/evaluate.hpp"
#include "io/exif.hpp"
#include "uavcover/artifact.hpp"
#include "uavcover/context.hpp"
#include "uavcover/plan.hpp"
#include "usecases/refly.hpp"

namespace uavcover::usecases {

struct PhotoOptions {
  /// The take-off ground's height above sea level, for photos that carry only a GPS altitude (no
  /// Xmp.drone-dji.RelativeAltitude) over a plan without a DEM.
  std::optional<double> takeoff_altitude_m;
};

struct PhotoFootprint {
  std::string name;
  GeoPolygon ground;      ///< the footprint (WGS84, one closed ring)
  double height_m = 0.0;  ///< the camera's height above the ground under it
  double yaw_deg = 0.0;   ///< where the camera faced (when the photo said; else the footprint is a disc)
  double pitch_deg = -90.0;
  bool yaw_known = false;
  std::string height_source;  ///< "relative" (XMP), "dem" (GPS altitude over the plan's DEM), "takeoff"
};

struct PhotoCoverage {
  std::vector<PhotoFootprint> photos;
  std::vector<std::string> skipped;  ///< "<name>: why" for photos that see no ground
  double poc = 0.0;                  ///< share of the free area's lattice samples inside a footprint
  double pooc = 0.0;                 ///< share inside two or more
  double planned_poc = 0.0;          ///< the plan's own
  evaluation::CoverageResult lattice;
  evaluation::GeoBounds bounds;  ///< the WGS84 box the overlay spans
  Artifact overlay;              ///< "photo-coverage.png": footprints per lattice sample
  ReflyGaps gaps;                ///< what no photo saw, as the refly flies it
};

/// Footprints, coverage and gaps of `photos` over `plan`'s free area, on the plan's own lattice. The
/// camera's fields of view come from the mission's camera (its footprint at the mission altitude), else
/// from each photo's 35 mm-equivalent focal length. Heights: over a plan with a DEM the GPS altitude less
/// the ground under the photo, else the XMP relative altitude, else the GPS altitude less
/// options.takeoff_altitude_m. InputError naming the photo and what is missing. ctx stops (Cancelled).
PhotoCoverage photo_coverage(const Plan& plan, const std::vector<io::PhotoTags>& photos,
                             const PhotoOptions& options = {}, const Context& ctx = {});

/// photos.geojson: a Polygon feature per footprint (properties kind "photo", name, height_m, yaw_deg,
/// pitch_deg, height_source) and a MultiPolygon feature of the gaps (kind "gap", area_m2).
std::string photos_geojson(const PhotoCoverage& coverage);

/// The summary as JSON (photos, skipped, poc, pooc, planned_poc, gaps_m2, gaps, bounds).
nlohmann::json photo_summary(const PhotoCoverage& coverage);

}  // namespace uavcover::usecases
