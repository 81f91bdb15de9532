#include "export/zip.hpp"

#include <zip.h>

#include <memory>

#include "uavcover/error.hpp"

namespace uavcover::exporting {

namespace {

constexpr time_t kEntryTime = 946684800;  // 2000-01-01T00:00:00Z: reproducible archives

struct SourceFree {
  void operator()(zip_source_t* s) const { zip_source_free(s); }
};

[[noreturn]] void fail(const std::string& what, zip_error_t* err) {
  const std::string msg = err != nullptr ? zip_error_strerror(err) : "unknown error";
  throw OperationError("zip archive: " + what + ": " + msg);
}

}  // namespace

std::string zip_bytes(const std::map<std::string, std::string>& entries) {
  zip_error_t err;
  zip_error_init(&err);
  std::unique_ptr<zip_source_t, SourceFree> src(zip_source_buffer_create(nullptr, 0, 0, &err));
  if (!src) fail("cannot create a buffer", &err);
  zip_t* za = zip_open_from_source(src.get(), ZIP_TRUNCATE, &err);
  if (za == nullptr) fail("cannot open the buffer", &err);
  zip_source_keep(src.get());  // the archive releases its reference on close; we read the buffer after
  for (const auto& [name, data] : entries) {
    zip_source_t* entry = zip_source_buffer(za, data.data(), data.size(), 0);
    const zip_int64_t idx =
        entry == nullptr ? -1 : zip_file_add(za, name.c_str(), entry, ZIP_FL_OVERWRITE | ZIP_FL_ENC_UTF_8);
    if (idx < 0 || zip_file_set_mtime(za, static_cast<zip_uint64_t>(idx), kEntryTime, 0) < 0) {
      if (entry != nullptr && idx < 0) zip_source_free(entry);
      const std::string msg = zip_strerror(za);
      zip_discard(za);
      throw OperationError("zip archive: cannot add '" + name + "': " + msg);
    }
  }
  if (zip_close(za) < 0) {
    const std::string msg = zip_strerror(za);
    zip_discard(za);
    throw OperationError("zip archive: cannot finish: " + msg);
  }
  // read the finished archive back out of the buffer source
  zip_stat_t st;
  zip_stat_init(&st);
  if (zip_source_stat(src.get(), &st) < 0 || (st.valid & ZIP_STAT_SIZE) == 0)
    fail("cannot size the buffer", zip_source_error(src.get()));
  if (zip_source_open(src.get()) < 0) fail("cannot read the buffer", zip_source_error(src.get()));
  std::string out(static_cast<std::size_t>(st.size), '\0');
  const zip_int64_t n = zip_source_read(src.get(), out.data(), st.size);
  zip_source_close(src.get());
  if (n < 0 || static_cast<zip_uint64_t>(n) != st.size) fail("short read", zip_source_error(src.get()));
  return out;
}

}  // namespace uavcover::exporting
