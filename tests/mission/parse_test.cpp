// Every validation rule of the mission file (issue 2) has a test here.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "uavcover/error.hpp"
#include "uavcover/mission.hpp"

using nlohmann::json;
using uavcover::InputError;
using uavcover::parse_mission;

namespace {

// A 1 km x 0.8 km field near Thessaloniki.
json base() {
  return json::parse(R"({
    "name": "test field",
    "area": {"type": "Polygon", "coordinates": [[[22.90, 40.60], [22.912, 40.60], [22.912, 40.607], [22.90, 40.607], [22.90, 40.60]]]},
    "spacing_m": 40,
    "uavs": [{"id": "a", "start": [22.901, 40.601]}, {"id": "b"}],
    "mode": "strict",
    "seed": 7
  })");
}

// Expects an InputError whose field is `field` and whose message contains `needle`.
void expect_error(const json& j, const std::string& field, const std::string& needle) {
  try {
    parse_mission(j.dump());
    FAIL() << "accepted: " << j.dump();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(MissionParse, AcceptsTheBaseMission) {
  const auto m = parse_mission(base().dump());
  EXPECT_EQ(m.name, "test field");
  ASSERT_EQ(m.uavs.size(), 2u);
  EXPECT_DOUBLE_EQ(m.uavs[0].share, 0.5);
  EXPECT_TRUE(m.uavs[0].start.has_value());
  EXPECT_FALSE(m.uavs[1].start.has_value());
  EXPECT_EQ(m.seed, 7u);
  EXPECT_EQ(m.mode, uavcover::Mode::Strict);
  EXPECT_DOUBLE_EQ(m.spacing_m, 40.0);
  EXPECT_EQ(m.altitude_source, "default");
  EXPECT_DOUBLE_EQ(m.altitude_m, 40.0);
}

TEST(MissionParse, NormalisesWindingAndClosure) {
  auto j = base();
  // clockwise and unclosed
  j["area"]["coordinates"] =
      json::parse("[[[22.90, 40.60], [22.90, 40.607], [22.912, 40.607], [22.912, 40.60]]]");
  const auto m = parse_mission(j.dump());
  const auto& ring = m.area.at(0).at(0);
  ASSERT_EQ(ring.size(), 5u);
  EXPECT_EQ(ring.front(), ring.back());
  double twice = 0;
  for (std::size_t i = 0; i + 1 < ring.size(); ++i)
    twice += ring[i].lon * ring[i + 1].lat - ring[i + 1].lon * ring[i].lat;
  EXPECT_GT(twice, 0) << "outer ring must be counter-clockwise (RFC 7946)";
}

TEST(MissionParse, HolesBecomeNoFlyZones) {
  auto j = base();
  j["area"]["coordinates"].push_back(
      json::parse("[[22.905, 40.603], [22.906, 40.603], [22.906, 40.604], [22.905, 40.604]]"));
  const auto m = parse_mission(j.dump());
  EXPECT_EQ(m.area.at(0).size(), 1u);
  ASSERT_EQ(m.no_fly_zones.size(), 1u);
}

TEST(MissionParse, MultiPolygonArea) {
  auto j = base();
  j["area"] = json::parse(R"({"type": "MultiPolygon", "coordinates": [
      [[[22.90, 40.60], [22.905, 40.60], [22.905, 40.605], [22.90, 40.605]]],
      [[[22.91, 40.60], [22.915, 40.60], [22.915, 40.605], [22.91, 40.605]]]]})");
  EXPECT_EQ(parse_mission(j.dump()).area.size(), 2u);
}

TEST(MissionParse, MalformedJson) {
  try {
    parse_mission("{\"area\": ");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "mission");
    EXPECT_NE(std::string(e.what()).find("malformed JSON"), std::string::npos);
  }
  EXPECT_THROW(parse_mission("[1,2]"), InputError);
  EXPECT_THROW(parse_mission(""), InputError);
  EXPECT_THROW(parse_mission("{\"spacing_m\": NaN}"), InputError);
}

TEST(MissionParse, WrongTypes) {
  auto j = base();
  j["spacing_m"] = "forty";
  expect_error(j, "spacing_m", "expected a number");
  j = base();
  j["uavs"] = "two";
  expect_error(j, "uavs", "expected a count or an array");
  j = base();
  j["mode"] = 3;
  expect_error(j, "mode", "expected a string");
  j = base();
  j["area"]["coordinates"][0][1] = "x";
  expect_error(j, "area.coordinates[0][1]", "expected a position");
  j = base();
  j["area"]["type"] = "LineString";
  expect_error(j, "area.type", "Polygon");
}

TEST(MissionParse, FuzzFoundNonStringTypeMember) {
  // found by fuzz_mission: {"type": 30} inside no_fly_zones used to escape as a json type_error
  auto j = base();
  j["no_fly_zones"] = json::parse(R"([{"type": 30}])");
  expect_error(j, "no_fly_zones[0].type", "missing");
  j = base();
  j["area"]["type"] = 30;
  expect_error(j, "area.type", "missing");
  j = base();
  j["seed"] = "x";
  expect_error(j, "seed", "non-negative integer");
}

