// `uavcover export` end to end: plan a mission with the CLI, export it, check files and exit codes.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "support/files.hpp"

namespace fs = std::filesystem;
using uavcover::testing::slurp;

namespace {

int run(const std::string& cmd) {
  const int st = std::system(cmd.c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

}  // namespace

TEST(ExportCli, PlanThenExportEveryFormat) {
  const fs::path dir = fs::temp_directory_path() / ("uavcover_export_cli_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "mission.json") << R"({
    "name": "cli export",
    "area": {"type": "Polygon", "coordinates": [[[8.5440, 47.3970], [8.5470, 47.3970], [8.5470, 47.3982],
                                                  [8.5440, 47.3982], [8.5440, 47.3970]]]},
    "spacing_m": 15,
    "uavs": [{"id": "a1", "share": 0.5, "start": [8.5438, 47.3968]},
             {"id": "b2", "share": 0.5, "start": [8.5472, 47.3968]}],
    "seed": 1
  })";
  const std::string cli = UAVCOVER_CLI;
  const fs::path plan = dir / "plan";
  ASSERT_EQ(run(cli + " -q plan " + (dir / "mission.json").string() + " --out " + plan.string()), 0);
  const fs::path out = dir / "out";
  ASSERT_EQ(run(cli + " -q export " + plan.string() +
                " --format qgc,wpl,kml,dji,litchi,csv,geojson,trajectory --kmz" +
                " --transition-base 50 --transition-step 5 --firmware-type 3 --out " + out.string()),
            0);
  for (const std::string id : {"a1", "b2"}) {
    for (const std::string ext :
         {".plan", ".waypoints", ".kml", ".kmz", ".wpml.kmz", ".litchi.csv", ".csv", ".geojson"})
      EXPECT_TRUE(fs::exists(out / "export" / (id + ext))) << id << ext;
    EXPECT_EQ(slurp(out / "trajectory" / (id + ".csv")).substr(0, 51),
              "t,kind,x,y,z,lat,lon,vx,vy,vz,ax,ay,az,v_max,a_max\n");
  }
  // --trajectory-step (or --dt) gives the sampled CSV instead
  const fs::path sampled = dir / "sampled";
  ASSERT_EQ(run(cli + " -q export " + plan.string() + " -f trajectory --trajectory-step 0.5 --out " +
                sampled.string()),
            0);
  const std::string s = slurp(sampled / "trajectory" / "a1.csv");
  EXPECT_EQ(s.substr(0, 34), "t,x,y,z,lat,lon,vx,vy,vz,ax,ay,az\n");
  EXPECT_NE(s.find("\n0.500000,"), std::string::npos);
  EXPECT_EQ(s.find("\n0.100000,"), std::string::npos);
  // options reach the files: firmware type 3, transition altitude 55 m for the second UAV
  const std::string qgc = slurp(out / "export" / "b2.plan");
  EXPECT_NE(qgc.find("\"firmwareType\": 3"), std::string::npos);
  EXPECT_NE(qgc.find("\"Altitude\": 55.0"), std::string::npos);
  // without --out the files go into the plan folder
  ASSERT_EQ(run(cli + " -q export " + plan.string() + " -f csv"), 0);
  EXPECT_TRUE(fs::exists(plan / "export" / "a1.csv"));
  // bad input: exit code 2, message names --format
  const fs::path err = dir / "err.txt";
  EXPECT_EQ(run(cli + " -q export " + plan.string() + " --format qgc,shapefile 2> " + err.string()), 2);
  EXPECT_NE(slurp(err).find("--format"), std::string::npos);
  EXPECT_NE(slurp(err).find("shapefile"), std::string::npos);
  EXPECT_EQ(run(cli + " -q export " + (dir / "nowhere").string() + " --format qgc 2> " + err.string()), 2);
  EXPECT_EQ(run(cli + " -q export " + plan.string() + " --format qgc --corners round 2> " + err.string()), 2);
  EXPECT_EQ(run(cli + " -q export " + plan.string() + " --format qgc --transition-step 0 2> " + err.string()),
            2);
  EXPECT_NE(slurp(err).find("share the transition altitude"), std::string::npos);
  // the transition ceiling: refused with what to change, named by its flag, and nothing written
  const fs::path out2 = dir / "out2";
  EXPECT_EQ(run(cli + " -q export " + plan.string() + " --format qgc,dji --transition-ceiling 61 --out " +
                out2.string() + " 2> " + err.string()),
            2);
  EXPECT_NE(slurp(err).find("--transition-ceiling: 2 UAVs need transition altitudes 60..70 m"),
            std::string::npos)
      << slurp(err);
  EXPECT_NE(slurp(err).find("a higher ceiling"), std::string::npos);
  EXPECT_FALSE(fs::exists(out2 / "export"));
  // compressed under a ceiling that still leaves 5 m: a warning, and the second UAV at 65 m
  EXPECT_EQ(run(cli + " -q export " + plan.string() + " --format qgc --transition-ceiling 65 --out " +
                out2.string() + " 2> " + err.string()),
            0);
  EXPECT_NE(slurp(err).find("warning: transition altitudes 60..70 m would exceed the 65 m ceiling"),
            std::string::npos)
      << slurp(err);
  EXPECT_NE(slurp(out2 / "export" / "b2.plan").find("\"Altitude\": 65.0"), std::string::npos);
  fs::remove_all(dir);
}
