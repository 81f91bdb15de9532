// The trajectory export of `uavcover plan`: the segment form by default, the sampled CSV with
// --trajectory-step, byte for byte the CSV of before the segment form at 0.1 s; the polynomial method
// sampled, and its options refused naming the flag.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "cli/cli_support.hpp"

using namespace uavcover::testing;

TEST(TrajectoryCli, SampledAtATenthOfASecondIsTheCsvOfBefore) {
  const auto dir = temp_dir("traj-golden");
  const auto r =
      run_cli("-q plan " + example("olive-grove.json").string() + " --out " + (dir / "p").string() +
              " --no-images --no-evaluate --export trajectory --trajectory-step 0.1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // the digests of the files of before (tests/data/trajectory-golden/README.md), checked by coreutils
  const std::string golden =
      std::string(UAVCOVER_SOURCE_DIR) + "/tests/data/trajectory-golden/olive-grove-0.1s.sha256";
  const std::string digests = slurp(golden);
  ASSERT_EQ(std::count(digests.begin(), digests.end(), '\n'), 3);
  const std::string check =
      "cd '" + (dir / "p" / "trajectory").string() + "' && sha256sum --strict -c '" + golden + "' 2>&1";
  std::string out;
  FILE* p = popen(check.c_str(), "r");
  ASSERT_NE(p, nullptr);
  char buf[512];
  for (std::size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
  EXPECT_EQ(pclose(p), 0) << out;
  EXPECT_EQ(out, "alpha.csv: OK\nbravo.csv: OK\ncharlie.csv: OK\n");
  std::filesystem::remove_all(dir);
}

TEST(TrajectoryCli, DefaultIsTheSegmentFormAndBadStepsAreRefused) {
  const auto dir = temp_dir("traj-default");
  auto r = run_cli("-q plan " + example("olive-grove.json").string() + " --out " + (dir / "p").string() +
                   " --no-images --no-evaluate --export trajectory");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string csv = slurp(dir / "p" / "trajectory" / "alpha.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "t,kind,x,y,z,lat,lon,vx,vy,vz,ax,ay,az,v_max,a_max");
  // a breakpoint per phase, not per tenth of a second: far fewer rows than the sampled file
  const std::string sampled_dir = (dir / "s").string();
  r = run_cli("-q plan " + example("olive-grove.json").string() + " --out " + sampled_dir +
              " --no-images --no-evaluate --export trajectory --trajectory-step 0.1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string sampled = slurp(dir / "s" / "trajectory" / "alpha.csv");
  EXPECT_LT(csv.size() * 10, sampled.size());
  for (const char* bad : {"0", "-1", "nan", "61"}) {
    r = run_cli("-q plan " + example("olive-grove.json").string() + " --out " + (dir / "x").string() +
                " --export trajectory --trajectory-step " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.output.find("--trajectory-step"), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "x"));
  }
  std::filesystem::remove_all(dir);
}

TEST(TrajectoryCli, PolynomialMethodIsSampledAndItsBoundsAreRefusedNamingTheFlag) {
  const auto dir = temp_dir("traj-poly");
  const std::string plan = (dir / "p").string();
  auto r = run_cli("-q plan " + example("olive-grove.json").string() + " --out " + plan +
                   " --no-images --no-evaluate");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // the polynomial trajectory has no segment form: sampled every 0.1 s, and its plot beside it
  r = run_cli("export " + plan +
              " -f trajectory,trajectory_plot --trajectory-method polynomial --order 7 "
              "--v-mean 3 --v-min -4 --a-min -1.5");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("polynomial trajectory flight time"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("limits hold"), std::string::npos) << r.output;
  const std::string csv = slurp(dir / "p" / "trajectory" / "alpha.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "t,x,y,z,lat,lon,vx,vy,vz,ax,ay,az");
  EXPECT_EQ(csv.substr(csv.find('\n') + 1, 9), "0.000000,");
  EXPECT_EQ(csv.substr(csv.find('\n', csv.find('\n') + 1) + 1, 9), "0.100000,");
  EXPECT_TRUE(std::filesystem::exists(dir / "p" / "export" / "alpha.trajectory.png"));
  // with a step, at that step
  r = run_cli("-q export " + plan + " -f trajectory --trajectory-method polynomial --trajectory-step 0.5");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string half = slurp(dir / "p" / "trajectory" / "alpha.csv");
  EXPECT_EQ(half.substr(half.find('\n', half.find('\n') + 1) + 1, 9), "0.500000,");
  // the flags' own checks, and a mean speed above the UAVs' (5 and 6 m/s) from the library, by flag
  for (const auto& [flags, named] :
       std::vector<std::pair<std::string, std::string>>{{"--order 4", "--order"},
                                                        {"--v-min 0", "--v-min"},
                                                        {"--a-min 1", "--a-min"},
                                                        {"--trajectory-method spline", "--trajectory-method"},
                                                        {"--v-mean 5.5", "--v-mean"}}) {
    r = run_cli("-q export " + plan + " -f trajectory --trajectory-method polynomial " + flags);
    EXPECT_EQ(r.exit_code, 2) << flags << ": " << r.output;
    EXPECT_NE(r.output.find(named), std::string::npos) << flags << ": " << r.output;
  }
  // and `plan` refuses it before planning
  r = run_cli("-q plan " + example("olive-grove.json").string() + " --out " + (dir / "x").string() +
              " --export trajectory --trajectory-method polynomial --v-mean 5.5");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--v-mean"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "x"));
  std::filesystem::remove_all(dir);
}
