// Jobs as the server runs them: parameter validation, plan/study/comparison results and artifacts,
// export lookup, catalog references, cancellation.
#include <gtest/gtest.h>

#include <set>
#include <stop_token>
#include <thread>

#include "export/export.hpp"
#include "support/files.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/jobs.hpp"
#include "usecases/plan_outputs.hpp"

using namespace uavcover;
using nlohmann::json;
using usecases::JobType;

namespace {

Mission rectangle() {
  return parse_mission(uavcover::testing::slurp(std::filesystem::path(UAVCOVER_BENCH_DATA) /
                                                "mondinelli2025" / "rectangle_3uav.json"));
}

std::string field_of(JobType t, const Mission& m, const json& params) {
  try {
    (void)usecases::validate_job_params(t, m, params);
  } catch (const InputError& e) {
    return e.field();
  }
  return "(accepted)";
}

std::set<std::string> names(const Artifacts& artifacts) {
  std::set<std::string> out;
  for (const auto& a : artifacts) out.insert(a.name);
  return out;
}

}  // namespace

TEST(JobParams, DefaultsAreFilledAndBadOnesNamed) {
  const Mission m = rectangle();
  const json p = usecases::validate_job_params(JobType::Plan, m, nullptr);
  EXPECT_EQ(p.at("planner"), m.planner);
  EXPECT_EQ(p.at("planner_params"), m.planner_params);
  const json b = usecases::validate_job_params(JobType::Plan, m, {{"planner", "boustrophedon"}, {"seed", 3}});
  EXPECT_EQ(b.at("planner"), "boustrophedon");
  EXPECT_TRUE(b.at("planner_params").is_object());

  EXPECT_EQ(field_of(JobType::Plan, m, json::array()), "body");
  EXPECT_EQ(field_of(JobType::Plan, m, {{"planer", "darp"}}), "planer");
  EXPECT_EQ(field_of(JobType::Plan, m, {{"planner", "nope"}}), "planner");
  EXPECT_EQ(field_of(JobType::Plan, m, {{"planner", 3}}), "planner");
  EXPECT_EQ(field_of(JobType::Plan, m, {{"seed", -1}}), "seed");
  EXPECT_EQ(field_of(JobType::Plan, m, {{"seed", 1.5}}), "seed");
  EXPECT_EQ(field_of(JobType::Plan, m, {{"time_limit_s", 0}}), "time_limit_s");
  EXPECT_EQ(field_of(JobType::Plan, m, {{"time_limit_s", 1e9}}), "time_limit_s");
  EXPECT_EQ(field_of(JobType::Plan, m, {{"planner_params", {{"bogus", 1}}}}), "planner_params.bogus");
  EXPECT_EQ(field_of(JobType::Plan, m, {{"trajectory_step_s", 0}}), "trajectory_step_s");
  EXPECT_EQ(field_of(JobType::Plan, m, {{"trajectory_step_s", 61}}), "trajectory_step_s");
  EXPECT_EQ(field_of(JobType::Plan, m, {{"trajectory_step_s", "0.1"}}), "trajectory_step_s");
  EXPECT_EQ(field_of(JobType::Plan, m, {{"trajectory_step_s", 0.5}}), "(accepted)");
  EXPECT_EQ(field_of(JobType::Study, m, json::object()), "uavs");
  EXPECT_EQ(field_of(JobType::Study, m, {{"uavs", "0..3"}}), "uavs");
  EXPECT_EQ(field_of(JobType::Study, m, {{"uavs", "1..3"}}), "(accepted)");
  EXPECT_EQ(field_of(JobType::Comparison, m, {{"planners", json::array()}}), "planners");
  EXPECT_EQ(field_of(JobType::Comparison, m, {{"planners", {"darp", "x"}}}), "planners[1]");
  EXPECT_EQ(field_of(JobType::Comparison, m, {{"planners", {"darp"}}}), "(accepted)");
}

