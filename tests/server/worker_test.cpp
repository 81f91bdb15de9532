// Jobs run end to end through a WorkerPool on a real store: a plan equal to the CLI's for the same
// mission and seed, its artifacts served, and a long plan cancelled through DELETE.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <thread>

#include "server/worker_fixture.hpp"

namespace uavcover::server::testing {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

/// Drops the keys whose values depend on the machine's speed.
void drop_timings(json& j) {
  if (j.is_object()) {
    j.erase("compute_time_s");
    for (auto& [k, v] : j.items()) drop_timings(v);
  } else if (j.is_array()) {
    for (auto& v : j) drop_timings(v);
  }
}

TEST_P(WorkerTest, PlanJobEqualsTheCliPlanAndServesItsArtifacts) {
  const auto mission_id = create_mission(olive_grove());
  Answer a = call("POST", "/api/v1/missions/" + std::to_string(mission_id) + "/plans", R"({"seed": 7})");
  ASSERT_EQ(a.status, 202) << a.body;
  const std::string url = "/api/v1/plans/" + std::to_string(a.json().at("id").get<store::Id>());
  start_workers();
  const json job = wait_job(url, terminal);
  ASSERT_EQ(job.at("state"), "done") << job.dump();
  EXPECT_EQ(job.at("attempts"), 1);
  EXPECT_DOUBLE_EQ(job.at("progress").get<double>(), 1.0);
  EXPECT_TRUE(job.at("error").is_null());
  EXPECT_FALSE(job.at("finished").is_null());
  EXPECT_FALSE(job.at("metrics").empty()) << job.dump();
  pool_->stop();
  EXPECT_EQ(plans_done_, 1);

  std::map<std::string, json> artifacts;
  for (const auto& art : job.at("artifacts")) artifacts[art.at("name")] = art;
  for (const char* name :
       {"plan.json", "paths.geojson", "plan.png", "plan.svg", "heatmap.png", "histogram.png"})
    ASSERT_TRUE(artifacts.contains(name)) << name << " missing in " << job.at("artifacts").dump();
  EXPECT_EQ(artifacts["plan.png"].at("url"), url + "/images/plan.png");
  EXPECT_EQ(artifacts["plan.json"].at("url"), url + "/plan.json");

  a = call("GET", url + "/plan.json");
  ASSERT_EQ(a.status, 200);
  EXPECT_EQ(a.content_type, "application/json");
  EXPECT_EQ(static_cast<std::int64_t>(a.body.size()), artifacts["plan.json"].at("size").get<std::int64_t>());
  json api_plan = json::parse(a.body);

  a = call("GET", url + "/paths.geojson");
  ASSERT_EQ(a.status, 200);
  EXPECT_EQ(json::parse(a.body).at("type"), "FeatureCollection");
  a = call("GET", url + "/images/plan.png");
  ASSERT_EQ(a.status, 200);
  EXPECT_EQ(a.content_type, "image/png");
  EXPECT_EQ(a.body.substr(0, 4), "\x89PNG");
  EXPECT_EQ(call("GET", url + "/images/other.png").status, 404);

  // three UAVs fly: an export needs ?uav=
  a = call("GET", url + "/exports/qgc");
  EXPECT_EQ(a.status, 422) << a.body;
  EXPECT_EQ(a.error_field(), "uav");
  EXPECT_NE(a.body.find("alpha"), std::string::npos);
  a = call("GET", url + "/exports/qgc?uav=alpha");
  ASSERT_EQ(a.status, 200) << a.body;
  const std::string disposition = a.header("Content-Disposition");
  EXPECT_TRUE(disposition.starts_with("attachment; filename=\"")) << disposition;
  EXPECT_NE(disposition.find("alpha"), std::string::npos) << disposition;
  EXPECT_EQ(disposition.find('/'), std::string::npos) << disposition;
  EXPECT_EQ(call("GET", url + "/exports/qgc?uav=nobody").status, 404);
  a = call("GET", url + "/exports/trajectory?uav=bravo");
  ASSERT_EQ(a.status, 200) << a.body;
  EXPECT_EQ(a.header("Content-Disposition"), "attachment; filename=\"trajectory_bravo.csv\"");
  for (const auto& [name, art] : artifacts)
    if (art.at("url").is_string() && name.starts_with("export/")) {
      EXPECT_EQ(call("GET", art["url"].get<std::string>()).status, 200) << name;
    }

  // the CLI plans the same mission with the same seed into the same plan.json
  const auto out = dir_ / "cli";
  const auto mission_file = dir_ / "mission.json";
  {
    std::ofstream f(mission_file);
    f << olive_grove();
  }
  const std::string cmd = std::string("\"") + UAVCOVER_CLI + "\" plan \"" + mission_file.string() +
                          "\" --out \"" + out.string() + "\" --seed 7 --quiet";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  json cli_plan = json::parse(uavcover::testing::slurp(out / "plan.json"));
  drop_timings(api_plan);
  drop_timings(cli_plan);
  EXPECT_EQ(api_plan, cli_plan) << nlohmann::json::diff(cli_plan, api_plan).dump(1).substr(0, 4000);
}

TEST_P(WorkerTest, TrajectoryExportsTakeTheMethodFromTheQuery) {
  // issue 33: ?method=polynomial&order=&v_mean=&v_min=&a_min= on the trajectory and trajectory_plot routes
  const json job =
      call("POST", "/api/v1/missions/" + std::to_string(create_mission(olive_grove())) + "/plans").json();
  const std::string url = "/api/v1/plans/" + std::to_string(job.at("id").get<store::Id>());
  start_workers();
  ASSERT_EQ(wait_job(url, terminal).at("state"), "done");
  Answer a = call("GET", url + "/exports/trajectory?uav=alpha");
  ASSERT_EQ(a.status, 200) << a.body;
  EXPECT_TRUE(a.body.starts_with("t,kind,")) << a.body.substr(0, 80);  // the segment form
  a = call("GET", url + "/exports/trajectory?uav=alpha&method=polynomial&order=7&v_mean=3&v_min=-4&a_min=-1");
  ASSERT_EQ(a.status, 200) << a.body;
  EXPECT_TRUE(a.body.starts_with("t,x,y,z,lat,lon,vx,vy,vz,ax,ay,az\n0.000000,")) << a.body.substr(0, 80);
  a = call("GET", url + "/exports/trajectory_plot?uav=alpha&method=polynomial");
  ASSERT_EQ(a.status, 200) << a.body;
  EXPECT_EQ(a.content_type, "image/png");
  EXPECT_EQ(a.body.substr(0, 4), "\x89PNG");
  // malformed: 400 naming the parameter; a mean speed above alpha's 5 m/s: 422 naming it
  for (const char* q : {"method=spline", "order=4", "order=x", "v_mean=-1", "v_min=0", "a_min=1"}) {
    a = call("GET", url + "/exports/trajectory?uav=alpha&method=polynomial&" + q);
    EXPECT_EQ(a.status, 400) << q << ": " << a.body;
    EXPECT_EQ(a.error_field(), std::string(q).substr(0, std::string(q).find('='))) << q;
  }
  a = call("GET", url + "/exports/trajectory?uav=alpha&method=polynomial&v_mean=5.5");
  EXPECT_EQ(a.status, 422) << a.body;
  EXPECT_EQ(a.error_field(), "v_mean");
  pool_->stop();
}

TEST_P(WorkerTest, CancellingARunningPlanStopsIt) {
  // the olive grove scanned every 1.5 m: DARP needs far longer than the test waits
  json doc = json::parse(olive_grove());
  doc.erase("camera");
  doc["spacing_m"] = 1.5;
  const auto mission_id = create_mission(doc.dump());
  Answer a = call("POST", "/api/v1/missions/" + std::to_string(mission_id) + "/plans", "{}");
  ASSERT_EQ(a.status, 202) << a.body;
  const std::string url = "/api/v1/plans/" + std::to_string(a.json().at("id").get<store::Id>());
  start_workers();
  json job = wait_job(url, [](const json& j) { return j.at("state") != "queued"; });
  ASSERT_EQ(job.at("state"), "running") << job.dump();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // let it get into the planner

  const auto t0 = Clock::now();
  a = call("DELETE", url);
  ASSERT_EQ(a.status, 200) << a.body;
  EXPECT_TRUE(a.json().at("cancel_requested").get<bool>() || a.json().at("state") == "cancelled") << a.body;
  job = wait_job(url, terminal, std::chrono::seconds(60));
  const double latency = std::chrono::duration<double>(Clock::now() - t0).count();
  EXPECT_EQ(job.at("state"), "cancelled") << job.dump();
  EXPECT_TRUE(job.at("artifacts").empty());
  RecordProperty("cancel_latency_s", std::to_string(latency));
  std::printf("cancelled %.3f s after DELETE\n", latency);
  EXPECT_EQ(plans_done_, 0);
}

TEST_P(WorkerTest, ShutdownLeavesARunningJobForTheNextLease) {
  json doc = json::parse(olive_grove());
  doc.erase("camera");
  doc["spacing_m"] = 1.5;
  const auto mission_id = create_mission(doc.dump());
  Answer a = call("POST", "/api/v1/missions/" + std::to_string(mission_id) + "/plans", "{}");
  ASSERT_EQ(a.status, 202) << a.body;
  const auto job_id = a.json().at("id").get<store::Id>();
  const std::string url = "/api/v1/plans/" + std::to_string(job_id);
  start_workers();
  ASSERT_EQ(wait_job(url, [](const json& j) { return j.at("state") != "queued"; }).at("state"), "running");
  pool_->stop();
  json job = call("GET", url).json();
  EXPECT_EQ(job.at("state"), "running") << job.dump();  // not cancelled: its lease runs out
  EXPECT_FALSE(job.at("cancel_requested").get<bool>());
  EXPECT_EQ(store_->recover_running(3), 1);
  EXPECT_EQ(call("GET", url).json().at("state"), "queued");
}

}  // namespace
}  // namespace uavcover::server::testing

