// End-to-end: every numeric option is validated as strictly as the mission file, and --out is
// checked before any work (issue items 12, 13). Refusals exit 2, name the option and write nothing.
#include <gtest/gtest.h>

#include <unistd.h>

#include "cli/cli_support.hpp"
#include "export/formats.hpp"

using namespace uavcover::testing;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

void expect_refused(const RunResult& r, const std::string& option) {
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(option + ": "), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
}

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

// A folder nobody may create entries in: read-only for a normal user; /sys for the super-user,
// who may write anywhere else.
fs::path unwritable_folder(const fs::path& tmp) {
  if (::geteuid() == 0) return "/sys";
  const fs::path d = tmp / "readonly";
  fs::create_directories(d);
  fs::permissions(d, fs::perms::owner_read | fs::perms::owner_exec);
  return d;
}

}  // namespace

TEST(OptionsCli, SeedsAreWholeNumbersThatFitInSixtyFourBits) {
  const auto dir = temp_dir("seed");
  const std::string plan = "plan " + example("olive-grove.json").string() + " -q --no-images --no-evaluate ";
  for (const char* bad : {"-1", "18446744073709551616", "99999999999999999999999", "1e3", "0x10", "nan",
                          "1.5", "+3", " 4", ""}) {
    SCOPED_TRACE(bad);
    expect_refused(run_cli(plan + "--out " + q(dir / "out") + " --seed '" + bad + "'"), "--seed");
    EXPECT_FALSE(fs::exists(dir / "out"));
    expect_refused(run_cli("study " + example("olive-grove.json").string() + " --uavs 1 --out " +
                           q(dir / "out") + " --seed '" + bad + "'"),
                   "--seed");
  }
  const auto r = run_cli(plan + "--out " + q(dir / "out") + " --seed 18446744073709551615");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_json(dir / "out" / "plan.json")["seed"].get<std::uint64_t>(), 18446744073709551615u);
  fs::remove_all(dir);
}

