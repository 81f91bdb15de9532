// Vector files -> a mission skeleton with GDAL/OGR: open the file read-only with the vector drivers we
// support, walk the layers' polygons (closed lines count: DXF and KML draw areas as closed polylines),
// refuse invalid geometry naming the feature, reproject to WGS84 (longitude first), take the largest
// polygon (or the features area_where matches) as the area and the others as no-fly zones.
#include "io/import.hpp"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <fmt/format.h>
#include <gdal_priv.h>
#include <ogr_geometry.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <charconv>
#include <cmath>
#include <memory>
#include <mutex>
#include <numbers>
#include <set>
#include <vector>

#include "io/quiet_gdal.hpp"
#include "uavcover/error.hpp"
#include "uavcover/mission.hpp"

namespace uavcover::io {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFile = "file";
constexpr double kMetresPerDegree = 111'320.0;
constexpr std::size_t kMaxName = 256;

[[noreturn]] void refuse(const std::string& field, const std::string& problem) {
  throw InputError(field, problem);
}

using detail::QuietGdal;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string extension(std::string_view name) {
  const auto dot = name.rfind('.');
  if (dot == std::string_view::npos) return {};
  return lower(std::string(name.substr(dot + 1)));
}

// Free text as the mission format accepts it: no control characters, at most kMaxName bytes (cut at a
// UTF-8 character boundary).
std::string clean_name(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x20 || c == 0x7f) continue;
    if (c == 0xc2 && i + 1 < s.size() && static_cast<unsigned char>(s[i + 1]) >= 0x80 &&
        static_cast<unsigned char>(s[i + 1]) <= 0x9f) {
      ++i;  // U+0080..U+009F
      continue;
    }
    out.push_back(s[i]);
  }
  if (out.size() > kMaxName) {
    std::size_t n = kMaxName;
    while (n > 0 && (static_cast<unsigned char>(out[n]) & 0xc0) == 0x80) --n;
    out.resize(n);
  }
  const auto b = out.find_first_not_of(' ');
  if (b == std::string::npos) return {};
  return out.substr(b, out.find_last_not_of(' ') - b + 1);
}

const char* const kDrivers[] = {"ESRI Shapefile", "KML", "LIBKML", "GPKG", "GeoJSON", "DXF", nullptr};
const std::set<std::string> kInnerExtensions = {"shp", "kml", "gpkg", "geojson", "json", "dxf"};

// The GDAL name to open: a zip's Shapefile folder or its one other vector file, a KMZ's KML.
std::string gdal_name(const std::string& name, const std::string& shown) {
  const std::string ext = extension(name);
  if (ext != "zip" && ext != "kmz") return name;
  const std::string root = "/vsizip/" + name;
  char** list = VSIReadDirRecursive(root.c_str());
  std::vector<std::string> found;
  for (char** p = list; p != nullptr && *p != nullptr; ++p) {
    const std::string entry = *p;
    if (entry.find("__MACOSX") != std::string::npos) continue;
    if (kInnerExtensions.count(extension(entry)) != 0) found.push_back(entry);
  }
  CSLDestroy(list);
  if (found.empty())
    refuse(kFile, fmt::format("{}: not a zip holding a Shapefile (.shp with .shx, .dbf, .prj), KML, "
                              "GeoPackage, GeoJSON or DXF",
                              shown));
  std::sort(found.begin(), found.end());
  const bool all_shp =
      std::all_of(found.begin(), found.end(), [](const auto& f) { return extension(f) == "shp"; });
  if (all_shp) {
    // the folder of the first Shapefile: the driver reads every .shp there as a layer
    const auto slash = found.front().rfind('/');
    return slash == std::string::npos ? root : root + "/" + found.front().substr(0, slash);
  }
  if (found.size() > 1)
    refuse(kFile, fmt::format("{} holds {} files to import ({}, {}, ...): zip one of them", shown,
                              found.size(), found[0], found[1]));
  return root + "/" + found.front();
}

