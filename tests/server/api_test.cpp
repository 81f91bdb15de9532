// The /api/v1 routes over a real SQLite store: missions with revisions, listing, catalogs, job
// creation, and the error codes with their JSON bodies naming the field.
#include <fmt/format.h>

#include <regex>

#include "export/formats.hpp"
#include "server/api_fixture.hpp"
#include "server/api_internal.hpp"
#include "uavcover/mission.hpp"

namespace uavcover::server::testing {
namespace {

using nlohmann::json;

/// The olive grove moved by (dlon, dlat) and renamed.
std::string moved_mission(const std::string& name, double dlon, double dlat) {
  json doc = json::parse(olive_grove());
  doc["name"] = name;
  auto shift = [&](json& ring) {
    for (auto& p : ring) {
      p[0] = p[0].get<double>() + dlon;
      p[1] = p[1].get<double>() + dlat;
    }
  };
  for (auto& ring : doc["area"]["coordinates"]) shift(ring);
  for (auto& z : doc["no_fly_zones"])
    for (auto& ring : z["coordinates"]) shift(ring);
  for (auto& u : doc["uavs"]) {
    u["start"][0] = u["start"][0].get<double>() + dlon;
    u["start"][1] = u["start"][1].get<double>() + dlat;
  }
  return doc.dump();
}

const std::regex kIsoTime(R"(\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}\.\d{3}Z)");

TEST(IsoTime, FormatsUnixMilliseconds) {
  EXPECT_EQ(iso_time(0), "1970-01-01T00:00:00.000Z");
  EXPECT_EQ(iso_time(1'795'741'323'456), "2026-11-27T01:02:03.456Z");
}

// The 5 x 4 km field's qgc export has ~900 PX4 distance warnings (~150 KB): in a header, Beast refused
// the field and dropped the connection. The header keeps the asked UAV's warnings and the plan's, as
// many as fit, and says how many it left off.
TEST(ExportWarningsHeader, KeepsTheUavsOwnAndFitsTheLimit) {
  EXPECT_EQ(detail::export_warnings_header({}, "alpha"), "");
  EXPECT_EQ(detail::export_warnings_header({"uav 'bravo': far"}, "alpha"), "");
  EXPECT_EQ(detail::export_warnings_header({"uav 'bravo': far", "ceiling"}, "alpha"), R"(["ceiling"])");
  EXPECT_EQ(detail::export_warnings_header({"uav 'bravo': far", "ceiling"}, ""),
            R"(["uav 'bravo': far","ceiling"])");
  EXPECT_EQ(detail::export_warnings_header({"uav 'alphabet': x", "uav 'alpha': y"}, "alpha"),
            R"(["uav 'alpha': y"])");
  std::vector<std::string> many{"transition altitudes compressed \u00e9"};
  for (int k = 0; k < 900; ++k)
    for (const char* id : {"alpha", "bravo"})
      many.push_back(
          fmt::format("uav '{}': PX4: mission item {} (MAV_CMD 16, coverage): 2474 m from the "
                      "previous waypoint, MIS_DIST_WPS 900 m",
                      id, k + 1));
  const std::string h = detail::export_warnings_header(many, "bravo");
  ASSERT_LE(h.size(), detail::kWarningsHeaderLimit);
  for (const char c : h) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << int(c);  // one ASCII header line
  const json a = json::parse(h);
  ASSERT_GT(a.size(), 10u);
  EXPECT_EQ(a[0], many[0]);
  std::size_t shown = 0;
  for (std::size_t k = 1; k + 1 < a.size(); ++k) {
    EXPECT_EQ(a[k], many[2 * k]) << k;  // bravo's, in order
    ++shown;
  }
  EXPECT_EQ(a.back(),
            fmt::format("{} more warnings left off (uavcover export prints them all)", 900 - shown));
}

TEST_P(ApiTest, MissionLifecycleWithRevisions) {
  const Answer created = call("POST", "/api/v1/missions", olive_grove());
  ASSERT_EQ(created.status, 201) << created.body;
  const auto id = created.json().at("id").get<store::Id>();
  EXPECT_EQ(created.json().at("revision"), 1);
  EXPECT_EQ(created.header("Location"), "/api/v1/missions/" + std::to_string(id));

  Answer got = call("GET", "/api/v1/missions/" + std::to_string(id));
  ASSERT_EQ(got.status, 200) << got.body;
  json m = got.json();
  EXPECT_EQ(m.at("name"), "North olive grove");
  EXPECT_EQ(m.at("revision"), 1);
  EXPECT_EQ(m.at("latest_revision"), 1);
  EXPECT_EQ(m.at("source"), json::parse(olive_grove()));
  EXPECT_EQ(m.at("mission").at("name"), "North olive grove");
  EXPECT_TRUE(std::regex_match(m.at("created").get<std::string>(), kIsoTime)) << m.at("created");
  EXPECT_TRUE(std::regex_match(m.at("updated").get<std::string>(), kIsoTime));
  ASSERT_EQ(m.at("bbox").size(), 4u);
  EXPECT_NEAR(m["bbox"][0].get<double>(), 22.8990, 1e-9);
  EXPECT_NEAR(m["bbox"][1].get<double>(), 40.6000, 1e-9);
  EXPECT_NEAR(m["bbox"][2].get<double>(), 22.9145, 1e-9);
  EXPECT_NEAR(m["bbox"][3].get<double>(), 40.6085, 1e-9);

  json revised = json::parse(olive_grove());
  revised["name"] = "South olive grove";
  const Answer put = call("PUT", "/api/v1/missions/" + std::to_string(id), revised.dump());
  ASSERT_EQ(put.status, 200) << put.body;
  EXPECT_EQ(put.json(), (json{{"id", id}, {"revision", 2}}));

  m = call("GET", "/api/v1/missions/" + std::to_string(id)).json();
  EXPECT_EQ(m.at("name"), "South olive grove");
  EXPECT_EQ(m.at("revision"), 2);
  EXPECT_EQ(m.at("latest_revision"), 2);

  const Answer old = call("GET", "/api/v1/missions/" + std::to_string(id) + "/revisions/1");
  ASSERT_EQ(old.status, 200) << old.body;
  EXPECT_EQ(old.json().at("name"), "North olive grove");
  EXPECT_EQ(old.json().at("revision"), 1);
  EXPECT_EQ(old.json().at("latest_revision"), 2);
  const Answer missing_rev = call("GET", "/api/v1/missions/" + std::to_string(id) + "/revisions/3");
  EXPECT_EQ(missing_rev.status, 404);
  EXPECT_EQ(missing_rev.error_field(), "revision");
  EXPECT_EQ(call("GET", "/api/v1/missions/" + std::to_string(id) + "/revisions/0").status, 400);

  const Answer del = call("DELETE", "/api/v1/missions/" + std::to_string(id));
  EXPECT_EQ(del.status, 204);
  EXPECT_TRUE(del.body.empty());
  EXPECT_EQ(call("GET", "/api/v1/missions/" + std::to_string(id)).status, 404);
  EXPECT_EQ(call("DELETE", "/api/v1/missions/" + std::to_string(id)).status, 404);
  EXPECT_EQ(call("PUT", "/api/v1/missions/" + std::to_string(id), olive_grove()).status, 404);
}

TEST_P(ApiTest, MissionListPagesAndFilters) {
  std::vector<store::Id> ids;
  for (int i = 0; i < 5; ++i)
    ids.push_back(
        create_mission(moved_mission((i % 2 ? "Vineyard " : "Orchard ") + std::to_string(i), i * 1.0, 0)));

  std::vector<store::Id> seen;
  std::string cursor;
  for (int page = 0; page < 10; ++page) {
    const Answer a = call("GET", "/api/v1/missions?limit=2" + (cursor.empty() ? "" : "&cursor=" + cursor));
    ASSERT_EQ(a.status, 200) << a.body;
    const json j = a.json();
    EXPECT_LE(j.at("items").size(), 2u);
    for (const auto& item : j["items"]) {
      seen.push_back(item.at("id").get<store::Id>());
      EXPECT_TRUE(item.contains("bbox") && item.contains("created") && item.contains("updated"));
      EXPECT_EQ(item.at("revision"), 1);
    }
    if (j.at("next_cursor").is_null()) break;
    cursor = std::to_string(j["next_cursor"].get<store::Id>());
  }
  EXPECT_EQ(seen, ids);

  json named = call("GET", "/api/v1/missions?name=vineyard").json();
  ASSERT_EQ(named.at("items").size(), 2u);
  EXPECT_EQ(named["items"][0].at("name"), "Vineyard 1");
  EXPECT_EQ(named["items"][1].at("name"), "Vineyard 3");
  EXPECT_TRUE(named.at("next_cursor").is_null());

  // the third one lies around longitude 24.9
  json boxed = call("GET", "/api/v1/missions?bbox=24.5,40,25.5,41").json();
  ASSERT_EQ(boxed.at("items").size(), 1u);
  EXPECT_EQ(boxed["items"][0].at("id"), ids[2]);
}

TEST_P(ApiTest, BadQueryParametersAre400NamingThem) {
  for (const auto& [query, field] :
       std::vector<std::pair<std::string, std::string>>{{"limit=0", "limit"},
                                                        {"limit=1001", "limit"},
                                                        {"limit=abc", "limit"},
                                                        {"cursor=-3", "cursor"},
                                                        {"cursor=x", "cursor"},
                                                        {"bbox=1,2,3", "bbox"},
                                                        {"bbox=1,2,3,4,5", "bbox"},
                                                        {"bbox=1,2,nan,4", "bbox"},
                                                        {"bbox=3,2,1,4", "bbox"},
                                                        {"bbox=-200,0,0,1", "bbox"},
                                                        {"name=" + std::string(201, 'a'), "name"}}) {
    const Answer a = call("GET", "/api/v1/missions?" + query);
    EXPECT_EQ(a.status, 400) << query;
    EXPECT_EQ(a.error_field(), field) << query;
  }
}

TEST_P(ApiTest, ErrorCodesAndBodies) {
  // 400: malformed JSON, duplicate keys, empty body, bad id
  Answer a = call("POST", "/api/v1/missions", "{\"name\": ");
  EXPECT_EQ(a.status, 400);
  EXPECT_EQ(a.error_field(), "body");
  EXPECT_FALSE(a.json()["error"]["message"].get<std::string>().empty());
  EXPECT_EQ(call("POST", "/api/v1/missions", "{\"a\": 1, \"a\": 2}").status, 400);
  a = call("POST", "/api/v1/missions", "");
  EXPECT_EQ(a.status, 400);
  EXPECT_EQ(a.error_field(), "body");
  a = call("GET", "/api/v1/missions/abc");
  EXPECT_EQ(a.status, 400);
  EXPECT_EQ(a.error_field(), "id");
  EXPECT_EQ(call("GET", "/api/v1/missions/0").status, 400);
  EXPECT_EQ(call("GET", "/api/v1/missions/99999999999999999999").status, 400);

  // 404: unknown route or id
  EXPECT_EQ(call("GET", "/api/v1/nothing").status, 404);
  a = call("GET", "/api/v1/missions/12345");
  EXPECT_EQ(a.status, 404);
  EXPECT_EQ(a.error_field(), "id");
  EXPECT_EQ(call("GET", "/api/v1/plans/12345").status, 404);

  // 405 with Allow
  a = call("PATCH", "/api/v1/missions/1");
  EXPECT_EQ(a.status, 405);
  EXPECT_NE(a.header("Allow").find("GET"), std::string::npos);
  EXPECT_NE(a.header("Allow").find("DELETE"), std::string::npos);
  EXPECT_EQ(call("DELETE", "/api/v1/missions").status, 405);

  // 415: not JSON; a charset parameter is fine
  a = call("POST", "/api/v1/missions", olive_grove(), {{"content-type", "text/plain"}});
  EXPECT_EQ(a.status, 415);
  EXPECT_EQ(a.error_field(), "body");
  EXPECT_EQ(
      call("POST", "/api/v1/missions", olive_grove(), {{"content-type", "application/json; charset=utf-8"}})
          .status,
      201);

  // 413: over the limit
  ctx_->config.max_body_bytes = 100;
  EXPECT_EQ(call("POST", "/api/v1/missions", olive_grove()).status, 413);
  ctx_->config.max_body_bytes = std::size_t{10} << 20;

  // 422: an invalid mission, with the parser's field
  json bad = json::parse(olive_grove());
  bad["uavs"][1]["share"] = -1;
  a = call("POST", "/api/v1/missions", bad.dump());
  EXPECT_EQ(a.status, 422) << a.body;
  EXPECT_EQ(a.error_field(), "uavs[1].share");
  bad = json::parse(olive_grove());
  bad.erase("area");
  a = call("POST", "/api/v1/missions", bad.dump());
  EXPECT_EQ(a.status, 422);
  EXPECT_EQ(a.error_field(), "area");
  EXPECT_EQ(call("POST", "/api/v1/missions", "[1, 2]").status, 422);

  // 409: deleting a mission with a queued job
  const auto id = create_mission(olive_grove());
  ASSERT_EQ(call("POST", "/api/v1/missions/" + std::to_string(id) + "/plans").status, 202);
  a = call("DELETE", "/api/v1/missions/" + std::to_string(id));
  EXPECT_EQ(a.status, 409);
  EXPECT_TRUE(a.json().contains("error"));
}

TEST_P(ApiTest, CatalogEntriesAreValidatedField_by_field) {
  const json camera = {{"name", "Sony RX1R II"},
                       {"sensor_width_mm", 35.9},
                       {"focal_length_mm", 35},
                       {"image_width_px", 7952},
                       {"hfov_deg", 54.3}};
  Answer a = call("POST", "/api/v1/cameras", camera.dump());
  ASSERT_EQ(a.status, 201) << a.body;
  const auto camera_id = a.json().at("id").get<store::Id>();
  a = call("GET", "/api/v1/cameras/" + std::to_string(camera_id));
  ASSERT_EQ(a.status, 200);
  EXPECT_EQ(a.json().at("name"), "Sony RX1R II");
  EXPECT_EQ(a.json().at("image_width_px"), 7952);
  EXPECT_EQ(a.json().at("id"), camera_id);
  EXPECT_TRUE(std::regex_match(a.json().at("updated").get<std::string>(), kIsoTime));

  const json uav = {{"name", "Quad"},      {"speed_mps", 8},          {"max_accel_mps2", 3},
                    {"endurance_min", 30}, {"cost_per_min_eur", 1.5}, {"camera_id", camera_id}};
  a = call("POST", "/api/v1/uavs", uav.dump());
  ASSERT_EQ(a.status, 201) << a.body;
  const auto uav_id = a.json().at("id").get<store::Id>();

  auto expect_422 = [&](const std::string& path, json body, const std::string& field) {
    const Answer r = call("POST", path, body.dump());
    EXPECT_EQ(r.status, 422) << body.dump() << " " << r.body;
    if (r.status == 422) {
      EXPECT_EQ(r.error_field(), field) << body.dump();
    }
  };
  auto with = [](json j, const std::string& k, json v) {
    j[k] = std::move(v);
    return j;
  };
  auto without = [](json j, const std::string& k) {
    j.erase(k);
    return j;
  };
  expect_422("/api/v1/uavs", without(uav, "name"), "name");
  expect_422("/api/v1/uavs", with(uav, "name", ""), "name");
  expect_422("/api/v1/uavs", with(uav, "name", std::string(201, 'x')), "name");
  expect_422("/api/v1/uavs", with(uav, "name", 5), "name");
  expect_422("/api/v1/uavs", with(uav, "speed_mps", 0), "speed_mps");
  expect_422("/api/v1/uavs", with(uav, "speed_mps", 50.5), "speed_mps");
  expect_422("/api/v1/uavs", with(uav, "speed_mps", "fast"), "speed_mps");
  expect_422("/api/v1/uavs", without(uav, "speed_mps"), "speed_mps");
  expect_422("/api/v1/uavs", with(uav, "max_accel_mps2", -1), "max_accel_mps2");
  expect_422("/api/v1/uavs", with(uav, "endurance_min", 1441), "endurance_min");
  expect_422("/api/v1/uavs", with(uav, "cost_per_min_eur", -0.01), "cost_per_min_eur");
  expect_422("/api/v1/uavs", with(uav, "camera_id", camera_id + 100), "camera_id");
  expect_422("/api/v1/uavs", with(uav, "camera_id", "1"), "camera_id");
  expect_422("/api/v1/uavs", with(uav, "colour", "red"), "colour");
  expect_422("/api/v1/cameras", with(camera, "image_width_px", 1.5), "image_width_px");
  expect_422("/api/v1/cameras", with(camera, "image_width_px", 100001), "image_width_px");
  expect_422("/api/v1/cameras", with(camera, "hfov_deg", 180), "hfov_deg");
  expect_422("/api/v1/cameras", with(camera, "sensor_width_mm", 0), "sensor_width_mm");
  expect_422("/api/v1/cameras", with(camera, "focal_length_mm", 1001), "focal_length_mm");
  expect_422("/api/v1/cameras", with(camera, "camera_id", 1), "camera_id");
  EXPECT_EQ(call("POST", "/api/v1/cameras", "[]").status, 422);
  EXPECT_EQ(call("POST", "/api/v1/cameras", "{").status, 400);

  // replace, list, delete
  a = call("PUT", "/api/v1/uavs/" + std::to_string(uav_id), with(uav, "speed_mps", 12).dump());
  ASSERT_EQ(a.status, 200) << a.body;
  EXPECT_EQ(a.json().at("speed_mps"), 12);
  EXPECT_EQ(call("PUT", "/api/v1/uavs/" + std::to_string(uav_id), with(uav, "speed_mps", 0).dump()).status,
            422);
  EXPECT_EQ(call("PUT", "/api/v1/uavs/999999", uav.dump()).status, 404);
  a = call("GET", "/api/v1/uavs");
  ASSERT_EQ(a.status, 200);
  bool found = false;
  const json listed = a.json();
  for (const auto& e : listed.at("items")) found = found || (e.at("id") == uav_id && e.at("speed_mps") == 12);
  EXPECT_TRUE(found) << a.body;

  // a mission referencing the catalog UAV gets its speed, acceleration and endurance
  json doc = json::parse(olive_grove());
  for (const char* k : {"speed_mps", "max_accel_mps2", "endurance_min"}) doc["uavs"][0].erase(k);
  doc["uavs"][0]["catalog_id"] = uav_id;
  a = call("POST", "/api/v1/missions", doc.dump());
  ASSERT_EQ(a.status, 201) << a.body;
  const json stored =
      call("GET", "/api/v1/missions/" + std::to_string(a.json().at("id").get<store::Id>())).json();
  EXPECT_EQ(stored.at("source").at("uavs").at(0).at("catalog_id"), uav_id);
  EXPECT_DOUBLE_EQ(stored.at("mission").at("uavs").at(0).at("speed_mps").get<double>(), 12.0);
  EXPECT_DOUBLE_EQ(stored.at("mission").at("uavs").at(0).at("max_accel_mps2").get<double>(), 3.0);
  doc["uavs"][0]["catalog_id"] = uav_id + 1000;
  EXPECT_EQ(call("POST", "/api/v1/missions", doc.dump()).status, 422);

  EXPECT_EQ(call("DELETE", "/api/v1/uavs/" + std::to_string(uav_id)).status, 204);
  EXPECT_EQ(call("GET", "/api/v1/uavs/" + std::to_string(uav_id)).status, 404);
  EXPECT_EQ(call("DELETE", "/api/v1/uavs/" + std::to_string(uav_id)).status, 404);
}

TEST_P(ApiTest, CatalogNamesAndReferencesHold) {
  const json camera = {{"name", "cam"},
                       {"sensor_width_mm", 35.9},
                       {"focal_length_mm", 35},
                       {"image_width_px", 7952},
                       {"hfov_deg", 54.3}};
  for (const std::string& name :
       std::vector<std::string>{"a\tb", "line\nbreak", "esc\x1b[2J", std::string("nul\0x", 5), "del\x7f"}) {
    json c = camera;
    c["name"] = name;
    const Answer r = call("POST", "/api/v1/cameras", c.dump());
    EXPECT_EQ(r.status, 422) << r.body;
    EXPECT_EQ(r.error_field(), "name");
  }
  Answer a = call("POST", "/api/v1/cameras", camera.dump());
  ASSERT_EQ(a.status, 201) << a.body;
  const auto camera_id = a.json().at("id").get<store::Id>();
  const json uav = {{"name", "carrier"},   {"speed_mps", 8},          {"max_accel_mps2", 3},
                    {"endurance_min", 30}, {"cost_per_min_eur", 1.5}, {"camera_id", camera_id}};
  a = call("POST", "/api/v1/uavs", uav.dump());
  ASSERT_EQ(a.status, 201) << a.body;
  const auto uav_id = a.json().at("id").get<store::Id>();
  // the camera is in use: 409, and the UAV keeps it
  a = call("DELETE", "/api/v1/cameras/" + std::to_string(camera_id));
  EXPECT_EQ(a.status, 409) << a.body;
  EXPECT_EQ(a.error_field(), "id");
  EXPECT_EQ(call("GET", "/api/v1/uavs/" + std::to_string(uav_id)).json().at("camera_id"), camera_id);
  EXPECT_EQ(call("DELETE", "/api/v1/uavs/" + std::to_string(uav_id)).status, 204);
  EXPECT_EQ(call("DELETE", "/api/v1/cameras/" + std::to_string(camera_id)).status, 204);
  // ids: plain decimal numbers
  EXPECT_EQ(call("GET", "/api/v1/cameras/0" + std::to_string(camera_id)).status, 400);
  EXPECT_EQ(call("GET", "/api/v1/cameras/+" + std::to_string(camera_id)).status, 400);
  // a body needs its JSON media type
  a = call("POST", "/api/v1/cameras", camera.dump(), {{"content-type", ""}});
  EXPECT_EQ(a.status, 415) << a.body;
}

TEST_P(ApiTest, PlannerThreadsAreBoundedByTheServer) {
  ctx_->config.planner_threads = 2;
  const auto id = create_mission(olive_grove());
  const std::string plans = "/api/v1/missions/" + std::to_string(id) + "/plans";
  bool smt = false;
  const json planners = call("GET", "/api/v1/planners").json();
  for (const auto& p : planners.at("items")) smt = smt || p.at("name") == "smt";
  if (!smt) GTEST_SKIP() << "no smt planner in this build";
  Answer a = call("POST", plans, R"({"planner": "smt", "planner_params": {"threads": 64}})");
  EXPECT_EQ(a.status, 422) << a.body;
  EXPECT_EQ(a.error_field(), "planner_params.threads");
  a = call("POST", plans, R"({"planner": "smt", "planner_params": {"threads": 2}})");
  EXPECT_EQ(a.status, 202) << a.body;
}

TEST_P(ApiTest, DarpObjectiveParamsAreListedAndRefusedByName) {
  const auto id = create_mission(olive_grove());
  const std::string plans = "/api/v1/missions/" + std::to_string(id) + "/plans";
  const json planners = call("GET", "/api/v1/planners").json();
  json objective;
  for (const auto& p : planners.at("items"))
    if (p.at("name") == "darp")
      for (const auto& q : p.at("schema").at("params"))
        if (q.at("name") == "objective") objective = q;
  ASSERT_FALSE(objective.is_null()) << planners.dump();
  EXPECT_EQ(objective.at("default"), "uavcover");
  EXPECT_EQ(objective.at("enum"), json({"uavcover", "paper"}));
  Answer a = call("POST", plans, R"({"planner": "darp", "planner_params": {"j_weight_a": 1.5}})");
  EXPECT_EQ(a.status, 422) << a.body;
  EXPECT_EQ(a.error_field(), "planner_params.j_weight_a");
  a = call("POST", plans, R"({"planner": "darp", "planner_params": {"objective": "theirs"}})");
  EXPECT_EQ(a.status, 422) << a.body;
  EXPECT_EQ(a.error_field(), "planner_params.objective");
  a = call("POST", plans,
           R"({"planner": "darp", "planner_params": {"objective": "paper", "j_weight_c": 0}})");
  EXPECT_EQ(a.status, 202) << a.body;
}

TEST_P(ApiTest, JobCreationValidatesParameters) {
  const auto id = create_mission(olive_grove());
  const std::string plans = "/api/v1/missions/" + std::to_string(id) + "/plans";
  Answer a = call("POST", plans, R"({"seed": "seven"})");
  EXPECT_EQ(a.status, 422) << a.body;
  EXPECT_EQ(a.error_field(), "seed");
  a = call("POST", plans, R"({"planner": "no-such-planner"})");
  EXPECT_EQ(a.status, 422) << a.body;
  EXPECT_EQ(a.error_field(), "planner");
  a = call("POST", "/api/v1/missions/" + std::to_string(id) + "/studies", "{}");
  EXPECT_EQ(a.status, 422) << a.body;
  EXPECT_EQ(a.error_field(), "uavs");
  EXPECT_EQ(call("POST", "/api/v1/missions/424242/plans").status, 404);
  EXPECT_EQ(call("POST", plans, "{").status, 400);

  a = call("POST", plans, R"({"seed": 7})");
  ASSERT_EQ(a.status, 202) << a.body;
  const json job = a.json();
  EXPECT_EQ(job.at("kind"), "plan");
  EXPECT_EQ(job.at("state"), "queued");
  EXPECT_EQ(job.at("mission_id"), id);
  EXPECT_EQ(job.at("revision"), 1);
  EXPECT_EQ(job.at("params").at("seed"), 7);
  EXPECT_TRUE(job.at("started").is_null());
  EXPECT_TRUE(job.at("error").is_null());
  EXPECT_EQ(job.at("artifacts"), json::array());
  const auto job_id = job.at("id").get<store::Id>();
  EXPECT_EQ(a.header("Location"), "/api/v1/plans/" + std::to_string(job_id));

  // a plan is not a study; artifacts of an unfinished job are a conflict
  EXPECT_EQ(call("GET", "/api/v1/studies/" + std::to_string(job_id)).status, 404);
  a = call("GET", "/api/v1/plans/" + std::to_string(job_id) + "/plan.json");
  EXPECT_EQ(a.status, 409);
  EXPECT_EQ(call("GET", "/api/v1/plans/" + std::to_string(job_id) + "/exports/qgc").status, 409);
  EXPECT_EQ(call("GET", "/api/v1/plans/" + std::to_string(job_id) + "/images/secret.txt").status, 404);
  EXPECT_EQ(call("GET", "/api/v1/plans/" + std::to_string(job_id) + "/exports/exe").status, 404);

  // cancelling a queued job ends it at once
  a = call("DELETE", "/api/v1/plans/" + std::to_string(job_id));
  ASSERT_EQ(a.status, 200) << a.body;
  EXPECT_EQ(a.json().at("state"), "cancelled");
  // a finished job is deleted (docs/cache.md)
  EXPECT_EQ(call("DELETE", "/api/v1/plans/" + std::to_string(job_id)).status, 204);
  EXPECT_EQ(call("GET", "/api/v1/plans/" + std::to_string(job_id)).status, 404);
  EXPECT_EQ(call("DELETE", "/api/v1/plans/" + std::to_string(job_id)).status, 404);
}

TEST_P(ApiTest, MissionPlansAreListedNewestFirst) {
  using namespace std::chrono_literals;
  const auto id = create_mission(olive_grove());
  const auto other = create_mission(olive_grove());
  const std::string plans = "/api/v1/missions/" + std::to_string(id) + "/plans";
  Answer a = call("GET", plans);
  ASSERT_EQ(a.status, 200) << a.body;
  EXPECT_EQ(a.json(), (json{{"items", json::array()}}));

  const auto first = call("POST", plans, R"({"planner": "boustrophedon", "seed": 3})").json().at("id");
  const auto second = call("POST", plans, R"({"seed": 4})").json().at("id");
  ASSERT_EQ(call("POST", "/api/v1/missions/" + std::to_string(other) + "/plans").status, 202);
  ASSERT_EQ(call("POST", "/api/v1/missions/" + std::to_string(id) + "/studies", R"({"uavs": "1..2"})").status,
            202);
  // the first plan finishes with metrics (as a worker would record them)
  const auto claimed = store_->claim_job("test-worker", 60s, 3);
  ASSERT_TRUE(claimed);
  ASSERT_EQ(claimed->id, first.get<store::Id>());
  const json result = {{"planner", "boustrophedon"},
                       {"metrics", {{"poc", 0.99}, {"flight_time_min", 12.5}}},
                       {"warnings", json::array({"a warning"})},
                       {"uavs", json::array()}};
  ASSERT_TRUE(store_->finish_job(claimed->id, "test-worker", store::JobState::Done, result, nullptr,
                                 {{"plan.json", "application/json", "{}"}}));

  a = call("GET", plans);
  ASSERT_EQ(a.status, 200) << a.body;
  const json items = a.json().at("items");
  ASSERT_EQ(items.size(), 2u) << "plans of this mission only, no studies";
  EXPECT_EQ(items[0].at("id"), second);
  EXPECT_EQ(items[0].at("state"), "queued");
  EXPECT_TRUE(items[0].at("finished").is_null());
  EXPECT_EQ(items[0].at("metrics"), json::object());
  const json& done = items[1];
  EXPECT_EQ(done.at("id"), first);
  EXPECT_EQ(done.at("kind"), "plan");
  EXPECT_EQ(done.at("mission_id"), id);
  EXPECT_EQ(done.at("revision"), 1);
  EXPECT_EQ(done.at("state"), "done");
  EXPECT_EQ(done.at("planner"), "boustrophedon");
  EXPECT_EQ(done.at("params").at("seed"), 3);
  EXPECT_TRUE(std::regex_match(done.at("created").get<std::string>(), kIsoTime));
  EXPECT_TRUE(std::regex_match(done.at("finished").get<std::string>(), kIsoTime));
  EXPECT_EQ(done.at("metrics"), result.at("metrics"));
  EXPECT_EQ(done.at("warnings"), json::array({"a warning"}));
  EXPECT_TRUE(done.at("error").is_null());
  EXPECT_FALSE(done.contains("artifacts"));
  EXPECT_FALSE(done.contains("result"));
  // stored with plan.json alone: no plan to make an export from (404, not the export service's failure)
  a = call("GET", "/api/v1/plans/" + std::to_string(first.get<store::Id>()) + "/exports/qgc");
  EXPECT_EQ(a.status, 404) << a.body;
  EXPECT_EQ(a.error_field(), "artifact") << a.body;

  a = call("GET", plans + "?limit=1");
  ASSERT_EQ(a.status, 200) << a.body;
  ASSERT_EQ(a.json().at("items").size(), 1u);
  EXPECT_EQ(a.json().at("items")[0].at("id"), second);
  EXPECT_EQ(call("GET", "/api/v1/missions/" + std::to_string(id) + "/studies").json().at("items").size(), 1u);
  for (const char* bad : {"0", "101", "ten", "", "5x"}) {
    a = call("GET", plans + "?limit=" + bad);
    EXPECT_EQ(a.status, 400) << bad;
    EXPECT_EQ(a.error_field(), "limit") << bad;
  }
  a = call("GET", "/api/v1/missions/424242/plans");
  EXPECT_EQ(a.status, 404);
  EXPECT_EQ(a.error_field(), "id");
  EXPECT_EQ(call("GET", "/api/v1/missions/x/plans").status, 400);
}

TEST_P(ApiTest, FullQueueIs503WithRetryAfter) {
  close();
  open(2);
  const auto id = create_mission(olive_grove());
  const std::string plans = "/api/v1/missions/" + std::to_string(id) + "/plans";
  EXPECT_EQ(call("POST", plans).status, 202);
  EXPECT_EQ(call("POST", plans).status, 202);
  const Answer a = call("POST", plans);
  EXPECT_EQ(a.status, 503) << a.body;
  EXPECT_EQ(a.header("Retry-After"), "5");
  EXPECT_TRUE(a.json().contains("error"));
}

TEST_P(ApiTest, PlannersAreListed) {
  const Answer a = call("GET", "/api/v1/planners");
  ASSERT_EQ(a.status, 200);
  std::vector<std::string> names;
  const json listed = a.json();
  for (const auto& p : listed.at("items")) {
    names.push_back(p.at("name"));
    EXPECT_TRUE(p.at("schema").is_object());
  }
  EXPECT_NE(std::find(names.begin(), names.end(), "darp"), names.end());
}

TEST_P(ApiTest, FormatsAreTheExportTableAndTheRoutesMadeFromIt) {
  const Answer a = call("GET", "/api/v1/formats");
  ASSERT_EQ(a.status, 200) << a.body;
  EXPECT_EQ(a.content_type, "application/json");
  const json listed = a.json();
  // items: the table itself, row by row
  ASSERT_EQ(listed.at("items"), exporting::formats_json());
  std::vector<std::string> names;
  for (const auto& f : listed.at("items")) {
    names.push_back(f.at("name"));
    for (const char* key : {"title", "extension", "media_type", "consumers", "limits"})
      EXPECT_FALSE(f.at(key).get<std::string>().empty()) << f.at("name") << " " << key;
    EXPECT_TRUE(f.at("per_sortie").is_boolean());
  }
  EXPECT_EQ(names, exporting::known_formats());
  // routes: every format of the table, in its order, and kmz (made by kml) right after kml
  std::vector<std::string> routes, expected;
  for (const auto& r : listed.at("routes")) {
    routes.push_back(r.at("name"));
    EXPECT_NE(exporting::find_format(r.at("format").get<std::string>()), nullptr) << r;
    EXPECT_FALSE(r.at("title").get<std::string>().empty()) << r;
    if (r.at("name") != "kmz") {
      EXPECT_EQ(r.at("format"), r.at("name"));
      EXPECT_EQ(r.at("title"), exporting::find_format(r.at("name").get<std::string>())->title);
    } else {
      EXPECT_EQ(r.at("format"), "kml");
    }
  }
  for (const auto& n : names) {
    expected.push_back(n);
    if (n == "kml") expected.push_back("kmz");
  }
  EXPECT_EQ(routes, expected);

  // an unknown export route is 404 naming the field, its text lists exactly these routes
  const auto id = create_mission(olive_grove());
  const auto plan = call("POST", "/api/v1/missions/" + std::to_string(id) + "/plans").json().at("id");
  const Answer bad = call("GET", "/api/v1/plans/" + std::to_string(plan.get<long long>()) + "/exports/gpx");
  EXPECT_EQ(bad.status, 404) << bad.body;
  EXPECT_EQ(bad.error_field(), "format");
  std::string list;
  for (const auto& r : routes) list += (list.empty() ? "" : ", ") + r;
  EXPECT_EQ(bad.json().at("error").at("message"), "unknown export format \"gpx\"; expected one of " + list);
  // a route of the list is known (the plan is queued: 409, not 404)
  for (const auto& r : routes)
    EXPECT_EQ(call("GET", "/api/v1/plans/" + std::to_string(plan.get<long long>()) + "/exports/" + r).status,
              409)
        << r;
}

TEST_P(ApiTest, MaxCellsBoundsEveryMissionTheServerParses) {
  // `serve --max-cells`: the olive grove at a 1 m spacing needs more than 1000 grid cells
  json doc = json::parse(olive_grove());
  doc.erase("camera");
  doc["spacing_m"] = 1.0;
  const store::Id stored = create_mission(doc.dump());  // under the default 4M cells
  ctx_->config.parse.max_cells = 1000;
  for (const std::string route : {"/api/v1/missions", "/api/v1/missions/validate"}) {
    const Answer a = call("POST", route, doc.dump());
    EXPECT_EQ(a.status, 422) << route << ": " << a.body;
    EXPECT_EQ(a.json()["error"]["field"], "spacing_m") << a.body;
    EXPECT_NE(a.json()["error"]["message"].get<std::string>().find("limit of 1000"), std::string::npos)
        << a.body;
  }
  // a mission stored under a larger limit is not planned under the smaller one
  const Answer plan = call("POST", "/api/v1/missions/" + std::to_string(stored) + "/plans", "{}");
  EXPECT_EQ(plan.status, 422) << plan.body;
  EXPECT_EQ(plan.json()["error"]["field"], "spacing_m") << plan.body;
  ctx_->config.parse.max_cells = 100'000'000;
  EXPECT_EQ(call("POST", "/api/v1/missions/validate", doc.dump()).status, 200);
}

TEST_P(ApiTest, ValidateGivesTheLibrarysDerivedValuesWithoutStoring) {
  const auto before = call("GET", "/api/v1/missions").json()["items"].size();
  json doc = json::parse(olive_grove());
  doc["camera"] = {{"altitude_m", 60},
                   {"sensor_width_mm", 13.2},
                   {"focal_length_mm", 8.8},
                   {"image_width_px", 5472},
                   {"side_overlap", 0.3}};
  const Answer ok = call("POST", "/api/v1/missions/validate", doc.dump());
  ASSERT_EQ(ok.status, 200) << ok.body;
  const json v = ok.json();
  // the library's formulas: GSD = h * sw / (f * px), footprint = GSD * px, spacing = footprint * (1 -
  // overlap)
  const double gsd = 60.0 * 13.2 / (8.8 * 5472);
  EXPECT_NEAR(v["gsd_m"].get<double>(), gsd, 1e-9);
  EXPECT_NEAR(v["footprint_m"].get<double>(), gsd * 5472, 1e-6);
  EXPECT_NEAR(v["spacing_m"].get<double>(), gsd * 5472 * 0.7, 1e-6);
  EXPECT_EQ(v["altitude_m"], 60.0);
  EXPECT_EQ(v["bbox"].size(), 4u);
  EXPECT_TRUE(v["mission"].contains("camera")) << "the normalised mission comes back";
  EXPECT_EQ(call("GET", "/api/v1/missions").json()["items"].size(), before) << "nothing stored";

  doc["camera"]["side_overlap"] = 1.5;
  const Answer bad = call("POST", "/api/v1/missions/validate", doc.dump());
  EXPECT_EQ(bad.status, 422);
  EXPECT_EQ(bad.json()["error"]["field"], "camera.side_overlap");
}

}  // namespace
}  // namespace uavcover::server::testing

