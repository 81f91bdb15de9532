// `uavcover import FILE [--out MISSION.json] [--layer NAME] [--where FILTER] [--crs EPSG:N]
// [--template MISSION.json]`: a mission skeleton from the polygons of a zipped Shapefile, KML, KMZ,
// GeoPackage, GeoJSON or DXF file (docs/import.md).
#include <iostream>

#include "cli/command.hpp"
#include "io/import.hpp"
#include "io/plan_io.hpp"
#include "json/strict.hpp"
#include "uavcover/error.hpp"

namespace uavcover::cli {
namespace {

struct ImportArgs {
  std::string file;
  std::string out;
  std::string layer, where, crs, template_file;
};

void run_import(const ImportArgs& a) {
  io::ImportOptions opt;
  if (!a.layer.empty()) opt.layer = a.layer;
  if (!a.where.empty()) opt.area_where = a.where;
  if (!a.crs.empty()) opt.crs = a.crs;
  if (!a.template_file.empty())
    opt.template_mission = strict::parse_json(io::read_text_file(a.template_file, "template"), "template");
  const nlohmann::json mission = io::import_mission(a.file, opt);
  const std::string text = mission.dump(1) + "\n";
  if (a.out.empty()) {
    std::cout << text;
    return;
  }
  io::write_file_atomic(a.out, text);
  if (!global_flags().quiet)
    std::cerr << "wrote " << a.out << ": area \"" << mission.value("name", "mission") << "\" and "
              << mission["no_fly_zones"].size() << " no-fly zone(s)\n";
}

const bool registered = CommandRegistry::add(5, [](CLI::App& app) {
  auto a = std::make_shared<ImportArgs>();
  auto* cmd = app.add_subcommand(
      "import", "A mission skeleton from a zipped Shapefile, KML, KMZ, GeoPackage, GeoJSON or DXF file");
  cmd->add_option("FILE", a->file, "The file (.zip, .kmz, .kml, .gpkg, .geojson, .json, .dxf, .shp)")
      ->required();
  cmd->add_option("--out,-o", a->out, "Write the mission here (default: standard output)");
  cmd->add_option("--layer", a->layer, "Read only this layer (default: every layer)");
  cmd->add_option("--where", a->where,
                  "The features this attribute filter matches are the area, e.g. \"name = 'North'\" "
                  "(default: the largest polygon; the others are no-fly zones)");
  cmd->add_option("--crs", a->crs, "The CRS of a file that has none (DXF), e.g. EPSG:2100");
  cmd->add_option("--template", a->template_file,
                  "A mission file whose other fields (spacing, camera, UAVs, ...) the skeleton takes");
  cmd->footer("Exit codes: 0 ok, 1 internal error, 2 bad input (message names the field and feature).");
  cmd->callback([a] { run_import(*a); });
});

}  // namespace
}  // namespace uavcover::cli