struct Shape {
  std::string layer;
  long long fid = 0;
  std::string name;
  bool selected = false;  // matched area_where
  nlohmann::json rings;   // [[[lon, lat], ...], ...] in WGS84
  double area_m2 = 0;
  std::shared_ptr<OGRPolygon> geometry;  // in WGS84
};

// Planar area of a WGS84 ring in an equirectangular frame at its mean latitude (m²).
double ring_area_m2(const nlohmann::json& ring) {
  double lat0 = 0;
  for (const auto& p : ring) lat0 += p[1].get<double>();
  lat0 /= static_cast<double>(ring.size());
  const double kx = kMetresPerDegree * std::cos(lat0 * std::numbers::pi / 180.0);
  double s = 0;
  for (std::size_t i = 0, n = ring.size(); i < n; ++i) {
    const auto& a = ring[i];
    const auto& b = ring[(i + 1) % n];
    s += a[0].get<double>() * kx * b[1].get<double>() * kMetresPerDegree -
         b[0].get<double>() * kx * a[1].get<double>() * kMetresPerDegree;
  }
  return std::fabs(s) / 2;
}

std::string feature_name(OGRFeature& f) {
  for (const char* field : {"name", "title", "label"}) {
    const int i = f.GetFieldIndex(field);  // case-insensitive: Name, NAME
    if (i >= 0 && f.IsFieldSetAndNotNull(i)) {
      const std::string v = clean_name(f.GetFieldAsString(i));
      if (!v.empty()) return v;
    }
  }
  return {};
}

std::string describe(const std::string& layer, long long fid, const std::string& name) {
  return fmt::format("layer '{}', feature {}{}", layer, fid, name.empty() ? "" : " ('" + name + "')");
}

class Reader {
 public:
  Reader(const ImportOptions& options, const ImportLimits& limits) : options_(options), limits_(limits) {
    if (options.crs) {
      const std::string& c = *options.crs;
      int code = 0;
      const char* end = c.data() + c.size();
      const auto upper = lower(c.substr(0, 5));
      const auto [p, ec] =
          upper == "epsg:" ? std::from_chars(c.data() + 5, end, code) : std::from_chars(end, end, code);
      if (upper != "epsg:" || ec != std::errc() || p != end || code <= 0 ||
          assigned_.importFromEPSG(code) != OGRERR_NONE)
        refuse("crs",
               fmt::format("expected a known EPSG code such as \"EPSG:2100\", got \"{}\"", c.substr(0, 60)));
      assigned_.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
      has_assigned_ = true;
    }
    wgs84_.SetWellKnownGeogCS("WGS84");
    wgs84_.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  }

  std::vector<Shape> read(GDALDataset& ds) {
    std::vector<OGRLayer*> layers;
    if (options_.layer) {
      OGRLayer* l = ds.GetLayerByName(options_.layer->c_str());
      if (l == nullptr) {
        std::string names;
        for (int i = 0; i < ds.GetLayerCount(); ++i)
          names += (i ? ", " : "") + std::string("'") + ds.GetLayer(i)->GetName() + "'";
        refuse("layer", fmt::format("no layer '{}'; the file has {}", options_.layer->substr(0, 100),
                                    names.empty() ? "none" : names));
      }
      layers.push_back(l);
    } else {
      for (int i = 0; i < ds.GetLayerCount(); ++i) layers.push_back(ds.GetLayer(i));
    }
    std::vector<Shape> shapes;
    std::size_t filter_errors = 0;
    std::string filter_problem;
    for (OGRLayer* layer : layers) {
      std::set<long long> selected;
      if (options_.area_where) {
        CPLErrorReset();
        if (layer->SetAttributeFilter(options_.area_where->c_str()) != OGRERR_NONE) {
          ++filter_errors;
          filter_problem = QuietGdal::last();
        } else {
          for (auto& f : *layer) selected.insert(f->GetFID());
        }
        layer->SetAttributeFilter(nullptr);
      }
      read_layer(*layer, selected, shapes);
    }
    if (options_.area_where && filter_errors == layers.size())
      refuse("area_where", fmt::format("not an attribute filter of this file: {}", filter_problem));
    return shapes;
  }

