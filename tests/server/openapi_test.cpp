// The embedded OpenAPI document parses, is OpenAPI 3.0.3 and describes exactly the routes registered.
#include <algorithm>
#include <set>

#include "json/strict.hpp"
#include "server/api_fixture.hpp"
#include "usecases/plan_outputs.hpp"

namespace uavcover::server::testing {
namespace {

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

TEST_P(ApiTest, OpenApiDocumentDescribesEveryRoute) {
  const Answer a = call("GET", "/api/v1/openapi.json");
  ASSERT_EQ(a.status, 200);
  EXPECT_EQ(a.content_type, "application/json");
  const nlohmann::json doc = strict::parse_json(a.body, "openapi.json");
  EXPECT_EQ(doc.at("openapi"), "3.0.3");
  const auto& paths = doc.at("paths");
  const auto& schemas = doc.at("components").at("schemas");
  for (const char* s : {"Error", "Mission", "MissionSummary", "Job", "CatalogUav", "CatalogCamera"})
    EXPECT_TRUE(schemas.contains(s)) << s;

  std::set<std::pair<std::string, std::string>> registered;
  for (const auto& [method, pattern] : router_->routes()) {
    registered.emplace(lower(method), pattern);
    ASSERT_TRUE(paths.contains(pattern)) << pattern << " is not documented";
    ASSERT_TRUE(paths[pattern].contains(lower(method))) << method << " " << pattern << " is not documented";
    const auto& op = paths[pattern][lower(method)];
    EXPECT_TRUE(op.at("responses").is_object());
    EXPECT_FALSE(op.at("responses").empty());
    bool has_success = false;
    for (const auto& [code, response] : op["responses"].items()) {
      has_success = has_success || code.front() == '2';
      EXPECT_TRUE(response.contains("description")) << method << " " << pattern << " " << code;
    }
    EXPECT_TRUE(has_success) << method << " " << pattern;
    // the transport's own answers, before any route: a foreign Origin or Host
    if (pattern != "/api/v1/events") {
      EXPECT_TRUE(op["responses"].contains("403")) << method << " " << pattern << ": no 403 (foreign Origin)";
      EXPECT_TRUE(op["responses"].contains("421")) << method << " " << pattern << ": no 421 (foreign Host)";
    }
    // HEAD is served for every GET route (the GET's headers, no body): documented beside it
    if (method == "GET" && pattern != "/api/v1/events") {
      EXPECT_TRUE(paths[pattern].contains("head")) << "HEAD " << pattern << " is not documented";
    }
  }
  // and nothing documented under /api/v1 that is not served (the transport serves the events)
  for (const auto& [pattern, item] : paths.items()) {
    if (!pattern.starts_with("/api/v1/") || pattern == "/api/v1/events") continue;
    for (const auto& [method, op] : item.items())
      if (method != "parameters") {
        // HEAD is the transport's, served wherever GET is
        const std::string served = method == "head" ? std::string("get") : method;
        EXPECT_TRUE(registered.contains({served, pattern})) << method << " " << pattern << " is not served";
      }
  }
  // every $ref points at a schema that exists
  std::vector<const nlohmann::json*> stack{&doc};
  while (!stack.empty()) {
    const nlohmann::json* node = stack.back();
    stack.pop_back();
    if (node->is_object()) {
      if (const auto it = node->find("$ref"); it != node->end()) {
        const std::string ref = *it;
        ASSERT_TRUE(ref.starts_with("#/components/schemas/")) << ref;
        EXPECT_TRUE(schemas.contains(ref.substr(21))) << ref;
      }
      for (const auto& [k, v] : node->items()) stack.push_back(&v);
    } else if (node->is_array()) {
      for (const auto& v : *node) stack.push_back(&v);
    }
  }
}

// The enum of GET /plans/{id}/exports/{format} is the server's export routes, made from the format table:
// a format added to the table (or a route) and not to src/server/openapi.json fails here.
TEST_P(ApiTest, OpenApiExportEnumIsTheExportRoutes) {
  const nlohmann::json doc = strict::parse_json(call("GET", "/api/v1/openapi.json").body, "openapi.json");
  const auto& params = doc.at("paths").at("/api/v1/plans/{id}/exports/{format}").at("parameters");
  const auto it =
      std::find_if(params.begin(), params.end(), [](const auto& p) { return p.at("name") == "format"; });
  ASSERT_NE(it, params.end());
  std::vector<std::string> documented, served;
  for (const auto& name : it->at("schema").at("enum")) documented.push_back(name);
  for (const auto& route : usecases::export_routes()) served.push_back(route.name);
  EXPECT_EQ(documented, served);
  // and GET /api/v1/formats gives the same routes
  std::vector<std::string> listed;
  const nlohmann::json formats = call("GET", "/api/v1/formats").json();
  for (const auto& r : formats.at("routes")) listed.push_back(r.at("name"));
  EXPECT_EQ(listed, served);
}

}  // namespace
}  // namespace uavcover::server::testing