TEST(MissionParse, UnknownFieldsAreNamed) {
  auto j = base();
  j["spacing"] = 40;
  expect_error(j, "spacing", "unknown field");
}

TEST(MissionParse, NonFiniteNumbers) {
  // JSON has no NaN literal; 1e999 overflows to infinity
  std::string text = base().dump();
  const auto pos = text.find("\"spacing_m\":40");
  ASSERT_NE(pos, std::string::npos);
  text.replace(pos, 14, "\"spacing_m\":1e999");
  try {
    parse_mission(text);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "mission");
    EXPECT_NE(std::string(e.what()).find("overflow"), std::string::npos) << e.what();
  }
}

TEST(MissionParse, CoordinatesOutOfRange) {
  auto j = base();
  j["area"]["coordinates"][0][2] = {190.0, 40.607};
  expect_error(j, "area.coordinates[0][2]", "longitude");
  j = base();
  j["area"]["coordinates"][0][2] = {22.912, 91.0};
  expect_error(j, "area.coordinates[0][2]", "latitude");
  j = base();
  j["uavs"][0]["start"] = {22.9, -95.0};
  expect_error(j, "uavs[0].start", "latitude");
}

TEST(MissionParse, TooFewDistinctVertices) {
  auto j = base();
  j["area"]["coordinates"] =
      json::parse("[[[22.90, 40.60], [22.91, 40.60], [22.90, 40.60], [22.91, 40.60]]]");
  expect_error(j, "area.coordinates[0]", "at least 3 distinct");
}

TEST(MissionParse, SelfIntersectingRing) {
  auto j = base();
  // bow-tie
  j["area"]["coordinates"] =
      json::parse("[[[22.90, 40.60], [22.91, 40.607], [22.91, 40.60], [22.90, 40.607]]]");
  expect_error(j, "area.coordinates[0]", "intersects itself");
  j = base();
  j["no_fly_zones"] = json::parse(
      R"([{"type": "Polygon", "coordinates": [[[22.903, 40.602], [22.905, 40.604], [22.905, 40.602], [22.903, 40.604]]]}])");
  expect_error(j, "no_fly_zones[0].coordinates[0]", "intersects itself");
}

TEST(MissionParse, NoFlyZoneSwallowsTheArea) {
  auto j = base();
  j["no_fly_zones"] = json::parse(
      R"([{"type": "Polygon", "coordinates": [[[22.89, 40.59], [22.92, 40.59], [22.92, 40.61], [22.89, 40.61]]]}])");
  expect_error(j, "no_fly_zones", "remove the whole area");
}

TEST(MissionParse, StartInsideNoFlyZone) {
  auto j = base();
  j["no_fly_zones"] = json::parse(
      R"([{"type": "Polygon", "coordinates": [[[22.9005, 40.6005], [22.902, 40.6005], [22.902, 40.602], [22.9005, 40.602]]]}])");
  expect_error(j, "uavs[0].start", "inside a no-fly zone");
}

TEST(MissionParse, StartOutsideTheAreaIsAllowed) {
  auto j = base();
  j["uavs"][0]["start"] = {22.899, 40.599};
  EXPECT_NO_THROW(parse_mission(j.dump()));
}

TEST(MissionParse, Shares) {
  auto j = base();
  j["uavs"][0]["share"] = 0;
  j["uavs"][1]["share"] = 0;
  expect_error(j, "uavs", "all shares are zero");
  j = base();
  j["uavs"][1]["share"] = -0.2;
  expect_error(j, "uavs[1].share", "negative");
  j = base();
  j["uavs"][0]["share"] = 3;
  j["uavs"][1]["share"] = 2;
  auto m = parse_mission(j.dump());
  EXPECT_NEAR(m.uavs[0].share, 0.6, 1e-12);
  EXPECT_NEAR(m.uavs[1].share, 0.4, 1e-12);
  j = base();
  j["uavs"][0]["share"] = 0.7;
  m = parse_mission(j.dump());
  EXPECT_NEAR(m.uavs[1].share, 0.3, 1e-12);
  j["uavs"][0]["share"] = 1.2;
  expect_error(j, "uavs", "already add up");
}

TEST(MissionParse, Spacing) {
  auto j = base();
  j["spacing_m"] = 0;
  expect_error(j, "spacing_m", "must be positive");
  j["spacing_m"] = -5;
  expect_error(j, "spacing_m", "must be positive");
  j.erase("spacing_m");
  expect_error(j, "spacing_m", "missing");
  j = base();
  j["camera"] = {{"altitude_m", 50}, {"hfov_deg", 73.4}, {"overlap", 0.5}};
  expect_error(j, "spacing_m", "not both");
}