TEST(Jobs, PlanJobGivesTheCliArtifactsEveryExportAndMetrics) {
  const Mission m = rectangle();
  const json params = usecases::validate_job_params(JobType::Plan, m, {{"seed", 7}});
  std::vector<double> progress;
  const Context ctx([&](std::string_view, double f) { progress.push_back(f); });
  const auto r = usecases::run_job(JobType::Plan, m, params, ctx);
  const auto got = names(r.artifacts);
  for (const char* n : {"plan.json", "paths.geojson", "evaluation.json", "plan.png", "plan.svg",
                        "heatmap.png", "histogram.png"})
    EXPECT_TRUE(got.count(n)) << n;
  // what a plan is, not its exports: those are made from plan.json and paths.geojson on request
  for (const auto& n : got) EXPECT_FALSE(n.starts_with("export/") || n.starts_with("trajectory/")) << n;
  auto bytes_of = [&](const std::string& name) {
    for (const auto& a : r.artifacts)
      if (a.name == name) return a.bytes;
    return std::string();
  };
  std::vector<std::string> exported;
  for (const auto& f : exporting::known_formats())
    for (const auto& file : usecases::build_export(bytes_of("plan.json"), bytes_of("paths.geojson"), f).files)
      exported.push_back(file.name);
  // every route of the server (the table's formats and kmz) finds each UAV's file among them, and every
  // file made is served by a route
  std::set<std::string> served;
  for (const auto& u : m.uavs)
    for (const auto& route : usecases::export_routes()) {
      const auto name = usecases::export_artifact_name(exported, route.name, u.id);
      EXPECT_TRUE(name.has_value()) << route.name << " " << u.id;
      if (name) served.insert(*name);
    }
  for (const auto& n : exported) EXPECT_TRUE(served.count(n)) << n << " is served by no route";
  EXPECT_EQ(r.result.at("seed"), 7);
  EXPECT_EQ(r.result.at("uavs").size(), m.uavs.size());
  EXPECT_GT(r.result.at("metrics").at("poc").get<double>(), 0.9);
  EXPECT_GT(r.result.at("metrics").at("turns").get<int>(), 0);
  ASSERT_FALSE(progress.empty());
  EXPECT_LE(*std::max_element(progress.begin(), progress.end()), 1.0);
  EXPECT_GE(progress.back(), 0.95) << "the pictures report in the last part of the job";
  EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end())) << "the job's progress never goes back";

  // the same plan.json as the CLI's plan command for the same mission and seed (but compute time)
  Mission seeded = m;
  PlanOptions po;
  po.seed = 7;
  const auto cli = usecases::plan_outputs(plan(seeded, po), {});
  auto strip = [](json j) {
    j.at("totals").erase("compute_time_s");
    return j;
  };
  const auto find = [](const Artifacts& as, const std::string& n) {
    for (const auto& a : as)
      if (a.name == n) return json::parse(a.bytes);
    return json();
  };
  EXPECT_EQ(strip(find(r.artifacts, "plan.json")).dump(), strip(find(cli.artifacts, "plan.json")).dump());
  const json ev = find(r.artifacts, "evaluation.json");
  EXPECT_TRUE(ev.contains("coverage") && ev.contains("cost"));
}

// Issue 30: a structure scan's job reports the wall's coverage (the plans list shows it: its ground PoC
// says nothing of the facade), and a plan of an area has no such figure.
TEST(Jobs, AStructureScanJobReportsTheWallsCoverage) {
  const Mission m = parse_mission(R"({
    "structure": {"footprint": {"type": "Polygon", "coordinates": [[[10.0, 45.0], [10.00038, 45.0],
                  [10.00038, 45.00027], [10.0, 45.00027], [10.0, 45.0]]]},
                  "height_m": 20, "standoff_m": 12},
    "camera": {"altitude_m": 20, "sensor_width_mm": 13.2, "focal_length_mm": 8.8, "image_width_px": 5472,
               "image_height_px": 3648, "side_overlap": 0.7, "front_overlap": 0.8},
    "uavs": [{"id": "a"}], "planner": "boustrophedon"})");
  const auto r =
      usecases::run_job(JobType::Plan, m, usecases::validate_job_params(JobType::Plan, m, {{"seed", 1}}), {});
  const json& metrics = r.result.at("metrics");
  ASSERT_TRUE(metrics.contains("facade_poc")) << metrics.dump();
  const double seen = metrics.at("facade_poc").get<double>(),
               three = metrics.at("facade_3plus").get<double>();
  EXPECT_GT(seen, 0.9);
  EXPECT_LE(seen, 1.0);
  EXPECT_GE(three, 0.0);
  EXPECT_LE(three, seen);
  const Mission area = rectangle();
  const auto flat = usecases::run_job(JobType::Plan, area,
                                      usecases::validate_job_params(JobType::Plan, area, {{"seed", 1}}), {});
  EXPECT_FALSE(flat.result.at("metrics").contains("facade_poc"));
}

TEST(Jobs, StudyAndComparisonJobs) {
  const Mission m = rectangle();
  const auto s = usecases::run_job(JobType::Study, m,
                                   usecases::validate_job_params(JobType::Study, m, {{"uavs", "1..2"}}), {});
  EXPECT_EQ(names(s.artifacts), (std::set<std::string>{"study.json", "study.png"}));
  const auto c =
      usecases::run_job(JobType::Comparison, m,
                        usecases::validate_job_params(JobType::Comparison, m, {{"planners", {"darp"}}}), {});
  EXPECT_EQ(names(c.artifacts), (std::set<std::string>{"compare.json", "compare.md", "compare.png"}));
  EXPECT_EQ(c.result.at("planners").size(), 1u);
}

