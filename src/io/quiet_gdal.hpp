// Internal to src/io/'s GDAL readers (the DEM reader, the vector importer): GDAL's messages go to a quiet
// handler (not stderr) while a file is read, the last one explains a refusal, and one thread-local
// configuration option holds for the read.
#pragma once

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal.h>

#include <mutex>
#include <string>

namespace uavcover::io::detail {

class QuietGdal {
 public:
  /// `option` = `value` (GDAL's CPLSetThreadLocalConfigOption) until this goes out of scope.
  QuietGdal(const char* option, const char* value) : option_(option) {
    static std::once_flag once;
    std::call_once(once, [] { GDALAllRegister(); });
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
    CPLSetThreadLocalConfigOption(option_, value);
  }
  ~QuietGdal() {
    CPLSetThreadLocalConfigOption(option_, nullptr);
    CPLPopErrorHandler();
  }
  QuietGdal(const QuietGdal&) = delete;
  QuietGdal& operator=(const QuietGdal&) = delete;
  /// GDAL's last message (300 characters at most), or "no reason given".
  static std::string last() {
    const char* m = CPLGetLastErrorMsg();
    return m != nullptr && *m != '\0' ? std::string(m).substr(0, 300) : "no reason given";
  }

 private:
  const char* option_;
};

}  // namespace uavcover::io::detail