 private:
  void read_layer(OGRLayer& layer, const std::set<long long>& selected, std::vector<Shape>& shapes) {
    const std::string lname = layer.GetName();
    std::unique_ptr<OGRCoordinateTransformation> ct;
    bool ct_ready = false;
    layer.ResetReading();
    for (auto& f : layer) {
      if (++features_ > limits_.max_features)
        refuse(kFile, fmt::format("more than {} features", limits_.max_features));
      OGRGeometry* g = f->GetGeometryRef();
      if (g == nullptr || g->IsEmpty()) continue;
      const std::string name = feature_name(*f);
      const long long fid = f->GetFID();
      if (!ct_ready) {
        ct =
            transform_for(g->getSpatialReference() ? g->getSpatialReference() : layer.GetSpatialRef(), lname);
        ct_ready = true;
      }
      std::vector<std::unique_ptr<OGRPolygon>> polys;
      collect(*g, polys);
      if (polys.empty()) continue;
      for (auto& poly : polys) {
        CPLErrorReset();
        if (!poly->IsValid()) {
          const std::string why = CPLGetLastErrorMsg();
          refuse(kFile, fmt::format("{}: invalid geometry{}", describe(lname, fid, name),
                                    why.empty() ? " (a self-intersecting, unclosed or badly nested ring)"
                                                : ": " + why.substr(0, 200)));
        }
        if (ct && poly->transform(ct.get()) != OGRERR_NONE)
          refuse(kFile, fmt::format("{}: cannot be reprojected to WGS84: {}", describe(lname, fid, name),
                                    QuietGdal::last()));
        Shape s{lname, fid, name, selected.count(fid) != 0, nlohmann::json::array(), 0, nullptr};
        add_ring(*poly->getExteriorRing(), s, lname, fid, name);
        double area = ring_area_m2(s.rings[0]);
        for (int r = 0; r < poly->getNumInteriorRings(); ++r) {
          add_ring(*poly->getInteriorRing(r), s, lname, fid, name);
          area -= ring_area_m2(s.rings.back());
        }
        s.area_m2 = area;
        s.geometry = std::shared_ptr<OGRPolygon>(poly.release());
        shapes.push_back(std::move(s));
      }
    }
  }

  std::unique_ptr<OGRCoordinateTransformation> transform_for(const OGRSpatialReference* srs,
                                                             const std::string& lname) {
    const OGRSpatialReference* from = srs;
    if (from == nullptr && has_assigned_) from = &assigned_;
    if (from == nullptr) {
      no_crs_ = true;  // checked per vertex: only longitude/latitude ranges are taken as WGS84
      return nullptr;
    }
    OGRSpatialReference src(*from);
    src.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    std::unique_ptr<OGRCoordinateTransformation> ct(OGRCreateCoordinateTransformation(&src, &wgs84_));
    if (!ct)
      refuse(kFile,
             fmt::format("layer '{}': its CRS cannot be transformed to WGS84: {}", lname, QuietGdal::last()));
    return ct;
  }

