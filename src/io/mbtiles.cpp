#include "io/mbtiles.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <system_error>

#include "uavcover/error.hpp"

namespace uavcover::io {

namespace {

constexpr int kMaxZoom = 30;
constexpr int kBusyTimeoutMs = 2000;
constexpr const char* kTileQuery =
    "SELECT tile_data FROM tiles WHERE zoom_level = ?1 AND tile_column = ?2 AND tile_row = ?3";

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

/// "a,b,c" as exactly `n` finite numbers; nullopt when malformed.
template <std::size_t N>
std::optional<std::array<double, N>> numbers(const std::string& text) {
  std::array<double, N> out{};
  std::size_t pos = 0;
  for (std::size_t i = 0; i < N; ++i) {
    const auto comma = i + 1 < N ? text.find(',', pos) : text.size();
    if (comma == std::string::npos) return std::nullopt;
    const std::string part = trim(text.substr(pos, comma - pos));
    const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), out[i]);
    if (ec != std::errc() || end != part.data() + part.size() || part.empty() || !std::isfinite(out[i]))
      return std::nullopt;
    pos = comma + 1;
  }
  return out;
}

std::optional<int> integer(const std::string& text) {
  const std::string t = trim(text);
  int v = 0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || ec != std::errc() || end != t.data() + t.size()) return std::nullopt;
  return v;
}

/// The raster format of a tile's bytes by its magic number; empty when none of png, jpg, webp.
std::string sniff(const std::string& bytes) {
  if (bytes.rfind("\x89PNG\r\n\x1a\n", 0) == 0) return "png";
  if (bytes.size() >= 3 && static_cast<unsigned char>(bytes[0]) == 0xFF &&
      static_cast<unsigned char>(bytes[1]) == 0xD8 && static_cast<unsigned char>(bytes[2]) == 0xFF)
    return "jpg";
  if (bytes.size() >= 12 && bytes.compare(0, 4, "RIFF") == 0 && bytes.compare(8, 4, "WEBP") == 0)
    return "webp";
  return "";
}

std::string column_text(sqlite3_stmt* s, int col) {
  const auto* p = sqlite3_column_text(s, col);
  return p == nullptr ? std::string()
                      : std::string(reinterpret_cast<const char*>(p),
                                    static_cast<std::size_t>(sqlite3_column_bytes(s, col)));
}

std::string column_blob(sqlite3_stmt* s, int col) {
  const void* p = sqlite3_column_blob(s, col);
  const int n = sqlite3_column_bytes(s, col);
  return p == nullptr || n <= 0 ? std::string()
                                : std::string(static_cast<const char*>(p), static_cast<std::size_t>(n));
}

/// One statement run to its end at open time.
struct Statement {
  Statement(sqlite3* db, const char* sql) { rc = sqlite3_prepare_v2(db, sql, -1, &stmt, nullptr); }
  ~Statement() { sqlite3_finalize(stmt); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  sqlite3_stmt* stmt = nullptr;
  int rc = SQLITE_OK;
};

}  // namespace

std::string tile_media_type(const std::string& format) {
  if (format == "png") return "image/png";
  if (format == "jpg") return "image/jpeg";
  if (format == "webp") return "image/webp";
  return "";
}

/// A read-only connection and its prepared tile query; used by one thread at a time.
struct MbTiles::Connection {
  sqlite3* db = nullptr;
  sqlite3_stmt* tile = nullptr;
  Connection() = default;
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;
  ~Connection() {
    sqlite3_finalize(tile);
    sqlite3_close(db);
  }
  [[nodiscard]] std::string error() const { return db == nullptr ? "out of memory" : sqlite3_errmsg(db); }

  /// Opens `file` read-only; the error message (empty on success) otherwise.
  std::string open(const std::filesystem::path& file) {
    const int rc = sqlite3_open_v2(file.c_str(), &db, SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX, nullptr);
    if (rc != SQLITE_OK) return error();
    sqlite3_busy_timeout(db, kBusyTimeoutMs);
    if (sqlite3_prepare_v2(db, kTileQuery, -1, &tile, nullptr) != SQLITE_OK) return error();
    return "";
  }
};

MbTiles::MbTiles(std::filesystem::path file, std::size_t max_connections)
    : file_(std::move(file)), max_connections_(std::max<std::size_t>(1, max_connections)) {}

MbTiles::~MbTiles() = default;