TEST(Jobs, AStopRequestCancelsAPlanJob) {
  const Mission m = rectangle();
  std::stop_source stop;
  stop.request_stop();
  const json params = usecases::validate_job_params(JobType::Plan, m, nullptr);
  EXPECT_THROW(usecases::run_job(JobType::Plan, m, params, Context({}, stop.get_token())), Cancelled);
}

TEST(Jobs, ExportNamesPickTheRightFile) {
  const std::vector<std::string> one{"export/a.plan",      "export/a.kml",          "export/a.kmz",
                                     "export/a.wpml.kmz",  "export/a.1.litchi.csv", "export/a.2.litchi.csv",
                                     "export/a.litchi.zip"};
  EXPECT_EQ(usecases::export_artifact_name(one, "qgc", ""), "export/a.plan");
  EXPECT_EQ(usecases::export_artifact_name(one, "kmz", ""), "export/a.kmz");
  EXPECT_EQ(usecases::export_artifact_name(one, "dji", "a"), "export/a.wpml.kmz");
  EXPECT_EQ(usecases::export_artifact_name(one, "litchi", "a"), "export/a.litchi.zip");
  EXPECT_EQ(usecases::export_artifact_name(one, "litchi", ""), "export/a.litchi.zip");
  EXPECT_FALSE(usecases::export_artifact_name(one, "wpl", "a"));
  EXPECT_FALSE(usecases::export_artifact_name(one, "qgc", "b"));
  EXPECT_FALSE(usecases::export_artifact_name(one, "exe", "a"));
  const std::vector<std::string> two{"export/a.plan", "export/b.plan"};
  EXPECT_FALSE(usecases::export_artifact_name(two, "qgc", "")) << "two UAVs: the caller must name one";
  EXPECT_EQ(usecases::export_artifact_name(two, "qgc", "b"), "export/b.plan");
}

