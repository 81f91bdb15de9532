// multipart/form-data bodies for the upload routes' tests (the importer's file, the photos' heads).
#pragma once

#include <map>
#include <string>

namespace uavcover::server::testing {

inline const std::string kBoundary = "----uavcoverTest7MA4YWxk";

inline std::string part(const std::string& name, const std::string& filename, const std::string& body) {
  std::string h = "--" + kBoundary + "\r\nContent-Disposition: form-data; name=\"" + name + "\"";
  if (!filename.empty()) h += "; filename=\"" + filename + "\"";
  return h + "\r\nContent-Type: application/octet-stream\r\n\r\n" + body + "\r\n";
}
inline std::string form(const std::string& parts) { return parts + "--" + kBoundary + "--\r\n"; }
inline const std::map<std::string, std::string> kHeaders = {
    {"content-type", "multipart/form-data; boundary=" + kBoundary}};

}  // namespace uavcover::server::testing