  // Polygons of any geometry: polygons, multi-polygons, curves (linearised), closed lines, collections.
  static void collect(const OGRGeometry& g, std::vector<std::unique_ptr<OGRPolygon>>& out) {
    const auto type = wkbFlatten(g.getGeometryType());
    if (type == wkbPolygon) {
      out.emplace_back(g.toPolygon()->clone());
    } else if (type == wkbCurvePolygon) {
      std::unique_ptr<OGRGeometry> lin(g.getLinearGeometry());
      if (lin) collect(*lin, out);
    } else if (type == wkbLineString || type == wkbCircularString || type == wkbCompoundCurve) {
      std::unique_ptr<OGRGeometry> lin(g.getLinearGeometry());
      if (!lin || wkbFlatten(lin->getGeometryType()) != wkbLineString) return;
      const OGRLineString* ls = lin->toLineString();
      if (ls->getNumPoints() < 4 || !ls->get_IsClosed()) return;  // an open line bounds nothing
      auto poly = std::make_unique<OGRPolygon>();
      auto ring = std::make_unique<OGRLinearRing>();
      for (int i = 0; i < ls->getNumPoints(); ++i) ring->addPoint(ls->getX(i), ls->getY(i));
      poly->addRingDirectly(ring.release());
      out.push_back(std::move(poly));
    } else if (OGR_GT_IsSubClassOf(type, wkbGeometryCollection)) {
      for (const OGRGeometry* part : *g.toGeometryCollection()) collect(*part, out);
    }
  }

  void add_ring(const OGRLinearRing& ring, Shape& s, const std::string& lname, long long fid,
                const std::string& name) {
    vertices_ += static_cast<std::size_t>(ring.getNumPoints());
    if (vertices_ > limits_.max_vertices)
      refuse(kFile, fmt::format("more than {} vertices", limits_.max_vertices));
    nlohmann::json r = nlohmann::json::array();
    for (int i = 0; i < ring.getNumPoints(); ++i) {
      const double lon = ring.getX(i), lat = ring.getY(i);
      if (!std::isfinite(lon) || !std::isfinite(lat) || lon < -180 || lon > 180 || lat < -90 || lat > 90)
        refuse(no_crs_ ? "crs" : kFile,
               fmt::format("{}: ({:.3f}, {:.3f}) is not a WGS84 longitude/latitude{}",
                           describe(lname, fid, name), lon, lat,
                           no_crs_ ? "; the file has no CRS: name its CRS (crs, e.g. \"EPSG:2100\")" : ""));
      r.push_back({std::round(lon * 1e9) / 1e9, std::round(lat * 1e9) / 1e9});
    }
    s.rings.push_back(std::move(r));
  }

  const ImportOptions& options_;
  const ImportLimits& limits_;
  OGRSpatialReference wgs84_, assigned_;
  bool has_assigned_ = false;
  bool no_crs_ = false;
  std::size_t features_ = 0, vertices_ = 0;
};

nlohmann::json polygon_json(const Shape& s) { return {{"type", "Polygon"}, {"coordinates", s.rings}}; }

nlohmann::json skeleton(std::vector<Shape> shapes, const ImportOptions& options, const std::string& stem) {
  if (shapes.empty())
    refuse(options.layer ? "layer" : kFile, "no polygon to import (points and open lines bound no area)");
  std::vector<const Shape*> area, zones;
  if (options.area_where) {
    for (const auto& s : shapes)
      if (s.selected) area.push_back(&s);
    if (area.empty())
      refuse("area_where", "no polygon matches \"" + options.area_where->substr(0, 100) + "\"");
    // the others are zones, but not one around a chosen area (a farm's boundary around its field)
    for (const auto& s : shapes)
      if (!s.selected && std::none_of(area.begin(), area.end(), [&](const Shape* a) {
            return s.geometry->Contains(a->geometry.get());
          }))
        zones.push_back(&s);
  } else {
    const auto largest = std::max_element(
        shapes.begin(), shapes.end(), [](const Shape& a, const Shape& b) { return a.area_m2 < b.area_m2; });
    area.push_back(&*largest);
    for (const auto& s : shapes)
      if (&s != &*largest) zones.push_back(&s);
  }
  nlohmann::json m = options.template_mission.is_null() ? nlohmann::json::object() : options.template_mission;
  if (!m.is_object()) refuse("template", "expected a mission object");
  m.erase("corridor");
  if (!m.contains("uavs")) m["uavs"] = 1;
  if (!m.contains("spacing_m") && !m.contains("camera")) m["spacing_m"] = 30;
  std::string name = area.front()->name;
  if (name.empty()) name = clean_name(area.front()->layer);
  if (name.empty()) name = clean_name(stem);
  if (!name.empty()) m["name"] = name;
  if (area.size() == 1) {
    m["area"] = polygon_json(*area.front());
  } else {
    nlohmann::json coords = nlohmann::json::array();
    for (const Shape* s : area) coords.push_back(s->rings);
    m["area"] = {{"type", "MultiPolygon"}, {"coordinates", coords}};
  }
  nlohmann::json nfz = nlohmann::json::array();
  for (const Shape* s : zones) {
    nlohmann::json props = {{"layer", s->layer}};
    if (!s->name.empty()) props["name"] = s->name;
    nfz.push_back({{"type", "Feature"}, {"properties", props}, {"geometry", polygon_json(*s)}});
  }
  m["no_fly_zones"] = nfz;
  parse_mission(m.dump());  // the skeleton is a mission: InputError naming the field otherwise
  return m;
}