namespace uavcover::server::testing {
namespace {

TEST_P(WorkerTest, StudyAndComparisonJobsServeTheirArtifacts) {
  const auto mission_id = create_mission(olive_grove());
  const std::string base = "/api/v1/missions/" + std::to_string(mission_id);
  Answer a = call("POST", base + "/studies", R"({"uavs": "1..2", "seed": 3})");
  ASSERT_EQ(a.status, 202) << a.body;
  EXPECT_EQ(a.json().at("kind"), "study");
  const std::string study = "/api/v1/studies/" + std::to_string(a.json().at("id").get<store::Id>());
  a = call("POST", base + "/comparisons", R"({"planners": ["darp", "boustrophedon"], "seed": 3})");
  ASSERT_EQ(a.status, 202) << a.body;
  const std::string comparison = "/api/v1/comparisons/" + std::to_string(a.json().at("id").get<store::Id>());
  EXPECT_EQ(call("GET", study + "/study.json").status, 409);
  start_workers();

  json job = wait_job(study, terminal);
  ASSERT_EQ(job.at("state"), "done") << job.dump();
  a = call("GET", study + "/study.json");
  ASSERT_EQ(a.status, 200) << a.body;
  EXPECT_EQ(a.content_type, "application/json");
  EXPECT_TRUE(json::parse(a.body).is_object());
  a = call("GET", study + "/study.png");
  ASSERT_EQ(a.status, 200);
  EXPECT_EQ(a.body.substr(0, 4), "\x89PNG");
  for (const auto& art : job.at("artifacts")) EXPECT_TRUE(art.at("url").is_string()) << art.dump();

  job = wait_job(comparison, terminal);
  ASSERT_EQ(job.at("state"), "done") << job.dump();
  for (const char* name : {"compare.json", "compare.md", "compare.png"})
    EXPECT_EQ(call("GET", comparison + "/" + name).status, 200) << name;
  EXPECT_EQ(call("GET", comparison + "/plan.json").status, 404);
  EXPECT_EQ(call("GET", "/api/v1/plans/" + job.at("id").dump()).status, 404);
}

TEST_P(WorkerTest, AJobThePlannerRefusesFailsNamingTheField) {
  // 70 separate no-fly zones: more than the boustrophedon planner plans around
  json doc = json::parse(olive_grove());
  doc["no_fly_zones"] = json::array();
  for (int i = 0; i < 10; ++i)
    for (int k = 0; k < 7; ++k) {
      const double lon = 22.9015 + i * 0.001, lat = 40.6012 + k * 0.0008;
      doc["no_fly_zones"].push_back({{"type", "Polygon"},
                                     {"coordinates",
                                      {{{lon, lat},
                                        {lon + 0.0001, lat},
                                        {lon + 0.0001, lat + 0.0001},
                                        {lon, lat + 0.0001},
                                        {lon, lat}}}}});
    }
  const auto mission_id = create_mission(doc.dump());
  Answer a = call("POST", "/api/v1/missions/" + std::to_string(mission_id) + "/plans",
                  R"({"planner": "boustrophedon"})");
  ASSERT_EQ(a.status, 202) << a.body;
  const std::string url = "/api/v1/plans/" + std::to_string(a.json().at("id").get<store::Id>());
  start_workers();
  const json job = wait_job(url, terminal);
  ASSERT_EQ(job.at("state"), "failed") << job.dump().substr(0, 2000);
  EXPECT_EQ(job.at("error").at("field"), "no_fly_zones");
  EXPECT_NE(job.at("error").at("message").get<std::string>().find("64"), std::string::npos);
  EXPECT_TRUE(job.at("artifacts").empty());
  EXPECT_EQ(call("GET", url + "/plan.json").status, 409);
  EXPECT_EQ(plans_done_, 0);
}

}  // namespace
}  // namespace uavcover::server::testing