std::shared_ptr<MbTiles> MbTiles::open(const std::filesystem::path& file, const std::string& field,
                                       std::size_t max_connections) {
  namespace fs = std::filesystem;
  const std::string name = "'" + file.string() + "'";
  std::error_code ec;
  const auto st = fs::status(file, ec);
  if (ec || !fs::exists(st)) throw InputError(field, name + " does not exist");
  if (!fs::is_regular_file(st)) throw InputError(field, name + " is not a file");
  std::shared_ptr<MbTiles> out(new MbTiles(file, max_connections));
  auto first = std::make_unique<Connection>();
  if (const std::string e = first->open(file); !e.empty()) {
    const std::string why = lower(e);
    if (why.find("not a database") != std::string::npos)
      throw InputError(field, name + " is not an MBTiles file (not an SQLite database)");
    if (why.find("no such table") != std::string::npos || why.find("no such column") != std::string::npos)
      throw InputError(field, name +
                                  " is not an MBTiles file: it has no table tiles(zoom_level, tile_column, "
                                  "tile_row, tile_data) (" +
                                  e + ")");
    throw InputError(field, "cannot open " + name + ": " + e);
  }
  sqlite3* db = first->db;
  std::map<std::string, std::string> meta;
  {
    Statement s(db, "SELECT name, value FROM metadata");
    if (s.rc != SQLITE_OK)
      throw InputError(field, name + " is not an MBTiles file: it has no table metadata(name, value) (" +
                                  std::string(sqlite3_errmsg(db)) + ")");
    int rc = SQLITE_ROW;
    while ((rc = sqlite3_step(s.stmt)) == SQLITE_ROW)
      meta[lower(trim(column_text(s.stmt, 0)))] = column_text(s.stmt, 1);
    if (rc != SQLITE_DONE)
      throw InputError(field, "cannot read the metadata of " + name + ": " + sqlite3_errmsg(db));
  }
  std::string first_tile;
  {
    Statement s(db, "SELECT tile_data FROM tiles LIMIT 1");
    const int rc = s.rc == SQLITE_OK ? sqlite3_step(s.stmt) : s.rc;
    if (rc == SQLITE_DONE) throw InputError(field, name + " holds no tiles");
    if (rc != SQLITE_ROW)
      throw InputError(field, "cannot read the tiles of " + name + ": " + sqlite3_errmsg(db));
    first_tile = column_blob(s.stmt, 0);
  }
  TileSetInfo& info = out->info_;
  info.name = meta.count("name") ? meta["name"] : file.stem().string();
  info.description = meta["description"];
  info.attribution = meta["attribution"];
  std::string format = lower(trim(meta["format"]));
  if (format == "jpeg") format = "jpg";
  if (format.empty()) format = sniff(first_tile);
  if (format.empty())
    throw InputError(field, name + " has no metadata 'format' and its tiles are not png, jpg or webp");
  if (tile_media_type(format).empty())
    throw InputError(field, name + " holds tiles of format '" + format.substr(0, 40) +
                                "', not a raster format (png, jpg or webp): vector tiles are not served");
  // the bytes have the last word among the raster formats (GDAL 3.6 writes "png" for WebP tiles), so
  // that Content-Type is right
  if (const std::string bytes_say = sniff(first_tile); !bytes_say.empty()) format = bytes_say;
  info.format = format;
  info.media_type = tile_media_type(format);
  auto minzoom = meta.count("minzoom") ? integer(meta["minzoom"]) : std::nullopt;
  auto maxzoom = meta.count("maxzoom") ? integer(meta["maxzoom"]) : std::nullopt;
  if (!minzoom || !maxzoom) {
    Statement s(db, "SELECT min(zoom_level), max(zoom_level) FROM tiles");
    if (s.rc != SQLITE_OK || sqlite3_step(s.stmt) != SQLITE_ROW)
      throw InputError(field, "cannot read the zoom levels of " + name + ": " + sqlite3_errmsg(db));
    if (!minzoom) minzoom = sqlite3_column_int(s.stmt, 0);
    if (!maxzoom) maxzoom = sqlite3_column_int(s.stmt, 1);
  }
  if (*minzoom < 0 || *maxzoom > kMaxZoom || *minzoom > *maxzoom)
    throw InputError(field, name + " has zoom levels " + std::to_string(*minzoom) + ".." +
                                std::to_string(*maxzoom) + "; they must lie in 0.." +
                                std::to_string(kMaxZoom));
  info.minzoom = *minzoom;
  info.maxzoom = *maxzoom;
  if (const auto b = numbers<4>(meta["bounds"]); b && (*b)[0] >= -180 && (*b)[2] <= 180 && (*b)[1] >= -90 &&
                                                 (*b)[3] <= 90 && (*b)[0] < (*b)[2] && (*b)[1] < (*b)[3])
    info.bounds = b;
  if (const auto c = numbers<3>(meta["center"]); c && std::abs((*c)[0]) <= 180 && std::abs((*c)[1]) <= 90)
    info.center = c;
  out->idle_.push_back(std::move(first));
  out->open_ = 1;
  return out;
}

std::unique_ptr<MbTiles::Connection> MbTiles::acquire() const {
  {
    std::unique_lock lock(mutex_);
    freed_.wait(lock, [this] { return !idle_.empty() || open_ < max_connections_; });
    if (!idle_.empty()) {
      auto c = std::move(idle_.back());
      idle_.pop_back();
      return c;
    }
    ++open_;
  }
  auto c = std::make_unique<Connection>();
  if (const std::string e = c->open(file_); !e.empty()) {
    {
      const std::lock_guard lock(mutex_);
      --open_;
    }
    freed_.notify_one();
    throw OperationError("cannot open the tiles '" + file_.string() + "': " + e);
  }
  return c;
}

void MbTiles::release(std::unique_ptr<Connection> c) const {
  {
    const std::lock_guard lock(mutex_);
    if (c)
      idle_.push_back(std::move(c));
    else
      --open_;
  }
  freed_.notify_one();
}

std::optional<std::string> MbTiles::tile(int z, std::int64_t x, std::int64_t y) const {
  if (z < 0 || z > kMaxZoom) return std::nullopt;
  const std::int64_t n = std::int64_t{1} << z;
  if (x < 0 || y < 0 || x >= n || y >= n) return std::nullopt;
  auto c = acquire();
  sqlite3_stmt* s = c->tile;
  sqlite3_bind_int(s, 1, z);
  sqlite3_bind_int64(s, 2, x);
  sqlite3_bind_int64(s, 3, n - 1 - y);  // TMS rows count from the south
  const int rc = sqlite3_step(s);
  std::optional<std::string> out;
  std::string error;
  try {
    if (rc == SQLITE_ROW)
      out = column_blob(s, 0);
    else if (rc != SQLITE_DONE)
      error = c->error();
  } catch (...) {
    sqlite3_reset(s);
    release(std::move(c));
    throw;
  }
  sqlite3_reset(s);
  sqlite3_clear_bindings(s);
  release(std::move(c));
  if (!error.empty()) throw OperationError("cannot read a tile of '" + file_.string() + "': " + error);
  return out;
}

}  // namespace uavcover::io
