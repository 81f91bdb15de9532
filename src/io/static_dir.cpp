#include "io/static_dir.hpp"

#include <algorithm>
#include <map>
#include <system_error>

#include "io/plan_io.hpp"
#include "uavcover/error.hpp"

namespace uavcover::io {

namespace {
constexpr std::size_t kMaxFiles = 10000;
}

std::string static_media_type(const std::filesystem::path& file) {
  static const std::map<std::string, std::string> types{
      {".html", "text/html; charset=utf-8"},
      {".htm", "text/html; charset=utf-8"},
      {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},
      {".json", "application/json"},
      {".map", "application/json"},
      {".svg", "image/svg+xml"},
      {".png", "image/png"},
      {".jpg", "image/jpeg"},
      {".jpeg", "image/jpeg"},
      {".webp", "image/webp"},
      {".ico", "image/x-icon"},
      {".woff2", "font/woff2"},
      {".woff", "font/woff"},
      {".txt", "text/plain; charset=utf-8"},
      {".wasm", "application/wasm"},
  };
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const auto it = types.find(ext);
  return it == types.end() ? std::string() : it->second;
}

Artifacts read_static_dir(const std::filesystem::path& dir, std::size_t max_total_bytes) {
  namespace fs = std::filesystem;
  const std::string field = "--static";
  std::error_code ec;
  const auto st = fs::symlink_status(dir, ec);
  if (ec || !fs::is_directory(st)) throw InputError(field, "'" + dir.string() + "' is not a folder");
  Artifacts out;
  std::size_t total = 0;
  fs::recursive_directory_iterator it(dir, fs::directory_options::none, ec);
  if (ec) throw InputError(field, "cannot read folder '" + dir.string() + "': " + ec.message());
  for (; it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (ec) throw InputError(field, "cannot read folder '" + dir.string() + "': " + ec.message());
    const fs::path& p = it->path();
    const std::string name = p.filename().string();
    const auto status = it->symlink_status(ec);
    if (ec) continue;
    if (!name.empty() && name.front() == '.') {
      if (fs::is_directory(status)) it.disable_recursion_pending();
      continue;
    }
    if (fs::is_symlink(status) || !fs::is_regular_file(status)) continue;  // links are never followed
    const std::string type = static_media_type(p);
    if (type.empty()) continue;
    if (out.size() >= kMaxFiles)
      throw InputError(field,
                       "'" + dir.string() + "' holds more than " + std::to_string(kMaxFiles) + " files");
    const std::size_t left = max_total_bytes - total;
    std::string bytes;
    try {
      bytes = read_text_file(p, field, left);
    } catch (const InputError&) {
      if (fs::file_size(p, ec) > left || ec)
        throw InputError(field, "the files in '" + dir.string() + "' are larger than " +
                                    std::to_string(max_total_bytes) + " bytes together");
      throw;
    }
    total += bytes.size();
    out.push_back(Artifact{fs::relative(p, dir).generic_string(), type, std::move(bytes)});
  }
  std::sort(out.begin(), out.end(), [](const Artifact& a, const Artifact& b) { return a.name < b.name; });
  return out;
}

}  // namespace uavcover::io