namespace uavcover::server::testing {
// ---- exports on demand and retention (issue 27, docs/cache.md) ----

TEST_P(WorkerTest, ExportsAreMadeOnRequestOnceForConcurrentCallsAndEqualTheCliExports) {
  // every build waits at the hook until the test lets it go
  std::mutex m;
  std::condition_variable cv;
  bool go = false;
  export_config_.before_build = [&](const std::string&) {
    std::unique_lock lock(m);
    cv.wait(lock, [&] { return go; });
  };
  close();
  open();
  const auto [blobs0, bytes0] = store_->count_blobs();
  const auto mission_id = create_mission(olive_grove());
  Answer a = call("POST", "/api/v1/missions/" + std::to_string(mission_id) + "/plans", R"({"seed": 7})");
  ASSERT_EQ(a.status, 202) << a.body;
  const store::Id id = a.json().at("id").get<store::Id>();
  const std::string url = "/api/v1/plans/" + std::to_string(id);
  start_workers();
  const json job = wait_job(url, terminal);
  ASSERT_EQ(job.at("state"), "done") << job.dump();
  pool_->stop();
  for (const auto& art : job.at("artifacts"))
    EXPECT_FALSE(art.at("name").get<std::string>().starts_with("export/"))
        << "exports are not made by the job";
  EXPECT_EQ(exports_->builds(), 0);

  // four concurrent first requests of one export: one build, the same bytes
  const std::string key = store::plan_cache_prefix(store_->get_job(id)->artifacts) + "/qgc";
  std::vector<Answer> answers(4);
  std::vector<std::thread> callers;
  for (auto& answer : answers)
    callers.emplace_back([&] { answer = call("GET", url + "/exports/qgc?uav=alpha"); });
  while (exports_->waiting(key) < 4) std::this_thread::yield();  // all four wait for the one build
  EXPECT_EQ(exports_->builds(), 1);
  {
    std::lock_guard lock(m);
    go = true;
  }
  cv.notify_all();
  for (auto& t : callers) t.join();
  for (const auto& answer : answers) {
    ASSERT_EQ(answer.status, 200) << answer.body;
    EXPECT_EQ(answer.body, answers[0].body);
  }
  EXPECT_EQ(exports_->builds(), 1);
  EXPECT_TRUE(store_->cache_entry(key)) << "cached";
  EXPECT_EQ(call("GET", url + "/exports/qgc?uav=bravo").status, 200);
  EXPECT_EQ(exports_->builds(), 1) << "the other UAVs' files came with the same build";
  // the trajectory options do not change a .plan: the plain .plan's entry, no new build
  a = call("GET", url + "/exports/qgc?uav=alpha&method=polynomial");
  ASSERT_EQ(a.status, 200) << a.body;
  EXPECT_EQ(a.body, answers[0].body);
  EXPECT_EQ(exports_->builds(), 1) << "the trajectory method is not in a .plan's cache key";

  // every format of every UAV: the bytes of the CLI's eager export of the same mission and seed
  const auto out = dir_ / "cli";
  const auto mission_file = dir_ / "mission.json";
  {
    std::ofstream f(mission_file);
    f << olive_grove();
  }
  const std::string cmd = std::string("\"") + UAVCOVER_CLI + "\" plan \"" + mission_file.string() +
                          "\" --out \"" + out.string() +
                          "\" --seed 7 --quiet --export geojson,qgc,wpl,kml,dji,litchi,csv,trajectory";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const std::map<std::string, std::string> files{
      {"qgc", "export/{}.plan"},        {"wpl", "export/{}.waypoints"},     {"kml", "export/{}.kml"},
      {"dji", "export/{}.wpml.kmz"},    {"litchi", "export/{}.litchi.csv"}, {"csv", "export/{}.csv"},
      {"geojson", "export/{}.geojson"}, {"trajectory", "trajectory/{}.csv"}};
  int compared = 0;
  for (const char* uav : {"alpha", "bravo", "charlie"})
    for (const auto& [format, pattern] : files) {
      std::string file = pattern;
      file.replace(file.find("{}"), 2, uav);
      a = call("GET", url + "/exports/" + format + "?uav=" + uav);
      ASSERT_EQ(a.status, 200) << format << " " << uav << ": " << a.body;
      EXPECT_TRUE(a.body == uavcover::testing::slurp(out / file)) << file << " differs from the CLI's";
      ++compared;
    }
  EXPECT_EQ(compared, 24);
  a = call("GET", url + "/exports/kmz?uav=alpha");
  ASSERT_EQ(a.status, 200) << a.body;
  EXPECT_EQ(a.body.substr(0, 2), "PK");

  // a plan a flight uses cannot be deleted; once its flight is gone it is, with its cache and blobs
  store::NewFlight nf;
  nf.plan_id = id;
  const store::Id flight = store_->create_flight(nf);
  a = call("DELETE", url);
  EXPECT_EQ(a.status, 409) << a.body;
  EXPECT_EQ(a.error_field(), "id");
  store_->delete_flight(flight);
  a = call("DELETE", url);
  EXPECT_EQ(a.status, 204) << a.body;
  EXPECT_EQ(call("GET", url).status, 404);
  EXPECT_EQ(call("GET", url + "/exports/qgc?uav=alpha").status, 404);
  EXPECT_FALSE(store_->cache_entry(key)) << "its exports are gone";
  EXPECT_EQ(store_->count_blobs(), std::make_pair(blobs0, bytes0)) << "and every blob of its own";
}

INSTANTIATE_TEST_SUITE_P(Stores, WorkerTest, ::testing::ValuesIn(uavcover::testing::store_test_urls()),
                         backend_name);
}  // namespace uavcover::server::testing
