// Flown coverage (docs/flights.md): tracks made from the olive grove plan's own paths, flown at the
// mission altitude over coverage and at the transition altitude in transit, through the evaluator.
#include "flight/coverage.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>

#include "evaluation/evaluate.hpp"
#include "geodesy/local_frame.hpp"
#include "support/examples.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"
#include "usecases/plan_outputs.hpp"

namespace uavcover {
namespace {

using flight::Track;

const Plan& olive_grove() { return testing::olive_grove_plan(); }

/// What a vehicle flying the plan reports, sampled every `step_m`: coverage parts at `coverage_alt`,
/// the inside of transit parts at the UAV's transition altitude (`transit_alt` < 0) or `transit_alt`.
std::vector<Track> tracks_of(const Plan& p, double coverage_alt, double transit_alt = -1,
                             double step_m = 1.0) {
  const geodesy::LocalFrame frame(p.origin);
  std::vector<Track> out;
  for (const auto& up : p.uavs) {
    Track t{up.id, {}};
    const double high = transit_alt < 0 ? up.transition_altitude_m : transit_alt;
    for (const auto& part : up.parts) {
      const bool cov = part.kind == PartKind::Coverage;
      for (std::size_t k = 1; k < part.local.size(); ++k) {
        const Point a = part.local[k - 1], b = part.local[k];
        const int steps = std::max(1, static_cast<int>(std::ceil(bg::distance(a, b) / step_m)));
        for (int j = 0; j <= steps; ++j) {
          const bool end = (k == 1 && j == 0) || (k + 1 == part.local.size() && j == steps);
          if (j == steps && k + 1 < part.local.size()) continue;  // the next segment starts there
          if (!cov && end) continue;                              // a transit's ends belong to coverage
          const double f = static_cast<double>(j) / steps;
          const LonLat g = frame.to_wgs84(Point(a.x() + f * (b.x() - a.x()), a.y() + f * (b.y() - a.y())));
          t.second.push_back({g.lon, g.lat, cov ? coverage_alt : high});
        }
      }
    }
    out.push_back(std::move(t));
  }
  return out;
}

std::vector<Track> first_half(std::vector<Track> tracks) {
  for (auto& t : tracks) t.second.resize(t.second.size() / 2);
  return tracks;
}

std::vector<Track> second_half(std::vector<Track> tracks) {
  for (auto& t : tracks)
    t.second.erase(t.second.begin(), t.second.begin() + static_cast<long>(t.second.size() / 2));
  return tracks;
}

TEST(FlownCoverage, TheTrackOfThePlanCoversWhatThePlanDoes) {
  const Plan& p = olive_grove();
  const auto fc = flight::flown_coverage(p, tracks_of(p, p.mission.altitude_m));
  EXPECT_NEAR(fc.planned_poc, evaluation::evaluate_plan(p).coverage.total.poc, 1e-12);
  EXPECT_GT(fc.planned_poc, 0.9);
  EXPECT_NEAR(fc.flown_poc, fc.planned_poc, 0.005);
  EXPECT_GT(fc.samples_in_band, 0u);
  EXPECT_GT(fc.samples_out_of_band, 0u);  // the transits
}

TEST(FlownCoverage, HalfTheTrackCoversAboutHalf) {
  const Plan& p = olive_grove();
  const auto all = tracks_of(p, p.mission.altitude_m);
  const auto full = flight::flown_coverage(p, all);
  // the plan's evaluation computed once, as a flight does
  const auto planned = evaluation::evaluate_plan(p);
  const auto a = flight::flown_coverage(p, planned, first_half(all));
  const auto b = flight::flown_coverage(p, planned, second_half(all));
  EXPECT_GT(a.flown_poc, 0.35 * full.flown_poc);
  EXPECT_LT(a.flown_poc, 0.65 * full.flown_poc);
  EXPECT_GT(b.flown_poc, 0.35 * full.flown_poc);
  EXPECT_LT(b.flown_poc, 0.65 * full.flown_poc);
  // the halves together scan what the whole does (the seam's legs overlap by a footprint)
  EXPECT_GE(a.flown_poc + b.flown_poc, full.flown_poc - 1e-9);
  EXPECT_EQ(a.planned_poc, full.planned_poc);
}

TEST(FlownCoverage, OnlyTheCoverageBandScans) {
  const Plan& p = olive_grove();
  const double h = p.mission.altitude_m;
  const auto full = flight::flown_coverage(p, tracks_of(p, h));
  // a little high or low, within the band: the same coverage
  EXPECT_NEAR(flight::flown_coverage(p, tracks_of(p, h + 4.0)).flown_poc, full.flown_poc, 1e-12);
  EXPECT_NEAR(flight::flown_coverage(p, tracks_of(p, h - 4.5)).flown_poc, full.flown_poc, 1e-12);
  // out of it: nothing
  const auto above = flight::flown_coverage(p, tracks_of(p, h + 6.0));
  EXPECT_EQ(above.flown_poc, 0.0);
  EXPECT_EQ(above.samples_in_band, 0u);
  // everything at the transition altitudes: nothing
  EXPECT_EQ(flight::flown_coverage(p, tracks_of(p, p.uavs[0].transition_altitude_m, -1)).flown_poc, 0.0);
  // transits flown at the mission altitude scan too (they are in the band), so the coverage grows
  EXPECT_GE(flight::flown_coverage(p, tracks_of(p, h, h)).flown_poc, full.flown_poc);
  EXPECT_EQ(flight::flown_coverage(p, {}).flown_poc, 0.0);
}

TEST(FlownCoverage, AUavWithASmallerOwnCameraScansLessOfTheSameTrack) {
  // bravo's own camera sees 25 m across, the mission's 74.5 m: the same tracks scan less
  const Plan& p = olive_grove();
  const Plan own = testing::olive_grove_with_own_camera(1, 25.0);
  const auto tracks = tracks_of(p, p.mission.altitude_m);
  const auto before = flight::flown_coverage(p, tracks);
  const auto after = flight::flown_coverage(own, tracks);
  ASSERT_EQ(after.coverage.uavs.size(), 3u);
  EXPECT_NEAR(after.coverage.uavs[1].footprint_m, 25.0, 1e-9);
  EXPECT_EQ(after.coverage.uavs[0].footprint_m, before.coverage.uavs[0].footprint_m);
  EXPECT_EQ(after.coverage.uavs[0].stats.poc, before.coverage.uavs[0].stats.poc) << "alpha is unchanged";
  EXPECT_LT(after.coverage.uavs[1].stats.poc, 0.8 * before.coverage.uavs[1].stats.poc);
  EXPECT_LT(after.flown_poc, before.flown_poc);
  // the evaluator sweeps the plan's own paths the same way: flying the plan still gives its PoC
  EXPECT_NEAR(after.planned_poc, evaluation::evaluate_plan(own).coverage.total.poc, 1e-12);
  EXPECT_LT(after.planned_poc, before.planned_poc);
  EXPECT_NEAR(after.flown_poc, after.planned_poc, 0.005);
}

std::uint32_t be32(const std::string& s, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t k = 0; k < 4; ++k) v = (v << 8) | static_cast<unsigned char>(s[at + k]);
  return v;
}

TEST(FlownCoverage, OverlayIsTheLatticeAndItsBoundsHoldTheArea) {
  const Plan& p = olive_grove();
  const auto fc = flight::flown_coverage(p, first_half(tracks_of(p, p.mission.altitude_m)));
  const auto planned = evaluation::evaluate_plan(p).coverage;
  // the plan's lattice
  EXPECT_EQ(fc.coverage.lattice_cols, planned.lattice_cols);
  EXPECT_EQ(fc.coverage.lattice_rows, planned.lattice_rows);
  EXPECT_EQ(fc.coverage.lattice_m, planned.lattice_m);
  // a PNG of one pixel per sample
  ASSERT_GT(fc.overlay.bytes.size(), 24u);
  EXPECT_EQ(fc.overlay.bytes.substr(1, 3), "PNG");
  EXPECT_EQ(fc.overlay.media_type, "image/png");
  EXPECT_EQ(be32(fc.overlay.bytes, 16), static_cast<std::uint32_t>(planned.lattice_cols));
  EXPECT_EQ(be32(fc.overlay.bytes, 20), static_cast<std::uint32_t>(planned.lattice_rows));
  // the same box as the plan's own heatmap overlay (the server's heatmap_bounds)
  usecases::OutputOptions oo;
  oo.heatmap_overlay = true;
  const auto outputs = usecases::plan_outputs(p, oo);
  EXPECT_EQ(outputs.heatmap_bounds,
            nlohmann::json({{fc.bounds.south, fc.bounds.west}, {fc.bounds.north, fc.bounds.east}}));
  for (const auto& poly : p.mission.area)
    for (const auto& v : poly.front()) {
      EXPECT_LE(fc.bounds.south, v.lat);
      EXPECT_GE(fc.bounds.north, v.lat);
      EXPECT_LE(fc.bounds.west, v.lon);
      EXPECT_GE(fc.bounds.east, v.lon);
    }
}

using testing::input_error_field;

TEST(FlownCoverage, RefusesBadTracksNamingTheField) {
  const Plan& p = olive_grove();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::array<double, 3> ok{22.905, 40.602, 50.0};
  EXPECT_EQ(input_error_field([&] { flight::flown_coverage(p, {{"zulu", {ok}}}); }), "tracks[0].uav");
  EXPECT_EQ(input_error_field([&] {
              flight::flown_coverage(p, {{"alpha", {ok}}, {"bravo", {ok, {nan, 40.6, 50}}}});
            }),
            "tracks[1].samples[1]");
  EXPECT_EQ(input_error_field([&] {
              flight::flown_coverage(p, {{"alpha", {{22.9, 91.0, 50.0}}}});
            }),
            "tracks[0].samples[0]");
  EXPECT_EQ(input_error_field([&] {
              flight::flown_coverage(
                  p, {{"alpha", std::vector<std::array<double, 3>>(flight::kMaxTrackSamples + 1, ok)}});
            }),
            "tracks");
}

}  // namespace
}  // namespace uavcover
