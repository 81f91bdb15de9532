// GeoTIFF DEM -> HeightGrid with GDAL: open read-only with the GTiff driver alone, transform the grid's
// WGS84 nodes to the DEM's CRS (traditional GIS axis order: longitude/easting first), read the window
// of pixels they need, sample bilinearly between pixel centres.
#include "io/dem.hpp"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <fmt/format.h>
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/quiet_gdal.hpp"
#include "uavcover/error.hpp"

namespace uavcover::io {

namespace fs = std::filesystem;

namespace {

constexpr const char* kField = "terrain.dem";
constexpr double kMetresPerDegree = 111'320.0;
constexpr double kMaxAbsHeight = 12'000.0;  // deeper than any sea floor, higher than any summit

[[noreturn]] void refuse(const std::string& problem) { throw InputError(kField, problem); }

using detail::QuietGdal;

struct Box {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0;
  double x1 = -std::numeric_limits<double>::infinity(), y1 = x1;
  std::size_t n = 0;
  void add(double x, double y) {
    x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
    ++n;
  }
  [[nodiscard]] std::string lonlat() const {
    return fmt::format("longitude {:.6f}..{:.6f}, latitude {:.6f}..{:.6f}", x0, x1, y0, y1);
  }
};

// WGS84 -> the DEM's CRS -> fractional pixel/line coordinates (pixel centres at i + 0.5).
class ToPixel {
 public:
  ToPixel(const OGRSpatialReference& dem_srs, const double* gt) {
    OGRSpatialReference wgs84;
    wgs84.SetWellKnownGeogCS("WGS84");
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    OGRSpatialReference dem(dem_srs);
    dem.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    ct_.reset(OGRCreateCoordinateTransformation(&wgs84, &dem));
    if (!ct_)
      refuse("its coordinate reference system cannot be reached from WGS84 (" + QuietGdal::last() + ")");
    if (!GDALInvGeoTransform(const_cast<double*>(gt), inv_)) refuse("its geotransform cannot be inverted");
  }
  /// Transforms x (lon) / y (lat) in place into pixel (x) / line (y); ok[k] false where it fails.
  void operator()(std::vector<double>& x, std::vector<double>& y, std::vector<int>& ok) const {
    ok.assign(x.size(), 0);
    ct_->Transform(x.size(), x.data(), y.data(), nullptr, ok.data());
    for (std::size_t k = 0; k < x.size(); ++k) {
      if (!ok[k] || !std::isfinite(x[k]) || !std::isfinite(y[k])) {
        ok[k] = 0;
        continue;
      }
      const double X = x[k], Y = y[k];
      x[k] = inv_[0] + inv_[1] * X + inv_[2] * Y;
      y[k] = inv_[3] + inv_[4] * X + inv_[5] * Y;
    }
  }

