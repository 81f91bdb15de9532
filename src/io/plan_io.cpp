#include "io/plan_io.hpp"
#include "io/write_artifacts.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmath>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <system_error>

#include "codec/plan_codec.hpp"
#include "engine/test_hold.hpp"
#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "json/strict.hpp"
#include "mission/mission_json.hpp"
#include "photo/photo.hpp"
#include "sorties/sorties.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover::io {

using nlohmann::json;

namespace {

json parse_file(const std::filesystem::path& p, const std::string& field) {
  return strict::parse_json(read_text_file(p, field), field);
}

std::atomic<std::size_t> g_max_input_bytes{0};  // 0: not set, use the environment or the default

std::string mib(std::size_t bytes) {
  return bytes % (std::size_t{1} << 20) == 0 ? std::to_string(bytes >> 20) + " MiB"
                                             : std::to_string(bytes) + " bytes";
}

// Why a file of this kind is not read ("" for a regular file).
std::string kind_problem(const struct stat& st, const std::string& name) {
  if (S_ISREG(st.st_mode)) return "";
  if (S_ISDIR(st.st_mode)) return name + " is a folder, not a file";
  return name + " is not a regular file (a device, a pipe or a socket); give a file";
}

}  // namespace

std::size_t max_input_bytes() {
  if (const std::size_t set = g_max_input_bytes.load()) return set;
  const char* env = std::getenv("UAVCOVER_MAX_INPUT_MB");
  if (env == nullptr || *env == '\0') return kDefaultMaxInputBytes;
  const std::string_view v(env);
  unsigned long mb = 0;
  const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), mb);
  if (ec != std::errc() || end != v.data() + v.size() || mb < 1 || mb > 4096)
    throw InputError("UAVCOVER_MAX_INPUT_MB",
                     "must be a whole number of MiB in 1..4096, got '" + std::string(v.substr(0, 40)) + "'");
  return static_cast<std::size_t>(mb) << 20;
}

void set_max_input_bytes(std::size_t bytes) { g_max_input_bytes.store(bytes); }

std::string read_text_file(const std::filesystem::path& path, const std::string& field) {
  return read_text_file(path, field, max_input_bytes());
}

std::string read_text_file(const std::filesystem::path& path, const std::string& field,
                           std::size_t max_bytes) {
  const std::string name = "'" + path.string() + "'";
  struct stat st {};
  // folders and devices are refused before they are opened (opening a pipe or a device can block)
  if (::stat(path.c_str(), &st) != 0)
    throw InputError(field, "cannot read file " + name + ": " + std::strerror(errno));
  if (const std::string why = kind_problem(st, name); !why.empty()) throw InputError(field, why);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) throw InputError(field, "cannot read file " + name + ": " + std::strerror(errno));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  if (::fstat(fd, &st) != 0) throw OperationError("cannot read file " + name + ": " + std::strerror(errno));
  // what was opened may differ from what was checked (the path was replaced in between)
  if (const std::string why = kind_problem(st, name); !why.empty()) throw InputError(field, why);
  auto too_large = [&] {
    return InputError(
        field, name + " is larger than the input limit of " + mib(max_bytes) + " (see docs/limits.md)");
  };
  if (static_cast<std::uintmax_t>(st.st_size) > max_bytes) throw too_large();
  // read at most max_bytes + 1 bytes, whatever the size said (files that grow, /proc files)
  std::string text(std::min<std::size_t>(static_cast<std::size_t>(st.st_size), max_bytes) + 1, '\0');
  std::size_t got = 0;
  for (;;) {
    if (got == text.size()) {
      if (got > max_bytes) throw too_large();
      text.resize(std::min(max_bytes + 1, std::max<std::size_t>(got * 2, 4096)));
    }
    const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw OperationError("cannot read file " + name + ": " + std::strerror(errno));
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  if (got > max_bytes) throw too_large();
  text.resize(got);
  return text;
}

void write_file_atomic(const std::filesystem::path& path, const std::string& content) {
  std::error_code mkdir_ec;
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), mkdir_ec);
  if (mkdir_ec) throw OperationError("cannot create the folder " + path.parent_path().string());
  const std::filesystem::path tmp = path.string() + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw OperationError("cannot write " + tmp.string());
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) throw OperationError("cannot write " + tmp.string());
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw OperationError("cannot write " + path.string());
  }
}