// the paper's camera (Apostolidis 2022 eq. 13-14, 23): po is the overlap on both sides of an image, in
// [0, 2) (its search-and-rescue mission flew 160 %), and the GSD is the footprint over hRes
TEST(MissionParse, PaperCameraTakesItsOwnOverlapRangeAndGsd) {
  auto j = base();
  j.erase("spacing_m");
  j["camera"] = {{"altitude_m", 50}, {"hfov_deg", 90}, {"overlap", 1.6}, {"image_width_px", 4000}};
  const uavcover::Mission m = parse_mission(j.dump());
  // d = 2·50·tan(45°) = 100 m; ds = (2 - 1.6)·50·tan(45°) = 20 m; GSD = 100 m / 4000 px
  ASSERT_TRUE(m.footprint_m);
  EXPECT_NEAR(*m.footprint_m, 100.0, 1e-9);
  EXPECT_NEAR(m.spacing_m, 20.0, 1e-9);
  ASSERT_TRUE(m.gsd_m);
  EXPECT_NEAR(*m.gsd_m, 0.025, 1e-12);
  // without hRes there is no GSD in this convention
  j["camera"].erase("image_width_px");
  EXPECT_FALSE(parse_mission(j.dump()).gsd_m);
  // po = 2 leaves no distance between lanes
  j["camera"]["overlap"] = 2.0;
  expect_error(j, "camera.overlap", "");
  j["camera"]["overlap"] = -0.1;
  expect_error(j, "camera.overlap", "");
  j["camera"]["overlap"] = 1.6;
  j["camera"]["image_width_px"] = 0;
  expect_error(j, "camera.image_width_px", "");
}

TEST(MissionParse, ZeroUavs) {
  auto j = base();
  j["uavs"] = 0;
  expect_error(j, "uavs", "at least one UAV");
  j["uavs"] = json::array();
  expect_error(j, "uavs", "at least one UAV");
}

TEST(MissionParse, GridTooLargeSaysWhatFits) {
  auto j = base();
  j["spacing_m"] = 0.05;
  try {
    parse_mission(j.dump());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "spacing_m");
    const std::string w = e.what();
    EXPECT_NE(w.find("cells"), std::string::npos) << w;
    EXPECT_NE(w.find("use a spacing of at least"), std::string::npos) << w;
  }
  uavcover::ParseOptions small;
  small.max_cells = 100;
  EXPECT_THROW(parse_mission(base().dump(), small), InputError);
}

TEST(MissionParse, AntimeridianIsRefusedClearly) {
  auto j = base();
  j["area"]["coordinates"] =
      json::parse("[[[179.99, 10.0], [-179.99, 10.0], [-179.99, 10.01], [179.99, 10.01]]]");
  j["uavs"] = 1;
  expect_error(j, "area.coordinates[0]", "antimeridian");
}

TEST(MissionParse, CameraEq14) {
  auto j = base();
  j.erase("spacing_m");
  j["camera"] = {{"altitude_m", 40}, {"hfov_deg", 73.4}, {"overlap", 0.5}};
  const auto m = parse_mission(j.dump());
  const double t = std::tan(73.4 / 2 * M_PI / 180);
  EXPECT_NEAR(m.spacing_m, 1.5 * 40 * t, 1e-9);
  EXPECT_NEAR(*m.footprint_m, 2 * 40 * t, 1e-9);
  EXPECT_EQ(m.altitude_source, "camera");
  EXPECT_DOUBLE_EQ(m.altitude_m, 40);
}

TEST(MissionParse, CameraQgcConvention) {
  auto j = base();
  j.erase("spacing_m");
  j["camera"] = {{"altitude_m", 100},
                 {"sensor_width_mm", 13.2},
                 {"focal_length_mm", 8.8},
                 {"image_width_px", 5472},
                 {"side_overlap", 0.7}};
  const auto m = parse_mission(j.dump());
  const double gsd = 100 * 13.2 / (8.8 * 5472);
  EXPECT_NEAR(*m.gsd_m, gsd, 1e-12);
  EXPECT_NEAR(*m.footprint_m, 5472 * gsd, 1e-9);
  EXPECT_NEAR(m.spacing_m, 5472 * gsd * 0.3, 1e-9);
  j["camera"].erase("focal_length_mm");
  expect_error(j, "camera.focal_length_mm", "missing");
}

TEST(MissionParse, UavCountGivesEqualShares) {
  auto j = base();
  j["uavs"] = 4;
  const auto m = parse_mission(j.dump());
  ASSERT_EQ(m.uavs.size(), 4u);
  for (const auto& u : m.uavs) EXPECT_DOUBLE_EQ(u.share, 0.25);
  EXPECT_EQ(m.uavs[3].id, "uav4");
}

TEST(MissionParse, UavIdsAreSafeAndUnique) {
  auto j = base();
  j["uavs"][1]["id"] = "a";
  expect_error(j, "uavs[1].id", "duplicate");
  j["uavs"][1]["id"] = "../x";
  expect_error(j, "uavs[1].id", "may contain only");
}