TEST(OptionsCli, PlanOptionsAreRanged) {
  const auto dir = temp_dir("plan-opts");
  const std::string plan = "plan " + example("olive-grove.json").string() + " --out " + q(dir / "out") + " ";
  for (const char* bad : {"0", "-1", "1000000001", "1e6", "18446744073709551616"})
    expect_refused(run_cli(plan + "--max-cells " + bad), "--max-cells");
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST(OptionsCli, EvaluateOptionsAreRangedAndFinite) {
  const auto dir = temp_dir("eval-opts");
  // refused while the command line is read: the files are not even opened
  const std::string eval = "evaluate " + example("olive-grove.json").string() + " " +
                           q(dir / "paths.geojson") + " --out " + q(dir / "out") + " ";
  struct Case {
    const char* option;
    const char* value;
  };
  for (const Case& c : {Case{"--max-samples", "0"}, Case{"--max-samples", "999"}, Case{"--max-samples", "-5"},
                        Case{"--footprint", "-1"}, Case{"--footprint", "0"}, Case{"--footprint", "nan"},
                        Case{"--footprint", "inf"}, Case{"--footprint", "-inf"}, Case{"--footprint", "1e400"},
                        Case{"--lattice", "-1"}, Case{"--lattice", "NaN"}, Case{"--lattice", "0"},
                        Case{"--fcm", "-0.5"}, Case{"--deploy-base", "-3"}, Case{"--deploy-per-uav", "inf"},
                        Case{"--battery-change", "-1"}, Case{"--battery-change", "1e7"}}) {
    SCOPED_TRACE(std::string(c.option) + " " + c.value);
    expect_refused(run_cli(eval + c.option + " " + c.value), c.option);
  }
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST(OptionsCli, ExportAndUploadOptionsAreRanged) {
  const auto dir = temp_dir("export-opts");  // exists, so PLAN_DIR's own check passes
  const std::string exp = "export " + q(dir) + " --format csv ";
  struct Case {
    const char* option;
    const char* value;
  };
  for (const Case& c :
       {Case{"--dt", "0"}, Case{"--dt", "-0.1"}, Case{"--dt", "nan"}, Case{"--trajectory-step", "0"},
        Case{"--trajectory-step", "61"}, Case{"--densify", "-1"}, Case{"--densify", "0.001"},
        Case{"--fillet-radius", "-2"}, Case{"--transition-base", "-1"}, Case{"--transition-step", "inf"},
        Case{"--firmware-type", "256"}, Case{"--vehicle-type", "-1"}, Case{"--corners", "round"}}) {
    SCOPED_TRACE(std::string(c.option) + " " + c.value);
    expect_refused(run_cli(exp + c.option + " " + c.value), c.option);
  }
  const std::string up = "upload " + q(dir) + " --uav a --to udp:127.0.0.1:14550 ";
  for (const Case& c :
       {Case{"--timeout", "0"}, Case{"--timeout", "nan"}, Case{"--timeout", "61"}, Case{"--retries", "-1"},
        Case{"--retries", "101"}, Case{"--target-system", "0"}, Case{"--target-component", "256"},
        Case{"--sysid", "4294967297"}, Case{"--compid", "-1"}, Case{"--transition-base", "nan"},
        Case{"--autopilot", "inav"}}) {
    SCOPED_TRACE(std::string(c.option) + " " + c.value);
    expect_refused(run_cli(up + c.option + " " + c.value), c.option);
  }
  EXPECT_TRUE(fs::is_empty(dir)) << "nothing written";
  fs::remove_all(dir);
}

// --format (export) and --export (plan) take the formats of the one table (export/formats.hpp): the
// help lists them, any of them is accepted while the command line is read, anything else is exit 2
// naming the option with the table's names, before any work.
TEST(OptionsCli, FormatChoicesAreTheExportTable) {
  namespace ex = uavcover::exporting;
  const auto dir = temp_dir("formats");  // exists, so PLAN_DIR's own check passes
  const std::string known = "(known: " + ex::format_list() + ")";
  for (const std::string& cmd :
       {"export " + q(dir) + " --format",
        "plan " + example("olive-grove.json").string() + " --out " + q(dir / "out") + " --export"}) {
    SCOPED_TRACE(cmd);
    const std::string option = cmd.substr(cmd.rfind(' ') + 1);
    for (const char* bad : {"gpx", "qgc,gpx", "'QGC, gpx'", "kmz", "''"}) {
      SCOPED_TRACE(bad);
      const auto r = run_cli(cmd + " " + bad);
      expect_refused(r, option);
      if (std::string(bad) != "''") {
        EXPECT_NE(r.output.find(known), std::string::npos) << r.output;
      }
    }
    // the help names every format of the table
    const auto help = run_cli(cmd.substr(0, cmd.find(' ')) + " --help");
    EXPECT_EQ(help.exit_code, 0) << help.output;
    EXPECT_NE(help.output.find(ex::format_list()), std::string::npos) << help.output;
  }
  EXPECT_TRUE(fs::is_empty(dir)) << "nothing written";
  // every format of the table gets past the option's check (export: then the empty folder is refused,
  // as a plan folder, not as a format)
  for (const auto& f : ex::formats()) {
    const auto r = run_cli("export " + q(dir) + " --format " + std::string(f.name));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(r.output.find("--format: "), std::string::npos) << f.name << ": " << r.output;
  }
  // names are read as the library reads them: any case, blanks around
  const auto r = run_cli("export " + q(dir) + " --format ' QGC,Kml'");
  EXPECT_EQ(r.output.find("--format: "), std::string::npos) << r.output;
  fs::remove_all(dir);
}

TEST(OptionsCli, OutputFolderProblemsAreTheUsersMistakes) {
  const auto dir = temp_dir("out");
  std::ofstream(dir / "file.txt") << "keep me";
  const fs::path locked = unwritable_folder(dir);
  const std::string mission = example("olive-grove.json").string();
  for (const std::string& out :
       {(dir / "file.txt").string(), std::string(), (dir / "file.txt" / "sub").string(),
        (locked / "out").string(), locked.string()}) {
    SCOPED_TRACE(out);
    expect_refused(run_cli("plan " + mission + " -q --out " + q(out)), "--out");
    expect_refused(run_cli("evaluate " + mission + " " + q(dir / "p.geojson") + " --out " + q(out)), "--out");
    expect_refused(run_cli("study " + mission + " --uavs 1 --out " + q(out)), "--out");
    expect_refused(run_cli("export " + q(dir) + " -f csv --out " + q(out)), "--out");
  }
  auto r = run_cli("plan " + mission + " --out " + q(dir / "file.txt"));
  EXPECT_NE(r.output.find("exists and is not a folder"), std::string::npos) << r.output;
  r = run_cli("plan " + mission + " --out ''");
  EXPECT_NE(r.output.find("empty"), std::string::npos) << r.output;
  r = run_cli("plan " + mission + " --out " + q(locked / "out"));
  EXPECT_NE(r.output.find("cannot write in"), std::string::npos) << r.output;
  // the default output folder of evaluate and study (the current one) is checked too
  r = run_cli("evaluate " + mission + " " + q(dir / "p.geojson"), "cd " + q(locked) + " &&");
  expect_refused(r, "--out");
  EXPECT_EQ(uavcover::testing::slurp(dir / "file.txt"), "keep me");
  EXPECT_FALSE(fs::exists(locked / "out"));
  if (locked != "/sys") fs::permissions(locked, fs::perms::owner_all);
  // a new folder (and its parents) is fine
  r = run_cli("plan " + mission + " -q --no-images --no-evaluate --out " + q(dir / "a" / "b"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "a" / "b" / "plan.json"));
  fs::remove_all(dir);
}