namespace {

std::filesystem::path checked_relative(const std::string& name) {
  const std::filesystem::path rel(name);
  bool ok = !name.empty() && rel.is_relative() && name.find('\\') == std::string::npos;
  for (const auto& part : rel) ok = ok && !part.empty() && part != "." && part != "..";
  if (!ok) throw OperationError("refusing to write an output named \"" + name + "\"");
  return rel;
}

}  // namespace

namespace {

std::vector<std::filesystem::path> write_staged(const std::filesystem::path& dir_in,
                                                const Artifacts& artifacts, const Context* ctx) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path dir = dir_in.lexically_normal();
  if (!dir.has_filename() && dir.has_relative_path()) dir = dir.parent_path();  // "a/b/" -> "a/b"
  if (dir.empty()) dir = ".";
  const bool fresh = !fs::exists(dir, ec);
  if (fresh) {
    if (dir.has_parent_path()) fs::create_directories(dir.parent_path(), ec);
    if (ec) throw OperationError("cannot create the folder " + dir.parent_path().string());
  } else if (!fs::is_directory(dir, ec)) {
    throw OperationError("cannot create the folder " + dir.string());
  }
  const std::string tag = ".staging-" + std::to_string(::getpid());
  // a fresh folder is staged beside itself and renamed into place whole; an existing one inside
  const fs::path staging = fresh ? dir.parent_path() / ("." + dir.filename().string() + tag) : dir / tag;
  fs::remove_all(staging, ec);
  auto stopped = [ctx] { return ctx != nullptr && ctx->stop_requested(); };
  std::vector<fs::path> written;
  try {
    fs::create_directories(staging);
    for (const auto& a : artifacts) {
      if (stopped()) throw Cancelled();
      const fs::path rel = checked_relative(a.name);
      const fs::path tmp = staging / rel;
      fs::create_directories(tmp.parent_path());
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      out.write(a.bytes.data(), static_cast<std::streamsize>(a.bytes.size()));
      out.flush();
      if (!out) throw OperationError("cannot write " + (dir / rel).string());
    }
    if (ctx != nullptr) engine::test_hold(*ctx, "storing", "");
    if (stopped()) throw Cancelled();
    // past this point the outputs are committed: a stop no longer undoes them
    if (fresh) {
      fs::rename(staging, dir);
      for (const auto& a : artifacts) written.push_back(dir / checked_relative(a.name));
      return written;
    }
    for (const auto& a : artifacts) {
      const fs::path rel = checked_relative(a.name);
      fs::create_directories((dir / rel).parent_path());
      fs::rename(staging / rel, dir / rel);
      written.push_back(dir / rel);
    }
  } catch (const fs::filesystem_error& e) {
    fs::remove_all(staging, ec);
    throw OperationError(std::string("cannot write the outputs: ") + e.what());
  } catch (...) {
    fs::remove_all(staging, ec);
    throw;
  }
  fs::remove_all(staging, ec);
  return written;
}

}  // namespace

std::vector<std::filesystem::path> write_artifacts(const std::filesystem::path& dir,
                                                   const Artifacts& artifacts) {
  return write_staged(dir, artifacts, nullptr);
}

std::vector<std::filesystem::path> write_artifacts(const std::filesystem::path& dir,
                                                   const Artifacts& artifacts, const Context& ctx) {
  return write_staged(dir, artifacts, &ctx);
}

Plan load_plan_dir(const std::filesystem::path& dir) {
  const auto plan_path = dir / "plan.json";
  const auto paths_path = dir / "paths.geojson";
  if (!std::filesystem::is_directory(dir))
    throw InputError("PLAN_DIR",
                     "no plan folder at " + dir.string() + " (expected plan.json and paths.geojson)");
  if (!std::filesystem::exists(plan_path)) throw InputError("PLAN_DIR", "no plan.json in " + dir.string());
  if (!std::filesystem::exists(paths_path))
    throw InputError("PLAN_DIR", "no paths.geojson in " + dir.string());
  return codec::load_plan(parse_file(plan_path, "plan.json"), parse_file(paths_path, "paths.geojson"));
}

}  // namespace uavcover::io