TEST(MissionParse, ImportsMcppOptimizedDarpFormat) {
  const auto j = json::parse(R"({
    "droneNo": 2, "scanningDensity": 30,
    "polygon": [{"lat": 40.60, "long": 22.90}, {"lat": 40.60, "long": 22.912}, {"lat": 40.607, "long": 22.912}, {"lat": 40.607, "long": 22.90}],
    "obstacles": [[{"lat": 40.603, "long": 22.905}, {"lat": 40.603, "long": 22.906}, {"lat": 40.604, "long": 22.906}, {"lat": 40.604, "long": 22.905}]],
    "pathsStrictlyInPoly": false,
    "initialPos": [{"lat": 40.601, "long": 22.901}, {"lat": 40.606, "long": 22.911}],
    "rPortions": [0.3, 0.7]
  })");
  const auto m = parse_mission(j.dump());
  EXPECT_EQ(m.source_format, "mcpp-optimized-darp");
  EXPECT_EQ(m.mode, uavcover::Mode::Coverage);
  EXPECT_DOUBLE_EQ(m.spacing_m, 30);
  ASSERT_EQ(m.uavs.size(), 2u);
  EXPECT_NEAR(m.uavs[1].share, 0.7, 1e-12);
  EXPECT_NEAR(m.uavs[0].start->lat, 40.601, 1e-12);
  EXPECT_EQ(m.no_fly_zones.size(), 1u);
  auto bad = j;
  bad["rPortions"] = {0.3};
  expect_error(bad, "rPortions", "one portion per drone");
}

TEST(MissionParse, RoundTripThroughJson) {
  const auto m = parse_mission(base().dump());
  const auto again = parse_mission(uavcover::mission_to_json(m));
  EXPECT_EQ(again.area, m.area);
  EXPECT_EQ(again.uavs.size(), m.uavs.size());
  EXPECT_DOUBLE_EQ(again.uavs[0].share, m.uavs[0].share);
}

TEST(MissionParse, RingTracedTwiceCollapsesToOneCycle) {
  auto j = base();
  auto ring = j["area"]["coordinates"][0];
  ring.erase(ring.size() - 1);
  auto twice = ring;
  for (const auto& p : ring) twice.push_back(p);
  twice.push_back(ring[0]);
  j["area"]["coordinates"][0] = twice;
  const auto m = parse_mission(j.dump());
  EXPECT_EQ(m.area.at(0).at(0).size(), 5u);
}

TEST(MissionParse, AllBenchmarkRoisParse) {
  for (int i = 1; i <= 20; ++i) {
    char name[64];
    std::snprintf(name, sizeof name, "%s/apostolidis2022/roi%02d.json", UAVCOVER_BENCH_DATA, i);
    FILE* f = std::fopen(name, "rb");
    ASSERT_NE(f, nullptr) << name;
    std::string text;
    char buf[4096];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) text.append(buf, n);
    std::fclose(f);
    EXPECT_NO_THROW(parse_mission(text)) << name;
  }
}

TEST(MissionParse, SharesAreNormalisedWithoutOverflowOrUnderflow) {
  auto j = base();
  j["uavs"][0]["share"] = 1e308;  // their sum overflowed to inf: both shares became 0
  j["uavs"][1]["share"] = 1e308;
  auto m = parse_mission(j.dump());
  EXPECT_DOUBLE_EQ(m.uavs[0].share, 0.5);
  EXPECT_DOUBLE_EQ(m.uavs[1].share, 0.5);
  j["uavs"][0]["share"] = 1e-300;
  j["uavs"][1]["share"] = 3e-300;
  m = parse_mission(j.dump());
  EXPECT_DOUBLE_EQ(m.uavs[0].share, 0.25);
  EXPECT_DOUBLE_EQ(m.uavs[1].share, 0.75);
  // 5e-324 next to 1 became 0 although zero shares are refused: refused as negligible
  j["uavs"][0]["share"] = 5e-324;
  j["uavs"][1]["share"] = 1;
  expect_error(j, "uavs[0].share", "less than a millionth of the largest share");
  j["uavs"][0]["share"] = 1e-6;  // the smallest ratio accepted
  EXPECT_NEAR(parse_mission(j.dump()).uavs[0].share, 1e-6, 1e-12);
  // some given: fractions of 1
  j = base();
  j["uavs"][0]["share"] = 1e308;
  expect_error(j, "uavs", "already add up to 1e+308");
  j["uavs"][0]["share"] = 5e-324;
  expect_error(j, "uavs[0].share", "less than a millionth");
  for (const auto& u : parse_mission(base().dump()).uavs) EXPECT_DOUBLE_EQ(u.share, 0.5);
}

TEST(MissionParse, McppPortionsAreNamedAsSuch) {
  const json j = json::parse(R"({"droneNo": 2, "scanningDensity": 40, "rPortions": [0, 1],
    "polygon": [{"lat": 40.60, "long": 22.90}, {"lat": 40.60, "long": 22.912}, {"lat": 40.607, "long": 22.912}]})");
  expect_error(j, "rPortions[0]", "must be positive");
}

