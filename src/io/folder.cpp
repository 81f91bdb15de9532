#include "io/folder.hpp"

#include <algorithm>
#include <system_error>

#include "uavcover/error.hpp"

namespace uavcover::io {

std::vector<std::filesystem::path> list_json_files(const std::filesystem::path& dir,
                                                   const std::string& field) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    throw InputError(field, "\"" + dir.string() + "\" is not a folder");
  std::vector<std::filesystem::path> files;
  std::filesystem::directory_iterator it(dir, ec), end;
  if (ec) throw InputError(field, "cannot read the folder \"" + dir.string() + "\": " + ec.message());
  for (; it != end; it.increment(ec)) {
    if (ec) throw InputError(field, "cannot read the folder \"" + dir.string() + "\": " + ec.message());
    std::error_code type_ec;
    if (it->path().extension() == ".json" && it->is_regular_file(type_ec)) files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace uavcover::io
