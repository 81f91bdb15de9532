// The trajectory export of `uavcover plan`: the segment form by default, the sampled CSV with
// --trajectory-step, byte for byte the CSV of before the segment form at 0.1 s.
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
