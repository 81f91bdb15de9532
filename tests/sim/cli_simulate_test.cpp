// `uavcover simulate` (the real binary): its endpoints, a clean stop on SIGTERM, and bad options
// refused with exit 2 and the option named.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace {

struct CliResult {
  int code = -1;
  std::string out, err;
};

CliResult run(const std::string& args, const std::string& prefix = "") {
  const fs::path dir = fs::temp_directory_path() / ("uavcover-simcli-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string cmd = prefix + "'" + UAVCOVER_CLI + "' " + args + " > '" + (dir / "out").string() +
                          "' 2> '" + (dir / "err").string() + "'";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::stringstream o, e;
  o << std::ifstream(dir / "out").rdbuf();
  e << std::ifstream(dir / "err").rdbuf();
  r.out = o.str();
  r.err = e.str();
  fs::remove_all(dir);
  return r;
}

}  // namespace

TEST(CliSimulate, PrintsOneLinePerVehicleAndStopsAfterDuration) {
  const auto r = run("simulate --vehicles 3 --listen udp:127.0.0.1:0 --speedup 20 --duration 2");
  ASSERT_EQ(r.code, 0) << r.err;
  for (int id = 1; id <= 3; ++id)
    EXPECT_NE(r.out.find("vehicle " + std::to_string(id) + ": udp:127.0.0.1:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("system id 3"), std::string::npos);
}

TEST(CliSimulate, TcpListenersPrintTheirPorts) {
  const auto r = run("simulate --vehicles 2 --listen tcp:127.0.0.1:0 --speedup 20 --duration 2");
  ASSERT_EQ(r.code, 0) << r.err;
  for (int id = 1; id <= 2; ++id)
    EXPECT_NE(r.out.find("vehicle " + std::to_string(id) + ": tcp:127.0.0.1:"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find(":0 system id"), std::string::npos) << "a real port, not 0: " << r.out;
}

TEST(CliSimulate, StopsCleanlyOnSigterm) {
  // `timeout` sends one SIGTERM after 1 s (--foreground: to the simulator only, not twice through the
  // process group, which the CLI takes as "the user insists"); the simulator stops and exits 0
  const auto r = run("simulate --vehicles 2 --listen udp:127.0.0.1:0",
                     "timeout --foreground --preserve-status -s TERM 1 ");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("vehicle 2:"), std::string::npos) << r.err;  // the summary
}

TEST(CliSimulate, RefusesBadOptionsNamingThem) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"--vehicles 2 --fail 3@0.4", "--fail"},
      {"--vehicles 2 --fail 1@1.5", "--fail"},
      {"--vehicles 2 --fail 1@0.5:explode", "--fail"},
      {"--vehicles 2 --listen udp:127.0.0.1:65535", "--listen"},
      {"--vehicles 2 --listen udp:127.0.0.1:14540,14541,14542", "--listen"},
      {"--vehicles 2 --listen udp:127.0.0.1:14540,14540", "--listen"},
      {"--vehicles 2 --listen serial:/dev/ttyS0:57600", "--listen"},
      {"--vehicles 2 --listen tcp:127.0.0.1:0,14541", "--listen"},
      {"--vehicles 1 --listen tcp:127.0.0.1:0 --gcs udp:127.0.0.1:14550", "--gcs"},
      {"--vehicles 0", "--vehicles"},
      {"--vehicles 256", "--vehicles"},
      {"--wind -1", "--wind"},
      {"--loss 1", "--loss"},
      {"--speedup 0", "--speedup"},
      {"--battery-min nan", "--battery-min"},
      {"--home 91,0", "--home"},
      {"--home 40.6", "--home"},
      {"--autopilot ardupilot", "--autopilot"},
      {"--autostart", "--autostart"},
      {"--gcs udp:nowhere:1", "--gcs"},
  };
  for (const auto& [args, field] : cases) {
    SCOPED_TRACE(args);
    const auto r = run("simulate --duration 1 " + args);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(field), std::string::npos) << r.err;
  }
}
