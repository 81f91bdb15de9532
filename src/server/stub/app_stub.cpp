// Stand-in for server::serve() while src/server/app.cpp (the API side) does not exist; the top
// CMakeLists.txt compiles it only then.
#include "server/app.hpp"
#include "uavcover/error.hpp"

namespace uavcover::server {

void serve(const ServeOptions&) {
  throw OperationError("this build has no API (src/server/app.cpp is missing)");
}

}  // namespace uavcover::server