namespace uavcover::server::testing {
namespace {

TEST_P(ApiTest, McppInputIsStoredNormalised) {
  const std::string mcpp = uavcover::testing::slurp(std::filesystem::path(UAVCOVER_SOURCE_DIR) / "examples" /
                                                    "mcpp-darp-input.json");
  const auto id = create_mission(mcpp);
  const Answer a = call("GET", "/api/v1/missions/" + std::to_string(id));
  ASSERT_EQ(a.status, 200);
  const nlohmann::json m = a.json();
  EXPECT_EQ(m.at("source"), nlohmann::json::parse(mcpp));
  // the normalised document is a uavcover v1 mission the parser reads back to the same document
  const std::string normalised = m.at("mission").dump();
  EXPECT_EQ(mission_to_json(parse_mission(normalised)), mission_to_json(parse_mission(mcpp)));
  EXPECT_EQ(call("POST", "/api/v1/missions/" + std::to_string(id) + "/plans").status, 202);
}

}  // namespace
}  // namespace uavcover::server::testing

namespace uavcover::server::testing {
INSTANTIATE_TEST_SUITE_P(Stores, ApiTest, ::testing::ValuesIn(uavcover::testing::store_test_urls()),
                         backend_name);
}  // namespace uavcover::server::testing

namespace uavcover::server::testing {
namespace {

// The server parses missions with the library's parser (issue 32, docs/wind.md): a wind and shares
// "auto" come back normalised; a wind the UAVs cannot fly against and an unknown share word are 422
// naming the field.
TEST_P(ApiTest, WindAndAutoSharesAreParsedAsTheLibraryDoes) {
  json doc = json::parse(olive_grove());
  doc["wind"] = {{"speed_mps", 3}, {"from_deg", 250}};
  for (auto& u : doc["uavs"]) u.erase("share");
  doc["shares"] = "capability";
  const Answer ok = call("POST", "/api/v1/missions/validate", doc.dump());
  ASSERT_EQ(ok.status, 200) << ok.body;
  const json m = ok.json()["mission"];
  EXPECT_EQ(m["wind"]["speed_mps"], 3.0);
  EXPECT_EQ(m["wind"]["from_deg"], 250.0);
  for (const auto& u : m["uavs"]) EXPECT_EQ(u["share"], "auto") << u.dump();

  json strong = doc;
  strong["wind"]["speed_mps"] = 5;  // alpha flies at 5 m/s
  const Answer a = call("POST", "/api/v1/missions/validate", strong.dump());
  EXPECT_EQ(a.status, 422);
  EXPECT_EQ(a.error_field(), "wind.speed_mps");
  json word = json::parse(olive_grove());
  word["uavs"][1]["share"] = "most";
  const Answer b = call("POST", "/api/v1/missions/validate", word.dump());
  EXPECT_EQ(b.status, 422);
  EXPECT_EQ(b.error_field(), "uavs[1].share");
}

}  // namespace
}  // namespace uavcover::server::testing
