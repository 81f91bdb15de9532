// `uavcover serve`: the CLI (src/cli/serve_cmd.cpp) fills ServeOptions; serve() (src/server/app.cpp,
// the API side) opens the store, builds the API router, starts the planning workers, and runs an
// HttpServer until options.http.stop is requested (SIGINT/SIGTERM through the CLI's interrupt handler).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "server/server.hpp"

namespace uavcover::server {

struct ServeOptions {
  ServerConfig http;
  std::string db_url = "sqlite:data/uavcover.db";
  int workers = 1;
  std::optional<std::filesystem::path> seed_dir;
  int max_queued = 100;
};

/// Blocks until options.http.stop is requested (HttpServer::run() returns then; workers should stop
/// too). Throws InputError / OperationError.
void serve(const ServeOptions& options);

}  // namespace uavcover::server