TEST(MissionParse, UavIdSyntax) {
  auto j = base();
  for (const char* bad : {".", "..", ".hidden", "a/b", "a\\b", "", "a b", "é", "a\u0001"}) {
    j["uavs"][1]["id"] = bad;
    try {
      parse_mission(j.dump());
      ADD_FAILURE() << "accepted id " << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "uavs[1].id") << e.what();
    }
  }
  j["uavs"][1]["id"] = std::string(65, 'x');
  expect_error(j, "uavs[1].id", "1 to 64 characters");
  j["uavs"][1]["id"] = ".";
  expect_error(j, "uavs[1].id", "must not start with '.'");
  j["uavs"][1]["id"] = "A";  // "a" and "A" would be one file on many file systems
  expect_error(j, "uavs[1].id", "differ in more than letter case");
  for (const std::string& good :
       std::vector<std::string>{"b", "uav.2", "-x", "_", "a..b", std::string(64, 'z')}) {
    j["uavs"][1]["id"] = good;
    EXPECT_EQ(parse_mission(j.dump()).uavs[1].id, good);
  }
}

TEST(MissionParse, NamesWithControlCharactersAreRefused) {
  auto j = base();
  using namespace std::string_literals;
  for (const std::string& bad :
       {"a\u0007b"s, "\u001b[31mred"s, "line\nbreak"s, "tab\there"s, "nul\0x"s, "del\u007f"s, "nel\u0085"s}) {
    j["name"] = bad;
    expect_error(j, "name", "control characters");
  }
  j["name"] = "Ελαιώνας «north» – 2025";
  EXPECT_EQ(parse_mission(j.dump()).name, "Ελαιώνας «north» – 2025");
  j["name"] = std::string(257, 'n');
  expect_error(j, "name", "at most 256 bytes");
}

TEST(MissionParse, CollinearRingsAreBlamedNotTheSpacing) {
  auto j = base();
  j["area"]["coordinates"] =
      json::parse("[[[22.90, 40.60], [22.91, 40.60], [22.92, 40.60], [22.90, 40.60]]]");
  expect_error(j, "area.coordinates[0]", "no area: its vertices lie on one line");
  j["area"]["coordinates"] = json::parse("[[[22.90, 40.60], [22.91, 40.61], [22.92, 40.62]]]");
  expect_error(j, "area.coordinates[0]", "lie on one line");
  j = base();
  j["no_fly_zones"] = json::parse(
      R"([{"type": "Polygon", "coordinates": [[[22.903, 40.602], [22.904, 40.603], [22.905, 40.604]]]}])");
  expect_error(j, "no_fly_zones[0].coordinates[0]", "lie on one line");
}

TEST(MissionParse, LongEdgesAreNotCalledAntimeridianCrossings) {
  // -170 -> 170 runs straight through 0 (RFC 7946): it does not cross the antimeridian
  auto j = base();
  j["area"]["coordinates"] = json::parse("[[[-170, 10], [170, 10], [170, 10.01], [-170, 10.01]]]");
  j["uavs"] = 1;
  try {
    parse_mission(j.dump());
    FAIL();
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_EQ(w.find("crosses"), std::string::npos) << w;
    EXPECT_NE(w.find("spans 340"), std::string::npos) << w;
    EXPECT_NE(w.find("long way round"), std::string::npos) << w;
  }
  // the same ring with vertices in between: far too large for a local flat frame
  j["area"]["coordinates"] =
      json::parse("[[[-170, 10], [0, 10], [170, 10], [170, 10.01], [0, 10.01], [-170, 10.01]]]");
  expect_error(j, "area.coordinates[0]", "at most 500 km from their centre");
  // an area 2 degrees across is fine
  j["area"]["coordinates"] = json::parse("[[[22, 40], [24, 40], [24, 41], [22, 41]]]");
  j["spacing_m"] = 2000;
  EXPECT_NO_THROW(parse_mission(j.dump()));
}

TEST(MissionParse, GridLimitMessagesStaySane) {
  uavcover::ParseOptions none;
  none.max_cells = 0;  // used to advise "a spacing of at least -9223372036854775808 m"
  try {
    parse_mission(base().dump(), none);
    FAIL();
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_EQ(w.find('-'), std::string::npos) << w;
    EXPECT_EQ(w.find("--max-cells"), std::string::npos) << "the library names no flag: " << w;
  }
  auto j = base();
  j["spacing_m"] = 1e-300;
  try {
    parse_mission(j.dump());
    FAIL();
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_EQ(e.field(), "spacing_m");
    EXPECT_EQ(w.find('-'), std::string::npos) << w;
    EXPECT_NE(w.find("use a spacing of at least 1 m"), std::string::npos) << w;
  }
}