 private:
  std::unique_ptr<OGRCoordinateTransformation> ct_;
  double inv_[6] = {};
};

}  // namespace

namespace {

/// The extent in WGS84 of a raster's four corners (W x H pixels, geotransform `gt`, CRS `srs`); empty when
/// the CRS cannot be transformed to WGS84. `n` counts the corners that transformed to finite values.
std::optional<Box> wgs84_extent(const OGRSpatialReference& srs, const double* gt, int W, int H) {
  OGRSpatialReference wgs84;
  wgs84.SetWellKnownGeogCS("WGS84");
  wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  OGRSpatialReference dem(srs);
  dem.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> back(OGRCreateCoordinateTransformation(&dem, &wgs84));
  if (!back) return std::nullopt;
  Box b;
  for (const auto& [cx, cy] : std::initializer_list<std::pair<int, int>>{{0, 0}, {W, 0}, {0, H}, {W, H}}) {
    double X = gt[0] + cx * gt[1] + cy * gt[2], Y = gt[3] + cx * gt[4] + cy * gt[5];
    if (back->Transform(1, &X, &Y) && std::isfinite(X) && std::isfinite(Y)) b.add(X, Y);
  }
  return b;
}

/// A unique /vsimem/ name for one read.
std::string vsimem_name(const char* ext) {
  static std::atomic<unsigned long long> counter{0};
  return fmt::format("/vsimem/uavcover-dem-{}{}", counter.fetch_add(1), ext);
}

/// Removes a /vsimem/ file when it goes out of scope.
struct MemFile {
  std::string name;
  explicit MemFile(std::string n) : name(std::move(n)) {}
  MemFile(MemFile&& o) noexcept : name(std::exchange(o.name, {})) {}  // the moved-from one unlinks nothing
  MemFile(const MemFile&) = delete;
  MemFile& operator=(const MemFile&) = delete;
  MemFile& operator=(MemFile&&) = delete;
  ~MemFile() {
    if (!name.empty()) VSIUnlink(name.c_str());
  }
};

/// Opens `path` (a file, /vsimem/ or a VRT) with `drivers` only; refuses naming `shown` when it cannot.
GDALDatasetUniquePtr open_dem(const std::string& path, const char* const* drivers, const std::string& shown) {
  GDALDatasetUniquePtr ds(GDALDataset::FromHandle(
      GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, drivers, nullptr, nullptr)));
  if (!ds) refuse("'" + shown + "' is not a GeoTIFF that GDAL can read (" + QuietGdal::last() + ")");
  return ds;
}

HeightGrid read_dataset(GDALDataset* ds, const fs::path& file, double west, double south, double east,
                        double north, const DemLimits& limits);

}  // namespace

HeightGrid read_dem(const fs::path& file, double west, double south, double east, double north,
                    const DemLimits& limits) {
  std::error_code ec;
  const auto st = fs::status(file, ec);
  if (ec || !fs::exists(st)) refuse("cannot open '" + file.string() + "': no such file");
  if (!fs::is_regular_file(st)) refuse("'" + file.string() + "' is not a regular file");
  if (!(west < east) || !(south < north)) refuse("the mission's extent is empty");
  QuietGdal quiet("GDAL_DISABLE_READDIR_ON_OPEN", "EMPTY_DIR");
  const char* const drivers[] = {"GTiff", nullptr};
  const GDALDatasetUniquePtr ds = open_dem(file.string(), drivers, file.string());
  return read_dataset(ds.get(), file, west, south, east, north, limits);
}

namespace {

/// A GeoTIFF held in memory, opened through /vsimem/ (GDAL reads the caller's buffer in place, which
/// outlives the dataset); the dataset closes before the file is unlinked.
struct MemDem {
  MemFile file;
  GDALDatasetUniquePtr ds;
};

MemDem open_bytes(std::string_view bytes, const std::string& name) {
  MemDem m{MemFile(vsimem_name(".tif")), nullptr};
  VSILFILE* f =
      VSIFileFromMemBuffer(m.file.name.c_str(), reinterpret_cast<GByte*>(const_cast<char*>(bytes.data())),
                           static_cast<vsi_l_offset>(bytes.size()), FALSE);
  if (f == nullptr) refuse("'" + name + "' cannot be read from memory");
  VSIFCloseL(f);
  const char* const drivers[] = {"GTiff", nullptr};
  m.ds = open_dem(m.file.name, drivers, name);
  return m;
}

}  // namespace

HeightGrid read_dem_bytes(std::string_view bytes, const std::string& name, double west, double south,
                          double east, double north, const DemLimits& limits) {
  if (!(west < east) || !(south < north)) refuse("the mission's extent is empty");
  QuietGdal quiet("GDAL_DISABLE_READDIR_ON_OPEN", "EMPTY_DIR");
  const MemDem m = open_bytes(bytes, name);
  return read_dataset(m.ds.get(), fs::path(name), west, south, east, north, limits);
}

