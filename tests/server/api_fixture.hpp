// A real store (a fresh SQLite file; a fresh PostgreSQL database too when the throwaway cluster runs),
// the API router over it, and requests dispatched the way the transport does (404 / 405 with Allow),
// without a network.
#pragma once

#include <gtest/gtest.h>

#include <unistd.h>
#include <atomic>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "server/api.hpp"
#include "server/exports.hpp"
#include "server/flights.hpp"
#include "server/http.hpp"
#include "store/store.hpp"
#include "store/test_backends.hpp"
#include "support/files.hpp"

namespace uavcover::server::testing {

inline std::filesystem::path fresh_dir(const std::string& tag) {
  static std::atomic<int> counter{0};
  const auto dir =
      std::filesystem::temp_directory_path() /
      ("uavcover-server-" + tag + "-" + std::to_string(getpid()) + "-" + std::to_string(counter++));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::string olive_grove() {
  return uavcover::testing::slurp(std::filesystem::path(UAVCOVER_SOURCE_DIR) / "examples" /
                                  "olive-grove.json");
}

struct Answer {
  int status = 0;
  std::string content_type;
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;
  [[nodiscard]] nlohmann::json json() const { return nlohmann::json::parse(body); }
  [[nodiscard]] std::string header(const std::string& name) const {
    for (const auto& [k, v] : headers)
      if (k == name) return v;
    return {};
  }
  [[nodiscard]] std::string error_field() const { return json().at("error").at("field").get<std::string>(); }
};

class ApiTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    dir_ = fresh_dir("api");
    const std::string& param = GetParam();
    if (param.starts_with(uavcover::testing::kPgUrlFile) &&
        !std::filesystem::exists(param.substr(uavcover::testing::kPgUrlFile.size())))
      GTEST_SKIP() << "no PostgreSQL test server (run through ctest, or scripts/pg-test-cluster start DIR)";
    open();
  }
  void TearDown() override {
    close();
    std::filesystem::remove_all(dir_);
  }

  /// A fresh store of the test's backend with the router over it.
  void open(int max_queued = 100) {
    url_ = uavcover::testing::fresh_store_url(GetParam());
    store_ = uavcover::testing::open_test_store(url_);
    FlightLimits limits;
    limits.flush_period = std::chrono::milliseconds(50);
    limits.max_live = 4;
    flights_ = std::make_unique<FlightManager>(*store_, limits);
    flights_->start();
    exports_ = std::make_unique<ExportService>(*store_, export_config_);
    ctx_ = std::make_unique<ApiContext>(ApiContext{*store_, ApiConfig{}, flights_.get(), exports_.get()});
    ctx_->config.max_queued = max_queued;
    router_ = std::make_unique<Router>();
    add_api_routes(*router_, *ctx_);
  }
  void close() {
    router_.reset();
    ctx_.reset();
    exports_.reset();
    flights_.reset();
    store_.reset();
    if (!url_.empty()) uavcover::testing::remove_test_store(url_);
    url_.clear();
  }

  /// Dispatches like the transport: the target is decoded by the transport's decode_target().
  Answer call(const std::string& method, const std::string& target, const std::string& body = "",
              std::map<std::string, std::string> headers = {}) {
    Request req;
    req.method = method;
    req.request_id = "test";
    decode_target(target, req);
    if (!body.empty() && !headers.contains("content-type")) headers["content-type"] = "application/json";
    req.headers = std::move(headers);
    req.body = body;
    const auto m = router_->match(method, req.path);
    Response r;
    if (m.handler) {
      req.params = m.params;
      r = (*m.handler)(req);
    } else if (!m.allowed.empty()) {
      r = Response::error(405, "", "method not allowed");
      std::string allow;
      for (const auto& a : m.allowed) allow += (allow.empty() ? "" : ", ") + a;
      r.headers.emplace_back("Allow", allow);
    } else {
      r = Response::error(404, "", "no such route");
    }
    return Answer{r.status, r.content_type, r.body, r.headers};
  }

  /// Stores the mission and returns its id.
  store::Id create_mission(const std::string& doc) {
    const Answer a = call("POST", "/api/v1/missions", doc);
    EXPECT_EQ(a.status, 201) << a.body;
    return a.json().at("id").get<store::Id>();
  }

  std::filesystem::path dir_;  ///< scratch files
  std::string url_;
  std::unique_ptr<store::Store> store_;
  std::unique_ptr<FlightManager> flights_;
  ExportConfig export_config_;  ///< the next open()'s export service
  std::unique_ptr<ExportService> exports_;
  std::unique_ptr<ApiContext> ctx_;
  std::unique_ptr<Router> router_;
};

/// "sqlite" or "postgresql", for the test names.
inline std::string backend_name(const ::testing::TestParamInfo<std::string>& info) {
  return info.param.starts_with("sqlite") ? "sqlite" : "postgresql";
}

}  // namespace uavcover::server::testing