TEST(MissionParse, TerrainBlock) {
  json j = base();
  j["terrain"] = {{"dem", "dem/srtm.tif"}};
  const auto m = parse_mission(j.dump());
  ASSERT_TRUE(m.terrain.has_value());
  EXPECT_EQ(m.terrain->dem, "dem/srtm.tif");
  EXPECT_EQ(m.terrain->mode, "follow");  // defaults
  EXPECT_EQ(m.terrain->tolerance_m, 1.0);
  EXPECT_EQ(m.terrain->grid, nullptr);  // parsing reads no file
  // written back and read again unchanged
  const auto again = parse_mission(uavcover::mission_to_json(m));
  ASSERT_TRUE(again.terrain.has_value());
  EXPECT_EQ(again.terrain->dem, "dem/srtm.tif");
  EXPECT_EQ(again.terrain->mode, "follow");
  // without the block, none
  EXPECT_FALSE(parse_mission(base().dump()).terrain.has_value());
  EXPECT_EQ(json::parse(uavcover::mission_to_json(parse_mission(base().dump()))).count("terrain"), 0u);

  j["terrain"] = {{"dem", "a.tif"}, {"mode", "off"}, {"tolerance_m", 0.5}};
  EXPECT_EQ(parse_mission(j.dump()).terrain->mode, "off");
  j["terrain"] = {{"mode", "follow"}};
  expect_error(j, "terrain.dem", "missing");
  j["terrain"] = {{"dem", ""}};
  expect_error(j, "terrain.dem", "must name a file");
  j["terrain"] = {{"dem", 5}};
  expect_error(j, "terrain.dem", "expected a string");
  j["terrain"] = {{"dem", "a.tif"}, {"mode", "hover"}};
  expect_error(j, "terrain.mode", "\"follow\" or \"off\"");
  j["terrain"] = {{"dem", "a.tif"}, {"tolerance_m", 0}};
  expect_error(j, "terrain.tolerance_m", "must be in [0.1, 100.0]");
  j["terrain"] = {{"dem", "a.tif"}, {"tol", 1}};
  expect_error(j, "terrain.tol", "unknown field");
  j["terrain"] = "a.tif";
  expect_error(j, "terrain", "expected an object");
}

TEST(MissionParse, UavCameraGivesThatUavItsOwnFootprint) {
  auto j = base();
  j.erase("spacing_m");
  j["camera"] = {{"altitude_m", 40}, {"hfov_deg", 90}, {"overlap", 0.5}};
  j["uavs"][1]["camera"] = {{"altitude_m", 40},       {"sensor_width_mm", 6.4}, {"focal_length_mm", 8},
                            {"image_width_px", 4000}, {"side_overlap", 0.3},    {"capture", "hover"}};
  const auto m = parse_mission(j.dump());
  EXPECT_FALSE(m.uavs[0].camera.has_value()) << "the mission's camera is the default";
  EXPECT_FALSE(m.uavs[0].camera_geometry.has_value());
  ASSERT_TRUE(m.uavs[1].camera_geometry.has_value());
  // QGroundControl: GSD = h * sensor width / (focal length * image width); footprint = width * GSD
  EXPECT_NEAR(*m.uavs[1].camera_geometry->gsd_m, 40 * 6.4 / (8 * 4000.0), 1e-12);
  EXPECT_NEAR(m.uavs[1].camera_geometry->footprint_m, 40 * 6.4 / 8, 1e-9);
  EXPECT_NEAR(m.uavs[1].camera_geometry->spacing_m, 40 * 6.4 / 8 * 0.7, 1e-9);
  EXPECT_NEAR(*m.footprint_m, 80.0, 1e-9) << "the mission's footprint is its own camera's";
  // round trip: the UAV's camera is written with it, the others' stays absent
  const json out = json::parse(uavcover::mission_to_json(m));
  EXPECT_FALSE(out["uavs"][0].contains("camera"));
  ASSERT_TRUE(out["uavs"][1].contains("camera"));
  EXPECT_EQ(out["uavs"][1]["camera"]["capture"], "hover");
  const auto again = parse_mission(out.dump());
  ASSERT_TRUE(again.uavs[1].camera_geometry.has_value());
  EXPECT_DOUBLE_EQ(again.uavs[1].camera_geometry->footprint_m, m.uavs[1].camera_geometry->footprint_m);
  EXPECT_EQ(again.uavs[1].camera->capture, "hover");
  EXPECT_FALSE(again.uavs[0].camera.has_value());
  // a mission without UAV cameras writes none
  const json plain = json::parse(uavcover::mission_to_json(parse_mission(base().dump())));
  for (const auto& u : plain["uavs"]) EXPECT_FALSE(u.contains("camera"));
}

