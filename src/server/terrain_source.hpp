// The server's ground heights (issue 31, docs/api.md "Elevation models"): a mission's terrain block names
// a DEM stored with POST /api/v1/dems ("dem_id") or the tile folder of `serve --dem-dir` ("source":
// "server"); never a file on the server's disk chosen by a client.
#pragma once

#include <filesystem>
#include <optional>

#include "store/store.hpp"
#include "uavcover/mission.hpp"

namespace uavcover::server {

/// The server's DEM tile folder (`serve --dem-dir`), if it has one.
using DemDir = std::optional<std::filesystem::path>;

/// Checks a submitted mission's terrain block: refuses `dem` (a path; InputError terrain.dem), a
/// dem_id the store does not hold (terrain.dem_id) and "source": "server" without a tile folder
/// (terrain.source). Reads nothing but the DEM's row.
void check_server_terrain(const Mission& mission, store::Store& store, const DemDir& dem_dir);

/// Sets mission.terrain->grid from the stored DEM or the tile folder; nothing without a terrain block
/// or when the grid is already there. InputError naming the field as io::read_dem does.
void load_server_terrain(Mission& mission, store::Store& store, const DemDir& dem_dir);

}  // namespace uavcover::server