DemInfo inspect_dem_bytes(std::string_view bytes, const std::string& name) {
  QuietGdal quiet("GDAL_DISABLE_READDIR_ON_OPEN", "EMPTY_DIR");
  const MemDem m = open_bytes(bytes, name);
  GDALDataset* ds = m.ds.get();
  DemInfo info;
  info.width = ds->GetRasterXSize();
  info.height = ds->GetRasterYSize();
  if (ds->GetRasterCount() < 1) refuse("'" + name + "' has no raster band");
  double gt[6];
  if (ds->GetGeoTransform(gt) != CE_None) refuse("'" + name + "' has no georeferencing (geotransform)");
  const OGRSpatialReference* srs = ds->GetSpatialRef();
  if (srs == nullptr || srs->IsEmpty())
    refuse("'" + name +
           "' has no coordinate reference system: write one into the GeoTIFF (gdal_edit.py -a_srs)");
  const int W = info.width, H = info.height;
  const std::optional<Box> extent = wgs84_extent(*srs, gt, W, H);
  if (!extent)
    refuse("its coordinate reference system cannot be transformed to WGS84 (" + QuietGdal::last() + ")");
  const Box& b = *extent;
  if (b.n != 4 || !(b.x0 >= -180.0 && b.x1 <= 180.0 && b.y0 >= -90.0 && b.y1 <= 90.0))
    refuse("'" + name + "' does not lie on the globe in WGS84");
  info.west = b.x0, info.south = b.y0, info.east = b.x1, info.north = b.y1;
  const char* wkt_name = srs->GetName();
  info.crs = wkt_name != nullptr ? wkt_name : "";
  return info;
}

HeightGrid read_dem_dir(const fs::path& dir, double west, double south, double east, double north,
                        const DemLimits& limits) {
  if (!(west < east) || !(south < north)) refuse("the mission's extent is empty");
  std::error_code ec;
  std::vector<std::string> tiles;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_regular_file(ec)) continue;
    std::string ext = it->path().extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".tif" || ext == ".tiff" || ext == ".hgt") tiles.push_back(it->path().string());
    if (tiles.size() > 100000) break;
  }
  if (ec) refuse("cannot read the server's DEM folder (" + ec.message() + ")");
  if (tiles.empty()) refuse("the server's DEM folder holds no GeoTIFF or SRTM .hgt tiles");
  std::sort(tiles.begin(), tiles.end());  // the same mosaic whatever the folder's order
  QuietGdal quiet("GDAL_DISABLE_READDIR_ON_OPEN", "EMPTY_DIR");
  // the tiles that overlap the box, as one virtual mosaic (GDALBuildVRT)
  const char* const tile_drivers[] = {"GTiff", "SRTMHGT", nullptr};
  std::vector<GDALDatasetH> open;
  std::vector<GDALDatasetUniquePtr> keep;
  for (const auto& t : tiles) {
    GDALDatasetUniquePtr ds(GDALDataset::FromHandle(
        GDALOpenEx(t.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, tile_drivers, nullptr, nullptr)));
    if (!ds) continue;  // not a raster GDAL reads: not a tile
    double gt[6];
    const OGRSpatialReference* srs = ds->GetSpatialRef();
    if (ds->GetGeoTransform(gt) != CE_None || srs == nullptr || !srs->IsGeographic()) continue;
    const double x0 = gt[0], x1 = gt[0] + gt[1] * ds->GetRasterXSize();
    const double y1 = gt[3], y0 = gt[3] + gt[5] * ds->GetRasterYSize();
    if (std::min(x0, x1) > east || std::max(x0, x1) < west || std::min(y0, y1) > north ||
        std::max(y0, y1) < south)
      continue;
    open.push_back(GDALDataset::ToHandle(ds.get()));
    keep.push_back(std::move(ds));
  }
  if (open.empty())
    refuse(fmt::format(
        "no tile of the server's DEM folder covers the mission (longitude {:.6f}..{:.6f}, latitude "
        "{:.6f}..{:.6f}; the folder holds {} files)",
        west, east, south, north, tiles.size()));
  MemFile vrt{vsimem_name(".vrt")};
  int usage_error = 0;
  GDALDatasetH mosaic = GDALBuildVRT(vrt.name.c_str(), static_cast<int>(open.size()), open.data(), nullptr,
                                     nullptr, &usage_error);
  if (mosaic == nullptr) refuse("the server's DEM tiles cannot be joined (" + QuietGdal::last() + ")");
  GDALDatasetUniquePtr ds(GDALDataset::FromHandle(mosaic));
  HeightGrid g = read_dataset(ds.get(), fs::path("server DEM tiles"), west, south, east, north, limits);
  g.source = fmt::format("server DEM folder: {} of {} tiles", open.size(), tiles.size());
  return g;
}