TEST(MissionParse, UavCameraRefusalsNameTheUavsField) {
  auto j = base();
  j.erase("spacing_m");
  j["camera"] = {{"altitude_m", 40}, {"hfov_deg", 90}, {"overlap", 0.5}};
  auto with = [&](const json& cam) {
    auto k = j;
    k["uavs"][1]["camera"] = cam;
    return k;
  };
  expect_error(with({{"altitude_m", 40}, {"hfov_deg", 190}, {"overlap", 0.5}}), "uavs[1].camera.hfov_deg",
               "(0, 180)");
  expect_error(with({{"altitude_m", 40}, {"hfov_deg", 60}}), "uavs[1].camera.overlap", "missing");
  expect_error(with({{"hfov_deg", 60}, {"overlap", 0.5}}), "uavs[1].camera.altitude_m", "missing");
  expect_error(with({{"altitude_m", 40}, {"hfov_deg", 60}, {"overlap", 0.5}, {"zoom", 2}}),
               "uavs[1].camera.zoom", "unknown field");
  expect_error(with({{"altitude_m", 40}, {"hfov_deg", 60}, {"overlap", 0.5}, {"sensor_width_mm", 6}}),
               "uavs[1].camera", "give either");
  expect_error(with("wide"), "uavs[1].camera", "expected an object");
  expect_error(with({{"altitude_m", 40}, {"hfov_deg", 60}, {"overlap", 0.5}, {"front_overlap", 0.99}}),
               "uavs[1].camera.front_overlap", "0.95");
  // every UAV flies the mission's altitude
  expect_error(with({{"altitude_m", 30}, {"hfov_deg", 60}, {"overlap", 0.5}}), "uavs[1].camera.altitude_m",
               "must equal camera.altitude_m");
  // the UAV's own camera limits its own speed
  auto fast = with({{"altitude_m", 40}, {"hfov_deg", 60}, {"overlap", 0.5}, {"min_trigger_interval_s", 10}});
  fast["uavs"][1]["speed_mps"] = 5;
  expect_error(fast, "uavs[1].speed_mps", "uavs[1].camera.min_trigger_interval_s");
  // a UAV camera needs the mission's camera as the others' default
  auto spacing = base();
  spacing["uavs"][1]["camera"] = {{"altitude_m", 40}, {"hfov_deg", 60}, {"overlap", 0.5}};
  expect_error(spacing, "uavs[1].camera", "needs the mission's camera");
}

// A 20 m x 20 m building (issue 30): the structure block is validated field by field; a valid one
// parses, its area the footprint buffered by the standoff (round corners: 20x20 + 4*20*15 + pi*15^2).
TEST(MissionParse, StructureIsValidatedFieldByField) {
  json j = base();
  j.erase("area");
  j.erase("spacing_m");
  j["camera"] = {{"altitude_m", 50}, {"hfov_deg", 73.4}, {"overlap", 0.5}};
  j["structure"] = {{"footprint", json::parse(R"({"type": "Polygon", "coordinates": [[[22.9, 40.6],
      [22.90024, 40.6], [22.90024, 40.60018], [22.9, 40.60018], [22.9, 40.6]]]})")},
                    {"height_m", 40},
                    {"standoff_m", 15}};
  {
    const uavcover::Mission m = parse_mission(j.dump());
    ASSERT_TRUE(m.structure.has_value());
    EXPECT_DOUBLE_EQ(m.structure->height_m, 40);
    EXPECT_DOUBLE_EQ(m.structure->standoff_m, 15);
    EXPECT_FALSE(m.structure->top);
    const uavcover::geodesy::LocalFrame f(uavcover::geodesy::centroid(m.area));
    const double a = uavcover::bg::area(uavcover::geometry::unite(uavcover::geometry::to_local(m.area, f)));
    const double side = 20.3;  // 0.00024 deg of longitude at 40.6 N is 20.3 m, 0.00018 deg of latitude 20.0 m
    EXPECT_NEAR(a, side * 20.0 + 2 * (side + 20.0) * 15 + 3.14159 * 225, 0.02 * a);
    // the normalised mission (plan.json, the store) is written as its structure, not its buffered area, and
    // reads back the same
    const json back = json::parse(uavcover::mission_to_json(m));
    EXPECT_FALSE(back.contains("area"));
    ASSERT_TRUE(back.contains("structure"));
    EXPECT_FALSE(back["structure"].contains("safe_height_m")) << "the default is left out";
    const uavcover::Mission again = parse_mission(back.dump());
    ASSERT_TRUE(again.structure.has_value());
    EXPECT_EQ(again.structure->footprint, m.structure->footprint);
    EXPECT_DOUBLE_EQ(again.structure->height_m, 40);
    EXPECT_DOUBLE_EQ(again.structure->standoff_m, 15);
    EXPECT_EQ(again.area, m.area);
    json safe = j;
    safe["structure"]["safe_height_m"] = 8;
    safe["structure"]["top"] = true;
    const json b2 = json::parse(uavcover::mission_to_json(parse_mission(safe.dump())));
    EXPECT_DOUBLE_EQ(b2["structure"]["safe_height_m"].get<double>(), 8);
    EXPECT_EQ(b2["structure"]["top"], true);
  }
  json k = j;
  k["structure"]["standoff_m"] = 0;
  expect_error(k, "structure.standoff_m", "> 0");
  k = j;
  k["structure"]["height_m"] = -3;
  expect_error(k, "structure.height_m", "");
  k = j;
  k["structure"].erase("height_m");
  expect_error(k, "structure.height_m", "missing");
  k = j;
  k.erase("camera");
  expect_error(k, "camera", "camera block");
  k = j;
  k["area"] = base()["area"];
  expect_error(k, "structure", "one of area");
  k = j;
  k["structure"]["footprint"]["coordinates"] =
      json::parse("[[[22.9, 40.6], [22.90024, 40.60018], [22.90024, 40.6], [22.9, 40.60018], [22.9, 40.6]]]");
  try {
    parse_mission(k.dump());
    FAIL() << "accepted a self-intersecting footprint";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.field()).rfind("structure.footprint", 0), 0u) << e.what();
  }
}

