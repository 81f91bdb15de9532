// POST /api/v1/missions/import: a multipart upload of files ogr2ogr writes at test time (a zipped
// Shapefile in UTM, a KMZ, a GeoPackage) -> the mission skeleton, which POST /missions then stores;
// bad framing, parts and files are 4xx naming the field. The strict multipart parser on its own.
#include <gtest/gtest.h>

#include "server/api_fixture.hpp"
#include "server/http.hpp"
#include "server/multipart.hpp"
#include "support/vector_files.hpp"

namespace uavcover::server::testing {
namespace {

using nlohmann::json;

class ImportApi : public ApiTest {
 protected:
  Answer upload(const std::string& body, std::map<std::string, std::string> headers = kHeaders) {
    return call("POST", "/api/v1/missions/import", body, std::move(headers));
  }
};

TEST_P(ImportApi, ZippedUtmShapefileKmzAndGeoPackageBecomeMissions) {
  testvec::TempDir dir("api");
  const auto zip = testvec::zipped_shapefile(dir.path, 32634);
  const auto kmz = testvec::kmz(dir.path);
  const auto gpkg = testvec::ogr2ogr(dir.path, "f.gpkg", "-f GPKG -t_srs EPSG:2100 -nln parcels");
  for (const auto& [file, name] : {std::pair{zip, "fields.zip"}, {kmz, "fields.kmz"}, {gpkg, "f.gpkg"}}) {
    const Answer a = upload(form(part("file", name, testvec::read_bytes(file))));
    ASSERT_EQ(a.status, 200) << name << ": " << a.body;
    const json m = a.json();
    EXPECT_EQ(m["name"], "North field") << name;
    EXPECT_EQ(m["no_fly_zones"].size(), 2U) << name;
    EXPECT_NEAR(m["area"]["coordinates"][0][0][1].get<double>(), 40.6035, 0.0036) << name;  // WGS84 latitude
    EXPECT_EQ(create_mission(m.dump()) > 0, true);  // the web stores it as any mission
  }
  // options: the layer, the area by attribute, a template
  const json options = {
      {"layer", "parcels"}, {"area_where", "name = 'Barn'"}, {"template", {{"uavs", 2}, {"spacing_m", 15}}}};
  const Answer a =
      upload(form(part("file", "f.gpkg", testvec::read_bytes(gpkg)) + part("options", "", options.dump())));
  ASSERT_EQ(a.status, 200) << a.body;
  EXPECT_EQ(a.json()["name"], "Barn");
  EXPECT_EQ(a.json()["uavs"], 2);
  EXPECT_EQ(upload(form(part("file", "f.gpkg", testvec::read_bytes(gpkg)) +
                        part("options", "", R"({"layer": "roads"})")))
                .error_field(),
            "layer");
}

TEST_P(ImportApi, BadUploadsAre4xxNamingTheField) {
  const std::string good = part("file", "f.geojson", testvec::kFeatures);
  EXPECT_EQ(upload(form(good)).status, 200);
  Answer a = upload(form(good), {{"content-type", "application/json"}});
  EXPECT_EQ(a.status, 415);
  EXPECT_EQ(a.error_field(), "content-type");
  EXPECT_EQ(upload(form(good), {{"content-type", "multipart/form-data"}}).error_field(), "content-type");
  EXPECT_EQ(upload(form("")).error_field(), "file");                                    // no file part
  EXPECT_EQ(upload(form(part("file", "", testvec::kFeatures))).error_field(), "file");  // no filename
  EXPECT_EQ(upload(form(good + part("extra", "", "x"))).error_field(), "extra");
  EXPECT_EQ(upload(form(good + good)).error_field(), "file");  // twice
  EXPECT_EQ(upload(good).error_field(), "file");               // never closed
  EXPECT_EQ(upload("garbage").error_field(), "body");
  EXPECT_EQ(upload(form(good + part("options", "", "{bad"))).status, 400);
  EXPECT_EQ(upload(form(good + part("options", "", "[]"))).error_field(), "options");
  EXPECT_EQ(upload(form(good + part("options", "", R"({"colour": "red"})"))).error_field(), "options.colour");
  EXPECT_EQ(upload(form(good + part("options", "", R"({"layer": 3})"))).error_field(), "options.layer");
  a = upload(form(part("file", "f.geojson", testvec::kBowTie)));
  EXPECT_EQ(a.status, 422);
  EXPECT_EQ(a.error_field(), "file");
  EXPECT_NE(a.body.find("Twisted"), std::string::npos) << a.body;
  EXPECT_EQ(upload(form(part("file", "../../etc/passwd", "root:x:0:0"))).error_field(), "file");
}

TEST(Multipart, ParsesStrictly) {
  const std::string ct = "multipart/form-data; boundary=\"" + kBoundary + "\"";
  const auto parts = parse_multipart(
      ct, "preamble\r\n" + form(part("file", "a \\\"b\\\".kml", "x\r\n--y") + part("o", "", "")));
  ASSERT_EQ(parts.size(), 2U);
  EXPECT_EQ(parts[0].name, "file");
  EXPECT_EQ(*parts[0].filename, "a \"b\".kml");
  EXPECT_EQ(parts[0].body, "x\r\n--y");  // a body may hold CRLF and dashes
  EXPECT_EQ(parts[0].content_type, "application/octet-stream");
  EXPECT_FALSE(parts[1].filename);
  EXPECT_EQ(parts[1].body, "");
  std::string many;
  for (int i = 0; i < 17; ++i) many += part("p" + std::to_string(i), "", "");
  EXPECT_THROW(parse_multipart(ct, form(many)), HttpError);
  // every prefix of a good body is refused, never read past its end
  const std::string body = form(part("file", "a.kml", "hello"));
  for (std::size_t n = 0; n < body.size() - 2; ++n)
    EXPECT_THROW(parse_multipart(ct, body.substr(0, n)), HttpError) << n;
  EXPECT_THROW(parse_multipart("multipart/form-data; boundary=" + std::string(71, 'a'), body), HttpError);
}

INSTANTIATE_TEST_SUITE_P(Sqlite, ImportApi, ::testing::Values(std::string("sqlite:")), backend_name);

}  // namespace
}  // namespace uavcover::server::testing
