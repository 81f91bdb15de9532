// Evaluating the paper's own paths reproduces its published PoC (Apostolidis et al. 2022, Table 3
// data in bench/data/apostolidis2022/paper_paths) within 1 percentage point for every region.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "evaluation/evaluate.hpp"
#include "geodesy/local_frame.hpp"
#include "support/files.hpp"
#include "uavcover/mission.hpp"

using namespace uavcover;
namespace fs = std::filesystem;
using uavcover::testing::slurp;

namespace {}  // namespace

TEST(PaperPaths, ReproducePublishedPoc) {
  const fs::path dir = fs::path(UAVCOVER_BENCH_DATA) / "apostolidis2022";
  ASSERT_TRUE(fs::exists(dir / "paper_paths")) << dir;
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(dir / "paper_paths")) {
    const std::string name = entry.path().filename().string();  // roiNN-<variant>.geojson
    if (entry.path().extension() != ".geojson") continue;
    SCOPED_TRACE(name);
    const Mission m = parse_mission(slurp(dir / (name.substr(0, 5) + ".json")));
    const geodesy::LocalFrame frame(geodesy::centroid(m.area));
    const std::string text = slurp(entry.path());
    const auto paths = evaluation::parse_paths_geojson(text, frame);
    const auto metrics = nlohmann::json::parse(text)["properties"]["paper_metrics"];
    evaluation::EvaluateOptions o;
    o.coverage.lattice_m = 1.0;
    std::vector<Uav> uavs(paths.flights.size(), m.uavs.at(0));
    const auto ev = evaluation::evaluate_flights(evaluation::free_area(m, frame), paths.flights, uavs,
                                                 evaluation::footprint_for(m), o);
    EXPECT_DOUBLE_EQ(ev.footprint_m, 60.0);
    EXPECT_NEAR(ev.coverage.total.poc, metrics["poc"].get<double>(), 0.01);
    if (paths.flights.size() == 1) {  // roi18-optimal's metrics count only its first loop
      // PoOC comes out a few points above the paper's (bench README)
      EXPECT_NEAR(ev.coverage.total.pooc, metrics["pooc"].get<double>(), 0.06);
      const double len = metrics["length_m"].get<double>();
      EXPECT_NEAR(ev.coverage.total.length_m, len, 0.02 * len);
      EXPECT_NEAR(ev.coverage.total.turns, metrics["turns"].get<double>(), 1.0);
    }
    std::printf("%-32s poc %.4f (paper %.4f)  pooc %.4f (paper %.4f)  turns %d (%g)\n", name.c_str(),
                ev.coverage.total.poc, metrics["poc"].get<double>(), ev.coverage.total.pooc,
                metrics["pooc"].get<double>(), ev.coverage.total.turns, metrics["turns"].get<double>());
    ++checked;
  }
  EXPECT_EQ(checked, 39);
}