TEST(MissionParse, WindBlockParsesRoundTripsAndRefusesWhatCannotBeFlown) {
  auto j = base();
  j["uavs"][0]["speed_mps"] = 12;
  j["uavs"][1]["speed_mps"] = 10;
  j["wind"] = {{"speed_mps", 8}, {"from_deg", 270}};
  const auto m = parse_mission(j.dump());
  ASSERT_TRUE(m.wind.has_value());
  EXPECT_DOUBLE_EQ(m.wind->speed_mps, 8.0);
  EXPECT_DOUBLE_EQ(m.wind->from_deg, 270.0);
  const auto again = parse_mission(uavcover::mission_to_json(m));
  ASSERT_TRUE(again.wind.has_value());
  EXPECT_DOUBLE_EQ(again.wind->speed_mps, 8.0);
  EXPECT_DOUBLE_EQ(again.wind->from_deg, 270.0);
  // no wind given: none parsed and none written
  EXPECT_FALSE(parse_mission(base().dump()).wind.has_value());
  EXPECT_EQ(json::parse(uavcover::mission_to_json(parse_mission(base().dump()))).count("wind"), 0u);

  auto with = [&](const json& w) {
    auto k = j;
    k["wind"] = w;
    return k;
  };
  expect_error(with({{"speed_mps", -1}, {"from_deg", 0}}), "wind.speed_mps", "must be in");
  expect_error(with({{"speed_mps", 5}, {"from_deg", 360}}), "wind.from_deg", "must be in");
  expect_error(with({{"speed_mps", 5}, {"from_deg", -10}}), "wind.from_deg", "must be in");
  expect_error(with({{"from_deg", 10}}), "wind.speed_mps", "missing");
  expect_error(with({{"speed_mps", 5}, {"gust_mps", 9}}), "wind.gust_mps", "unknown field");
  expect_error(with("strong"), "wind", "expected an object");
  // uav "b" flies 10 m/s: a 10 m/s wind leaves it no ground speed into the wind
  expect_error(with({{"speed_mps", 10}, {"from_deg", 90}}), "wind.speed_mps", "cannot be flown");
}

// Issue 31: rally points, resume with overlap, vehicle profiles; each refusal names its field, and the
// normalised mission writes them back.
TEST(MissionParse, RallyBackoffAndVehicleProfile) {
  auto j = base();
  j["no_fly_zones"] = json::parse(
      R"([{"type": "Polygon", "coordinates": [[[22.905, 40.603], [22.906, 40.603], [22.906, 40.604], [22.905, 40.604]]]}])");
  j["rally"] = json::parse("[[22.899, 40.599], [22.91, 40.605]]");
  j["resume_backoff_m"] = 12.5;
  j["autopilot"] = "ardupilot";
  j["max_mission_items"] = 1200;
  j["uavs"][1]["autopilot"] = "px4";
  const auto m = parse_mission(j.dump());
  ASSERT_EQ(m.rally.size(), 2u);
  EXPECT_DOUBLE_EQ(m.rally[1].lon, 22.91);
  EXPECT_EQ(*m.resume_backoff_m, 12.5);
  EXPECT_EQ(m.autopilot, "ardupilot");
  EXPECT_EQ(*m.max_mission_items, 1200);
  EXPECT_EQ(m.uavs[0].autopilot, "");
  EXPECT_EQ(m.uavs[1].autopilot, "px4");
  const auto again = parse_mission(uavcover::mission_to_json(m));
  EXPECT_EQ(again.rally, m.rally);
  EXPECT_EQ(again.resume_backoff_m, m.resume_backoff_m);
  EXPECT_EQ(again.autopilot, "ardupilot");
  EXPECT_EQ(again.max_mission_items, m.max_mission_items);
  EXPECT_EQ(again.uavs[1].autopilot, "px4");

  auto bad = j;
  bad["rally"] = json::parse("[[22.9055, 40.6035]]");
  expect_error(bad, "rally[0]", "no-fly zone");
  bad["rally"] = json::parse("[[23.2, 40.6]]");
  expect_error(bad, "rally[0]", "km from the area");
  bad["rally"] = json::parse("[[22.9, 95]]");
  expect_error(bad, "rally[0]", "");
  bad["rally"] = "here";
  expect_error(bad, "rally", "array");
  bad = j;
  bad["propose_rally"] = true;
  expect_error(bad, "propose_rally", "not both");
  bad["propose_rally"] = "yes";
  expect_error(bad, "propose_rally", "true or false");
  bad = j;
  bad["resume_backoff_m"] = -1;
  expect_error(bad, "resume_backoff_m", "");
  bad = j;
  bad["autopilot"] = "inav";
  expect_error(bad, "autopilot", "\"px4\", \"ardupilot\", \"dji\", \"litchi\"");
  bad = j;
  bad["uavs"][0]["autopilot"] = 3;
  expect_error(bad, "uavs[0].autopilot", "");
  bad = j;
  bad["max_mission_items"] = 2.5;
  expect_error(bad, "max_mission_items", "integer");
  bad["max_mission_items"] = 70000;
  expect_error(bad, "max_mission_items", "65535");
}
