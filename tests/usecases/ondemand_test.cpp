// Exports on demand (issue 27): every export format made from a plan job's stored plan.json and
// paths.geojson gives the bytes the job's eager export of the same plan gave, for several plans.
#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>

#include "export/export.hpp"
#include "export/zip.hpp"
#include "support/files.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/jobs.hpp"
#include "usecases/plan_outputs.hpp"

using namespace uavcover;
using nlohmann::json;

namespace {

json example(const std::string& file) {
  return json::parse(
      uavcover::testing::slurp(std::filesystem::path(UAVCOVER_SOURCE_DIR) / "examples" / file));
}

const Artifact* find(const Artifacts& as, const std::string& name) {
  for (const auto& a : as)
    if (a.name == name) return &a;
  return nullptr;
}

/// The missions of the test: no-fly zones, two planners, the mCPP input, five UAVs, and a dense field whose
/// Litchi missions split at 99 waypoints.
std::vector<std::pair<std::string, json>> missions() {
  std::vector<std::pair<std::string, json>> out;
  out.emplace_back("olive-grove darp", example("olive-grove.json"));
  json b = example("olive-grove.json");
  b["planner"] = "boustrophedon";
  out.emplace_back("olive-grove boustrophedon", b);
  // (a DEM mission is not planned by the server: it reads no DEM files)
  out.emplace_back("mcpp-darp-input", example("mcpp-darp-input.json"));
  json five = json::parse(uavcover::testing::slurp(std::filesystem::path(UAVCOVER_BENCH_DATA) /
                                                   "mondinelli2025" / "rectangle_3uav.json"));
  five["uavs"].push_back({{"id", "blue"}, {"speed_mps", 4}, {"endurance_min", 20}});
  five["uavs"].push_back({{"id", "white"}, {"speed_mps", 20}, {"endurance_min", 20}});  // clamped
  five["spacing_m"] = 4;  // > 99 waypoints per UAV: Litchi parts
  five["seed"] = 5;
  out.emplace_back("rectangle 5 UAVs dense", five);
  // one UAV over the olive grove at 12 m: more than 99 waypoints, so Litchi missions in parts (a zip)
  json grove = example("olive-grove.json");
  grove["uavs"] = json::array({grove["uavs"][0]});
  grove.erase("camera");
  grove["spacing_m"] = 12;
  out.emplace_back("olive grove 1 UAV at 12 m", grove);
  return out;
}

}  // namespace

TEST(ExportsOnDemand, EveryFormatIsByteIdenticalToTheEagerExport) {
  bool split_litchi = false;
  for (const auto& [label, doc] : missions()) {
    SCOPED_TRACE(label);
    const Plan p = plan(parse_mission(doc.dump()));
    // eager: what a plan job made before (every format, .kmz with each .kml, refusals as warnings)
    usecases::OutputOptions eager_options;
    eager_options.exports = exporting::known_formats();
    eager_options.kmz = true;
    eager_options.refused_exports_are_warnings = true;
    const auto eager = usecases::plan_outputs(p, eager_options);
    // stored: what a plan job stores now (no exports), then each format from its plan.json and
    // paths.geojson
    const auto stored = usecases::plan_outputs(p, {});
    for (const auto& a : stored.artifacts)
      EXPECT_FALSE(a.name.starts_with("export/") || a.name.starts_with("trajectory/")) << a.name;
    const Artifact* pj = find(stored.artifacts, "plan.json");
    const Artifact* pg = find(stored.artifacts, "paths.geojson");
    ASSERT_TRUE(pj && pg);
    EXPECT_EQ(pg->bytes, find(eager.artifacts, "paths.geojson")->bytes);
    std::size_t eager_exports = 0, compared = 0;
    for (const auto& a : eager.artifacts)
      if (a.name.starts_with("export/") || a.name.starts_with("trajectory/")) ++eager_exports;
    for (const auto& format : exporting::known_formats()) {
      SCOPED_TRACE(format);
      const auto built = usecases::build_export(pj->bytes, pg->bytes, format);
      EXPECT_TRUE(built.refused.empty()) << built.refused;
      EXPECT_FALSE(built.files.empty());
      std::map<std::string, std::map<std::string, std::string>> parts;  // Litchi parts per UAV
      for (const auto& f : built.files) {
        if (f.name.ends_with(".litchi.zip")) continue;
        const Artifact* e = find(eager.artifacts, f.name);
        ASSERT_NE(e, nullptr) << f.name << " was not exported eagerly";
        EXPECT_EQ(f.media_type, e->media_type) << f.name;
        EXPECT_TRUE(f.bytes == e->bytes)
            << f.name << " differs (" << f.bytes.size() << " vs " << e->bytes.size() << " bytes)";
        ++compared;
        const std::string stem = f.name.substr(7);
        if (f.name.ends_with(".litchi.csv") && std::count(stem.begin(), stem.end(), '.') == 3)
          parts[stem.substr(0, stem.find('.'))][stem] = f.bytes;
      }
      for (const auto& [id, files] : parts) {
        const Artifact* zip = find(built.files, "export/" + id + ".litchi.zip");
        ASSERT_NE(zip, nullptr) << id;
        EXPECT_EQ(zip->bytes, exporting::zip_bytes(files)) << id;
        split_litchi = true;
      }
      // the exporter's warnings are among the eager job's
      for (const auto& w : built.warnings)
        EXPECT_NE(std::find(eager.warnings.begin(), eager.warnings.end(), w), eager.warnings.end()) << w;
    }
    EXPECT_EQ(compared, eager_exports) << "every eager export file is made on demand";
    EXPECT_GT(compared, 0u);
  }
  EXPECT_TRUE(split_litchi) << "one plan's Litchi missions are split in parts (their zip is compared)";
}

TEST(ExportsOnDemand, AnUnreadableStoredPlanIsAnOperationError) {
  const Plan p = plan(parse_mission(example("olive-grove.json").dump()));
  const auto stored = usecases::plan_outputs(p, {});
  const Artifact* pj = find(stored.artifacts, "plan.json");
  const Artifact* pg = find(stored.artifacts, "paths.geojson");
  ASSERT_TRUE(pj && pg);
  EXPECT_THROW(usecases::build_export("{", pg->bytes, "qgc"), OperationError);
  EXPECT_THROW(usecases::build_export(pj->bytes, "[]", "qgc"), OperationError);
  EXPECT_EQ(usecases::export_source_format("kmz"), "kml");
  EXPECT_EQ(usecases::export_source_format("qgc"), "qgc");
}

// A cache of exports keys an entry by what its format reads: the trajectory method on a .plan, or a
// capacity split on the trajectory, makes the same files as without it.
TEST(ExportsOnDemand, AVariantKeepsOnlyWhatItsFormatReads) {
  usecases::ExportVariant v;
  v.autopilot = "ardupilot";
  v.split_capacity = true;
  v.trajectory.method = trajectory::Method::Polynomial;
  v.trajectory.order = 5;
  EXPECT_EQ(v.for_format("qgc").key(), "@autopilot=ardupilot@split_capacity");
  EXPECT_EQ(v.for_format("trajectory").key(), "@autopilot=ardupilot@method=polynomial@order=5");
  EXPECT_EQ(v.for_format("trajectory_plot").key(), v.for_format("trajectory").key());
  EXPECT_EQ(v.for_format("geojson").key(), "@autopilot=ardupilot");
  EXPECT_EQ(v.for_format("kml").key(), v.for_format("qgc").key());
}