namespace {

HeightGrid read_dataset(GDALDataset* ds, const fs::path& file, double west, double south, double east,
                        double north, const DemLimits& limits) {
  if (ds->GetRasterCount() < 1) refuse("'" + file.string() + "' has no raster band");
  const int W = ds->GetRasterXSize(), H = ds->GetRasterYSize();
  double gt[6];
  if (ds->GetGeoTransform(gt) != CE_None)
    refuse("'" + file.string() + "' has no georeferencing (geotransform)");
  const OGRSpatialReference* srs = ds->GetSpatialRef();
  if (srs == nullptr || srs->IsEmpty())
    refuse("'" + file.string() +
           "' has no coordinate reference system: write one into the GeoTIFF (gdal_edit.py -a_srs)");
  const ToPixel to_pixel(*srs, gt);
  GDALRasterBand* band = ds->GetRasterBand(1);
  int has_nodata = 0;
  const double nodata = band->GetNoDataValue(&has_nodata);

  // the grid: about one node per DEM pixel, from the pixels per degree at the box's centre
  const double clon = 0.5 * (west + east), clat = 0.5 * (south + north);
  const double d = 1e-4;
  std::vector<double> px{clon, clon + d, clon}, py{clat, clat, clat + d};
  std::vector<int> ok;
  to_pixel(px, py, ok);
  if (!(ok[0] && ok[1] && ok[2]))
    refuse("the mission's area cannot be transformed into its coordinate reference system");
  const double ppd_lon = std::hypot(px[1] - px[0], py[1] - py[0]) / d;  // pixels per degree of longitude
  const double ppd_lat = std::hypot(px[2] - px[0], py[2] - py[0]) / d;
  if (!(ppd_lon > 0) || !(ppd_lat > 0)) refuse("its pixels have no size");
  double dlon = 1.0 / ppd_lon, dlat = 1.0 / ppd_lat;
  auto count = [&](double span, double step) { return std::max(2.0, std::ceil(span / step) + 1.0); };
  const double max_nodes = static_cast<double>(std::max<std::size_t>(limits.max_grid_nodes, 4));
  while (count(east - west, dlon) * count(north - south, dlat) > max_nodes) dlon *= 1.05, dlat *= 1.05;
  HeightGrid g;
  g.lon0 = west, g.lat0 = south;
  g.cols = static_cast<int>(count(east - west, dlon));
  g.rows = static_cast<int>(count(north - south, dlat));
  g.dlon = (east - west) / (g.cols - 1);
  g.dlat = (north - south) / (g.rows - 1);
  g.step_m = kMetresPerDegree * std::min(g.dlat, g.dlon * std::cos(clat * std::numbers::pi / 180.0));

  auto row_pixels = [&](int r, std::vector<double>& x, std::vector<double>& y, std::vector<int>& okr) {
    x.resize(static_cast<std::size_t>(g.cols));
    y.assign(static_cast<std::size_t>(g.cols), g.lat0 + r * g.dlat);
    for (int c = 0; c < g.cols; ++c) x[static_cast<std::size_t>(c)] = g.lon0 + c * g.dlon;
    to_pixel(x, y, okr);
  };
  auto inside = [&](double x, double y) { return x >= 0 && y >= 0 && x <= W && y <= H; };

  // pass 1: the window of pixels the nodes need, and the nodes outside the raster
  Box outside, window;
  std::vector<double> x, y;
  for (int r = 0; r < g.rows; ++r) {
    row_pixels(r, x, y, ok);
    for (int c = 0; c < g.cols; ++c) {
      const auto k = static_cast<std::size_t>(c);
      if (!ok[k] || !inside(x[k], y[k]))
        outside.add(g.lon0 + c * g.dlon, g.lat0 + r * g.dlat);
      else
        window.add(x[k], y[k]);
    }
  }
  if (outside.n > 0) {
    // the DEM's own extent in WGS84 (its corners), to say what it does cover
    std::string covers;
    if (const auto b = wgs84_extent(*srs, gt, W, H); b && b->n == 4)
      covers = "; the DEM covers " + b->lonlat();
    refuse(fmt::format("'{}' does not cover the mission: no ground heights for {} ({} of {} grid points){}",
                       file.string(), outside.lonlat(), outside.n,
                       static_cast<std::size_t>(g.cols) * static_cast<std::size_t>(g.rows), covers));
  }
  const int x0 = std::clamp(static_cast<int>(std::floor(window.x0 - 0.5)), 0, W - 1);
  const int y0 = std::clamp(static_cast<int>(std::floor(window.y0 - 0.5)), 0, H - 1);
  const int x1 = std::clamp(static_cast<int>(std::floor(window.x1 + 0.5)), 0, W - 1);
  const int y1 = std::clamp(static_cast<int>(std::floor(window.y1 + 0.5)), 0, H - 1);
  const int ww = x1 - x0 + 1, wh = y1 - y0 + 1;
  const double pixels = static_cast<double>(ww) * static_cast<double>(wh);
  if (pixels > static_cast<double>(limits.max_window_pixels))
    refuse(fmt::format(
        "the mission needs a window of {} x {} pixels of '{}' ({} x {}), more than the limit of {} "
        "pixels: crop or resample the DEM to the mission's area",
        ww, wh, file.string(), W, H, limits.max_window_pixels));
  std::vector<float> buf(static_cast<std::size_t>(ww) * static_cast<std::size_t>(wh));
  if (band->RasterIO(GF_Read, x0, y0, ww, wh, buf.data(), ww, wh, GDT_Float32, 0, 0) != CE_None)
    refuse("reading its pixels failed (" + QuietGdal::last() + ")");

  // pass 2: bilinear between the pixel centres around each node
  Box missing, nans, wild;
  g.heights.resize(static_cast<std::size_t>(g.cols) * static_cast<std::size_t>(g.rows));
  g.max_m = -std::numeric_limits<double>::infinity();
  auto pixel = [&](int cx, int cy) {
    cx = std::clamp(cx, 0, W - 1) - x0, cy = std::clamp(cy, 0, H - 1) - y0;
    return static_cast<double>(
        buf[static_cast<std::size_t>(cy) * static_cast<std::size_t>(ww) + static_cast<std::size_t>(cx)]);
  };
  for (int r = 0; r < g.rows; ++r) {
    row_pixels(r, x, y, ok);
    for (int c = 0; c < g.cols; ++c) {
      const auto k = static_cast<std::size_t>(c);
      const double lon = g.lon0 + c * g.dlon, lat = g.lat0 + r * g.dlat;
      const double fx = x[k] - 0.5, fy = y[k] - 0.5;
      const int cx = static_cast<int>(std::floor(fx)), cy = static_cast<int>(std::floor(fy));
      const double tx = std::clamp(fx - cx, 0.0, 1.0), ty = std::clamp(fy - cy, 0.0, 1.0);
      const double h00 = pixel(cx, cy), h10 = pixel(cx + 1, cy), h01 = pixel(cx, cy + 1),
                   h11 = pixel(cx + 1, cy + 1);
      bool bad = false;
      for (double h : {h00, h10, h01, h11}) {
        if (has_nodata && (h == nodata || (std::isnan(nodata) && std::isnan(h)))) {
          missing.add(lon, lat), bad = true;
          break;
        }
        if (!std::isfinite(h)) {
          nans.add(lon, lat), bad = true;
          break;
        }
        if (std::fabs(h) > kMaxAbsHeight) {
          wild.add(lon, lat), bad = true;
          break;
        }
      }
      if (bad) continue;
      const double h = (1 - ty) * ((1 - tx) * h00 + tx * h10) + ty * ((1 - tx) * h01 + tx * h11);
      g.heights[static_cast<std::size_t>(r) * static_cast<std::size_t>(g.cols) + k] = static_cast<float>(h);
      g.max_m = std::max(g.max_m, h);
    }
  }
  if (missing.n > 0)
    refuse(fmt::format(
        "'{}' has no data (nodata value {}) under the mission: no ground heights for {} ({} grid points)",
        file.string(), nodata, missing.lonlat(), missing.n));
  if (nans.n > 0)
    refuse(fmt::format(
        "'{}' has NaN or infinite heights under the mission (and no nodata value saying so) at {} ({} grid "
        "points)",
        file.string(), nans.lonlat(), nans.n));
  if (wild.n > 0)
    refuse(
        fmt::format("'{}' has heights beyond +-{} m under the mission at {} ({} grid points): not an "
                    "elevation model in metres",
                    file.string(), kMaxAbsHeight, wild.lonlat(), wild.n));
  g.source = fmt::format("{} ({} x {} pixels, window {} x {} at pixel {}, {})", file.filename().string(), W,
                         H, ww, wh, x0, y0);
  return g;
}

}  // namespace