nlohmann::json import_named(const std::string& name, const std::string& shown, const std::string& stem,
                            const ImportOptions& options, const ImportLimits& limits) {
  QuietGdal quiet("DXF_CLOSED_LINE_AS_POLYGON", "TRUE");
  Reader reader(options, limits);  // checks crs before the file is opened
  const std::string open_name = gdal_name(name, shown);
  std::unique_ptr<GDALDataset> ds(
      GDALDataset::Open(open_name.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, kDrivers, nullptr, nullptr));
  if (!ds)
    refuse(kFile,
           fmt::format("{}: not a Shapefile, KML, KMZ, GeoPackage, GeoJSON or DXF file GDAL can read: {}",
                       shown, QuietGdal::last()));
  return skeleton(reader.read(*ds), options, stem);
}

std::atomic<unsigned long long> g_upload_counter{0};

}  // namespace

nlohmann::json import_mission(const fs::path& file, const ImportOptions& options,
                              const ImportLimits& limits) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) refuse(kFile, file.string() + ": no such file");
  return import_named(file.string(), file.filename().string(), file.stem().string(), options, limits);
}

nlohmann::json import_mission_bytes(std::string_view bytes, std::string_view filename,
                                    const ImportOptions& options, const ImportLimits& limits) {
  static const std::set<std::string> kUploads = {"zip", "kmz", "kml", "gpkg", "geojson", "json", "dxf"};
  const std::string ext = extension(filename);
  if (kUploads.count(ext) == 0)
    refuse("file", fmt::format("the file name must end in .zip (a zipped Shapefile), .kmz, .kml, .gpkg, "
                               ".geojson, .json or .dxf, got \"{}\"",
                               clean_name(std::string(filename.substr(0, 100)))));
  if (bytes.empty()) refuse("file", "the file is empty");
  // a private in-memory file: the name is ours (a counter), never the client's
  const std::string dir = fmt::format("/vsimem/uavcover_import_{}", ++g_upload_counter);
  const std::string path = dir + "/upload." + ext;
  struct Cleanup {
    std::string dir;
    ~Cleanup() { VSIRmdirRecursive(dir.c_str()); }
  } cleanup{dir};
  VSIMkdir(dir.c_str(), 0700);
  VSILFILE* f = VSIFileFromMemBuffer(path.c_str(), reinterpret_cast<GByte*>(const_cast<char*>(bytes.data())),
                                     static_cast<vsi_l_offset>(bytes.size()), /*bTakeOwnership=*/FALSE);
  if (f == nullptr) throw OperationError("cannot hold the upload in memory");
  VSIFCloseL(f);
  std::string stem(filename);
  if (const auto slash = stem.find_last_of("/\\"); slash != std::string::npos) stem = stem.substr(slash + 1);
  stem = stem.substr(0, stem.rfind('.'));
  return import_named(path, "the upload", stem, options, limits);
}

}  // namespace uavcover::io
