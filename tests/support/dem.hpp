// Synthetic GeoTIFF elevation models written with GDAL for the terrain tests: a Gaussian hill around a
// local frame's origin, in WGS84 or a projected CRS (UTM), with optional nodata, NaN or no CRS.
#pragma once

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "geodesy/local_frame.hpp"

namespace uavcover::testdem {

/// Ground height at local point (x, y): 200 m plain with a hill of `peak` m and sigma `sigma` m at (cx, cy).
struct Hill {
  double base = 200.0, peak = 60.0, sigma = 60.0, cx = 0.0, cy = 0.0;
  [[nodiscard]] double operator()(double x, double y) const {
    return base + peak * std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (2 * sigma * sigma));
  }
};

struct DemSpec {
  int epsg = 4326;        ///< CRS of the raster (4326, or a UTM zone such as 32632)
  bool write_crs = true;  ///< false: a GeoTIFF without a CRS
  double half_m = 400.0;  ///< the raster spans the origin +- half_m (local metres)
  double pixel_m = 4.0;   ///< pixel size, about (metres)
  std::optional<double> nodata;
  /// pixels whose local position satisfies this get `hole_value` (nodata or NaN)
  std::function<bool(double x, double y)> hole;
  float hole_value = std::nanf("");
};

/// Writes the hill as a float32 GeoTIFF at `path` with GDAL; returns the path.
inline std::filesystem::path write_hill(const std::filesystem::path& path, const geodesy::LocalFrame& frame,
                                        const Hill& hill, const DemSpec& spec = {}) {
  GDALAllRegister();
  OGRSpatialReference srs;
  srs.importFromEPSG(spec.epsg);
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  OGRSpatialReference wgs84;
  wgs84.SetWellKnownGeogCS("WGS84");
  wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> to_dem(OGRCreateCoordinateTransformation(&wgs84, &srs));
  std::unique_ptr<OGRCoordinateTransformation> to_wgs(OGRCreateCoordinateTransformation(&srs, &wgs84));
  // corners of the raster in the DEM's CRS: the local square's south-west and north-east corners
  const LonLat sw = frame.to_wgs84({-spec.half_m, -spec.half_m});
  const LonLat ne = frame.to_wgs84({spec.half_m, spec.half_m});
  double x0 = sw.lon, y0 = sw.lat, x1 = ne.lon, y1 = ne.lat;
  to_dem->Transform(1, &x0, &y0);
  to_dem->Transform(1, &x1, &y1);
  const int cols = static_cast<int>(std::ceil(2 * spec.half_m / spec.pixel_m));
  const int rows = cols;
  const double px = (x1 - x0) / cols, py = (y1 - y0) / rows;
  GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GTiff");
  GDALDataset* ds = drv->Create(path.c_str(), cols, rows, 1, GDT_Float32, nullptr);
  if (ds == nullptr) throw std::runtime_error("cannot create " + path.string());
  double gt[6] = {x0, px, 0, y1, 0, -py};  // north-up
  ds->SetGeoTransform(gt);
  if (spec.write_crs) ds->SetSpatialRef(&srs);
  GDALRasterBand* band = ds->GetRasterBand(1);
  if (spec.nodata) band->SetNoDataValue(*spec.nodata);
  std::vector<float> row(static_cast<std::size_t>(cols));
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      double X = x0 + (c + 0.5) * px, Y = y1 - (r + 0.5) * py;
      to_wgs->Transform(1, &X, &Y);
      const Point p = frame.to_local({X, Y});
      row[static_cast<std::size_t>(c)] =
          spec.hole && spec.hole(p.x(), p.y()) ? spec.hole_value : static_cast<float>(hill(p.x(), p.y()));
    }
    if (band->RasterIO(GF_Write, 0, r, cols, 1, row.data(), cols, 1, GDT_Float32, 0, 0) != CE_None)
      throw std::runtime_error("cannot write " + path.string());
  }
  GDALClose(ds);
  return path;
}

}  // namespace uavcover::testdem