TerrainBox terrain_box(const Mission& mission) {
  Box b;
  auto add_rings = [&](const std::vector<GeoPolygon>& polys) {
    for (const auto& poly : polys)
      for (const auto& ring : poly)
        for (const LonLat& p : ring) b.add(p.lon, p.lat);
  };
  add_rings(mission.area);
  add_rings(mission.no_fly_zones);
  for (const Uav& u : mission.uavs)
    if (u.start) b.add(u.start->lon, u.start->lat);
  const double margin_m = std::max(50.0, 2.0 * mission.spacing_m);
  const double lat = 0.5 * (b.y0 + b.y1);
  const double mlat = margin_m / kMetresPerDegree;
  const double mlon =
      margin_m / (kMetresPerDegree * std::max(0.01, std::cos(lat * std::numbers::pi / 180.0)));
  return {std::max(-180.0, b.x0 - mlon), std::max(-90.0, b.y0 - mlat), std::min(180.0, b.x1 + mlon),
          std::min(90.0, b.y1 + mlat)};
}

void load_terrain(Mission& mission, const fs::path& base_dir, const DemLimits& limits) {
  if (!mission.terrain) return;
  if (mission.terrain->dem_id > 0 || mission.terrain->source == "server")
    refuse(
        "names a DEM stored in a server (dem_id) or the server's tiles (source): plan it through the "
        "server, or name the GeoTIFF file (dem)");
  const TerrainBox box = terrain_box(mission);
  fs::path file(mission.terrain->dem);
  if (file.is_relative()) file = base_dir / file;
  auto grid = std::make_shared<HeightGrid>(read_dem(file, box.west, box.south, box.east, box.north, limits));
  mission.terrain->dem = fs::absolute(file).lexically_normal().string();
  mission.terrain->grid = std::move(grid);
}

void load_terrain_bytes(Mission& mission, std::string_view bytes, const std::string& name,
                        const DemLimits& limits) {
  if (!mission.terrain) return;
  const TerrainBox box = terrain_box(mission);
  mission.terrain->grid = std::make_shared<HeightGrid>(
      read_dem_bytes(bytes, name, box.west, box.south, box.east, box.north, limits));
}

void load_terrain_dir(Mission& mission, const fs::path& dir, const DemLimits& limits) {
  if (!mission.terrain) return;
  const TerrainBox box = terrain_box(mission);
  mission.terrain->grid =
      std::make_shared<HeightGrid>(read_dem_dir(dir, box.west, box.south, box.east, box.north, limits));
}

}  // namespace uavcover::io
