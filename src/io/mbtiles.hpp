// A raster MBTiles file (https://github.com/mapbox/mbtiles-spec, 1.3) for `uavcover serve --tiles`: the
// map's tiles without internet (docs/offline-maps.md). Read with SQLite, read-only, through a bounded
// pool of connections, each with its one prepared, parameterised statement.
#pragma once

#include <array>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace uavcover::io {

/// What the file's `metadata` table says (and, where it is silent, the `tiles` table).
struct TileSetInfo {
  std::string name;
  std::string format;      ///< "png", "jpg" or "webp" ("jpeg" is read as "jpg")
  std::string media_type;  ///< "image/png", "image/jpeg", "image/webp"
  std::string description;
  std::string attribution;
  int minzoom = 0;
  int maxzoom = 0;
  /// west, south, east, north in degrees (WGS84), when the metadata has them
  std::optional<std::array<double, 4>> bounds;
  /// longitude, latitude, zoom, when the metadata has them
  std::optional<std::array<double, 3>> center;
};

/// The media type of a raster tile format ("png" -> "image/png"); empty for other formats.
std::string tile_media_type(const std::string& format);

class MbTiles {
 public:
  /// Opens `file` read-only and checks it: an SQLite database with the tables metadata(name, value)
  /// and tiles(zoom_level, tile_column, tile_row, tile_data), a raster format (metadata "format" png,
  /// jpg or webp; the first tile's bytes tell when they are one of these, as GDAL 3.6 writes "png" for
  /// WebP tiles), zoom levels in 0..30. InputError naming
  /// `field` otherwise. At most `max_connections` (at least 1) readers run at once; more wait.
  static std::shared_ptr<MbTiles> open(const std::filesystem::path& file,
                                       const std::string& field = "--tiles", std::size_t max_connections = 4);
  ~MbTiles();
  MbTiles(const MbTiles&) = delete;
  MbTiles& operator=(const MbTiles&) = delete;

  [[nodiscard]] const TileSetInfo& info() const { return info_; }
  [[nodiscard]] const std::filesystem::path& file() const { return file_; }

  /// The bytes of the tile at zoom `z`, column `x` and row `y` counted from the north (XYZ, as web
  /// maps ask; the file counts rows from the south, TMS: row = 2^z - 1 - y); nullopt when the file has
  /// no such tile or z, x, y are out of range. Thread-safe. OperationError when SQLite fails.
  [[nodiscard]] std::optional<std::string> tile(int z, std::int64_t x, std::int64_t y) const;

  struct Connection;

 private:
  MbTiles(std::filesystem::path file, std::size_t max_connections);
  std::unique_ptr<Connection> acquire() const;
  void release(std::unique_ptr<Connection> c) const;

  std::filesystem::path file_;
  TileSetInfo info_;
  std::size_t max_connections_;
  mutable std::mutex mutex_;
  mutable std::condition_variable freed_;
  mutable std::vector<std::unique_ptr<Connection>> idle_;
  mutable std::size_t open_ = 0;  ///< connections in use or idle
};

}  // namespace uavcover::io
