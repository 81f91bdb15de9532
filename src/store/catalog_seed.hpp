// The UAV and camera catalogs a new database starts with (schema migration 2 of both backends, one
// table for both): datasheet values; hfov_deg is the horizontal field of view, 2·atan(sensor width /
// 2·focal length). The cost per minute is the paper's (Apostolidis 2022, eq. 21) for every UAV: it is the
// operator's to set. Never change a released entry: a migration that ran keeps what it wrote.
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <string_view>

namespace uavcover::store::catalog_seed {

struct Camera {
  std::string_view name;
  double sensor_width_mm, focal_length_mm;
  int image_width_px;
  double hfov_deg;
};

struct Uav {
  std::string_view name;
  double speed_mps, max_accel_mps2, endurance_min;
  std::string_view camera;  ///< a camera's name, or empty
};

inline constexpr double kCostPerMinEur = 0.017228;

inline constexpr std::array<Camera, 5> kCameras{{
    {"DJI Phantom 4 Pro camera", 13.2, 8.8, 5472, 73.7},
    {"DJI Mavic 3 Enterprise wide camera", 17.3, 12.29, 5280, 70.3},
    {"DJI Zenmuse P1 (35 mm lens)", 35.9, 35.0, 8192, 54.3},
    {"Sony RX1R II", 35.9, 35.0, 7952, 54.3},
    {"MicaSense RedEdge-MX", 4.8, 5.4, 1280, 47.2},
}};

inline constexpr std::array<Uav, 4> kUavs{{
    {"DJI Phantom 4 Pro V2.0", 10, 4, 28, "DJI Phantom 4 Pro camera"},
    {"DJI Mavic 3 Enterprise", 12, 5, 42, "DJI Mavic 3 Enterprise wide camera"},
    {"DJI Matrice 300 RTK", 15, 5, 55, "DJI Zenmuse P1 (35 mm lens)"},
    {"Generic quadrotor", 5, 2, 25, ""},
}};

/// A camera entry's data.
inline nlohmann::json camera_data(const Camera& k) {
  return {{"name", k.name},
          {"sensor_width_mm", k.sensor_width_mm},
          {"focal_length_mm", k.focal_length_mm},
          {"image_width_px", k.image_width_px},
          {"hfov_deg", k.hfov_deg}};
}

/// A UAV entry's data, without its camera_id (the backend adds the id its camera got).
inline nlohmann::json uav_data(const Uav& u) {
  return {{"name", u.name},
          {"speed_mps", u.speed_mps},
          {"max_accel_mps2", u.max_accel_mps2},
          {"endurance_min", u.endurance_min},
          {"cost_per_min_eur", kCostPerMinEur}};
}

/// Seeds through `insert(kind, name, data) -> id` in the table's order, each UAV with its camera's id.
template <class Insert>
void seed(Insert&& insert) {
  std::array<long long, kCameras.size()> ids{};
  for (std::size_t i = 0; i < kCameras.size(); ++i)
    ids[i] = insert("camera", kCameras[i].name, camera_data(kCameras[i]));
  for (const Uav& u : kUavs) {
    nlohmann::json data = uav_data(u);
    for (std::size_t i = 0; i < kCameras.size(); ++i)
      if (!u.camera.empty() && kCameras[i].name == u.camera) data["camera_id"] = ids[i];
    insert("uav", u.name, data);
  }
}

}  // namespace uavcover::store::catalog_seed
