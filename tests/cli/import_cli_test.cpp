// `uavcover import`: a zipped Shapefile in UTM (made by ogr2ogr at test time) to a mission file that
// `uavcover plan` then plans; exit 2 naming the field for bad files and options.
#include <gtest/gtest.h>

#include "cli/cli_support.hpp"
#include "support/vector_files.hpp"

namespace uavcover::testing {
namespace {

TEST(ImportCli, ShapefileToMissionAndPlan) {
  testvec::TempDir dir("cli");
  const auto zip = testvec::zipped_shapefile(dir.path, 32634);
  const auto out = dir.path / "mission.json";
  const auto tmpl = testvec::write_text(dir.path / "base.json", R"({"uavs": 2, "spacing_m": 40})");
  const RunResult r = run_cli("import '" + zip.string() + "' --out '" + out.string() + "' --template '" +
                              tmpl.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto m = read_json(out);
  EXPECT_EQ(m["name"], "North field");
  EXPECT_EQ(m["uavs"], 2);
  EXPECT_EQ(m["no_fly_zones"].size(), 2U);
  const RunResult plan = run_cli("plan '" + out.string() + "' --out '" + (dir.path / "plan").string() +
                                 "' --no-evaluate --no-images -q");
  EXPECT_EQ(plan.exit_code, 0) << plan.output;
  // without --out: the mission on standard output
  const RunResult stdout_run = run_cli("-q import '" + zip.string() + "'");
  ASSERT_EQ(stdout_run.exit_code, 0) << stdout_run.output;
  EXPECT_EQ(nlohmann::json::parse(stdout_run.output)["name"], "North field");
}

TEST(ImportCli, BadInputExitsTwoNamingTheField) {
  testvec::TempDir dir("cli_bad");
  const auto bow = testvec::write_text(dir.path / "bow.geojson", testvec::kBowTie);
  RunResult r = run_cli("import '" + bow.string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("file: layer 'bow', feature 1 ('Twisted'): invalid geometry"), std::string::npos)
      << r.output;
  const auto good = testvec::write_text(dir.path / "f.geojson", testvec::kFeatures);
  r = run_cli("import '" + good.string() + "' --layer roads");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("layer:"), std::string::npos) << r.output;
  r = run_cli("import '" + good.string() + "' --where 'name = \"x'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("area_where:"), std::string::npos) << r.output;
  r = run_cli("import '" + (dir.path / "none.kml").string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(std::filesystem::exists(dir.path / "out.json"));
}

}  // namespace
}  // namespace uavcover::testing