TEST(Jobs, CatalogReferencesFillWhatTheMissionLeavesOut) {
  const json uav_entry = {{"name", "P4"}, {"speed_mps", 10}, {"max_accel_mps2", 4}, {"endurance_min", 28}};
  const json cam_entry = {{"name", "P4 cam"},
                          {"sensor_width_mm", 13.2},
                          {"focal_length_mm", 8.8},
                          {"image_width_px", 5472},
                          {"hfov_deg", 73.7}};
  auto uavs = [&](long long id) -> std::optional<json> {
    if (id == 1) return uav_entry;
    return std::nullopt;
  };
  auto cams = [&](long long id) -> std::optional<json> {
    if (id == 2) return cam_entry;
    return std::nullopt;
  };
  json doc = {{"uavs", {{{"id", "a"}, {"catalog_id", 1}, {"speed_mps", 6}}, {{"id", "b"}}}},
              {"camera", {{"catalog_id", 2}, {"altitude_m", 60}, {"side_overlap", 0.3}}}};
  const json r = usecases::resolve_catalog_refs(doc, uavs, cams);
  EXPECT_EQ(r["uavs"][0]["speed_mps"], 6) << "the mission's own value wins";
  EXPECT_EQ(r["uavs"][0]["endurance_min"], 28);
  EXPECT_FALSE(r["uavs"][0].contains("catalog_id"));
  EXPECT_FALSE(r["uavs"][1].contains("speed_mps"));
  EXPECT_EQ(r["camera"]["image_width_px"], 5472);
  EXPECT_FALSE(r["camera"].contains("hfov_deg")) << "QGC convention: sensor fields only";
  json paper = {{"camera", {{"catalog_id", 2}, {"altitude_m", 60}, {"overlap", 0.5}}}};
  EXPECT_EQ(usecases::resolve_catalog_refs(paper, uavs, cams)["camera"]["hfov_deg"], 73.7);
  auto field = [&](const json& d) {
    try {
      (void)usecases::resolve_catalog_refs(d, uavs, cams);
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(field({{"uavs", {{{"catalog_id", 9}}}}}), "uavs[0].catalog_id");
  EXPECT_EQ(field({{"uavs", {{{"catalog_id", "1"}}}}}), "uavs[0].catalog_id");
  EXPECT_EQ(field({{"uavs", {{{"catalog_id", -1}}}}}), "uavs[0].catalog_id");
  EXPECT_EQ(field({{"camera", {{"catalog_id", 1}}}}), "camera.catalog_id");
}

TEST(Jobs, ACatalogUavsCameraBecomesItsOwnCameraAtTheMissionsAltitude) {
  const json cam2 = {{"name", "wide"},
                     {"sensor_width_mm", 13.2},
                     {"focal_length_mm", 8.8},
                     {"image_width_px", 5472},
                     {"hfov_deg", 73.7}};
  const json cam4 = {{"name", "narrow"},
                     {"sensor_width_mm", 6.3},
                     {"focal_length_mm", 9.0},
                     {"image_width_px", 4000},
                     {"hfov_deg", 38.6}};
  auto uavs = [&](long long id) -> std::optional<json> {
    if (id == 1)
      return json{{"name", "with wide"}, {"speed_mps", 8}, {"endurance_min", 30}, {"camera_id", 2}};
    if (id == 3)
      return json{{"name", "with narrow"}, {"speed_mps", 8}, {"endurance_min", 30}, {"camera_id", 4}};
    return std::nullopt;
  };
  auto cams = [&](long long id) -> std::optional<json> {
    if (id == 2) return cam2;
    if (id == 4) return cam4;
    return std::nullopt;
  };
  const json own_block = {{"altitude_m", 60}, {"hfov_deg", 50}, {"overlap", 0.4}};
  json doc = {
      {"uavs",
       {{{"id", "a"}, {"catalog_id", 1}},
        {{"id", "b"}, {"catalog_id", 3}},
        {{"id", "c"}, {"catalog_id", 3}, {"camera", own_block}}}},
      {"camera", {{"catalog_id", 2}, {"altitude_m", 60}, {"side_overlap", 0.3}, {"front_overlap", 0.7}}}};
  const json r = usecases::resolve_catalog_refs(doc, uavs, cams);
  EXPECT_FALSE(r["uavs"][0].contains("camera")) << "a carries the mission's camera";
  ASSERT_TRUE(r["uavs"][1].contains("camera")) << r.dump();
  const json& b = r["uavs"][1]["camera"];
  EXPECT_EQ(b["altitude_m"], 60);
  EXPECT_EQ(b["side_overlap"], 0.3);
  EXPECT_EQ(b["front_overlap"], 0.7);
  EXPECT_EQ(b["image_width_px"], 4000);
  EXPECT_EQ(b["focal_length_mm"], 9.0);
  EXPECT_FALSE(b.contains("hfov_deg")) << "the mission's (QGC) convention";
  EXPECT_EQ(r["uavs"][2]["camera"], own_block) << "a UAV's own camera block wins";

  // the paper's convention: the catalog camera's HFOV
  json paper = doc;
  paper["camera"] = {{"catalog_id", 2}, {"altitude_m", 50}, {"overlap", 0.5}};
  const json p = usecases::resolve_catalog_refs(paper, uavs, cams);
  EXPECT_EQ(p["uavs"][1]["camera"], (json{{"altitude_m", 50}, {"overlap", 0.5}, {"hfov_deg", 38.6}}));

  // a mission without a camera block (spacing given) has no camera to share: the UAVs get none
  json spaced = {{"spacing_m", 20}, {"uavs", {{{"catalog_id", 3}}}}};
  EXPECT_FALSE(usecases::resolve_catalog_refs(spaced, uavs, cams)["uavs"][0].contains("camera"));
}

TEST(Jobs, APlanJobsTrajectoryIsTheSegmentFormOrSampledAtItsStep) {
  const Mission m = rectangle();
  auto trajectory_of = [&](const json& given) {
    const auto r =
        usecases::run_job(JobType::Plan, m, usecases::validate_job_params(JobType::Plan, m, given), {});
    // a plan job stores no exports: the trajectory is made on request from the stored plan, with the
    // job's trajectory_step_s (0 = the segment form)
    std::string plan_json, paths;
    for (const auto& a : r.artifacts) {
      if (a.name == "plan.json") plan_json = a.bytes;
      if (a.name == "paths.geojson") paths = a.bytes;
    }
    const double step = given.contains("trajectory_step_s") ? given["trajectory_step_s"].get<double>() : 0.0;
    const auto built = usecases::build_export(plan_json, paths, "trajectory", step);
    for (const auto& a : built.files)
      if (a.name == "trajectory/" + m.uavs[0].id + ".csv") return a.bytes;
    return std::string();
  };
  const std::string segments = trajectory_of({{"seed", 7}});
  EXPECT_TRUE(segments.starts_with("t,kind,x,y,z,lat,lon,vx,vy,vz,ax,ay,az,v_max,a_max\n"));
  const std::string sampled = trajectory_of({{"seed", 7}, {"trajectory_step_s", 0.5}});
  EXPECT_TRUE(sampled.starts_with("t,x,y,z,lat,lon,vx,vy,vz,ax,ay,az\n0.000000,"));
  EXPECT_NE(sampled.find("\n0.500000,"), std::string::npos);
  EXPECT_LT(segments.size(), sampled.size());
}
