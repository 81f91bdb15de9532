#include "server/terrain_source.hpp"

#include <fmt/format.h>

#include "io/dem.hpp"
#include "uavcover/error.hpp"

namespace uavcover::server {

void check_server_terrain(const Mission& mission, store::Store& store, const DemDir& dem_dir) {
  if (!mission.terrain) return;
  const Terrain& t = *mission.terrain;
  if (t.dem_id > 0) {
    if (!store.get_dem(t.dem_id))
      throw InputError(
          "terrain.dem_id",
          fmt::format("no elevation model {} is stored (upload it with POST /api/v1/dems)", t.dem_id));
    return;
  }
  if (t.source == "server") {
    if (!dem_dir)
      throw InputError(
          "terrain.source",
          "this server has no DEM tiles (start it with `uavcover serve --dem-dir DIR`); upload a "
          "GeoTIFF with POST /api/v1/dems and give its dem_id");
    return;
  }
  // a DEM named by a mission would be a path on the server's disk chosen by a client: refused
  throw InputError("terrain.dem",
                   "the server reads no elevation model named by a path; upload the GeoTIFF with POST "
                   "/api/v1/dems and give \"dem_id\", or use \"source\": \"server\"");
}

void load_server_terrain(Mission& mission, store::Store& store, const DemDir& dem_dir) {
  if (!mission.terrain || mission.terrain->grid) return;
  check_server_terrain(mission, store, dem_dir);
  const Terrain& t = *mission.terrain;
  if (t.dem_id > 0) {
    const auto dem = store.get_dem(t.dem_id);
    const auto bytes = store.dem_bytes(t.dem_id);
    if (!dem || !bytes)
      throw InputError("terrain.dem_id", fmt::format("elevation model {} is gone", t.dem_id));
    io::load_terrain_bytes(mission, *bytes, dem->name);
    return;
  }
  io::load_terrain_dir(mission, *dem_dir);
}

}  // namespace uavcover::server
