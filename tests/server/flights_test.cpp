// The flight routes (docs/flights.md) over a real store (SQLite and PostgreSQL): a small field planned by
// a WorkerPool, then flights: validation with the field named (404, 409, 422), and a simulated flight
// on loopback that uploads, starts, flies and ends done with every waypoint reached in its log.
// Waits are bounded by wall-time caps only against hangs; nothing asserts a duration.
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <thread>

#include "geodesy/local_frame.hpp"
#include "io/exif.hpp"
#include "server/api_fixture.hpp"
#include "server/multipart.hpp"
#include "server/worker.hpp"
#include "support/photos.hpp"
#include "usecases/refly.hpp"

namespace uavcover::server::testing {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

/// A 150 m x 100 m field, two UAVs 30 m apart south of it, scanned every 25 m at 20 m.
std::string small_field() {
  constexpr double lon0 = 22.95, lat0 = 40.60, mlat = 1.0 / 111320.0;
  const double mlon = mlat / std::cos(lat0 * M_PI / 180.0);
  auto at = [&](double x, double y) { return json::array({lon0 + x * mlon, lat0 + y * mlat}); };
  json uavs = json::array();
  for (int i = 0; i < 2; ++i)
    uavs.push_back({{"id", std::string(1, static_cast<char>('A' + i))},
                    {"start", at(10.0 + 30.0 * i, -20.0)},
                    {"speed_mps", 8},
                    {"endurance_min", 30}});
  json doc{{"name", "flight field"},
           {"area",
            {{"type", "Polygon"},
             {"coordinates",
              json::array({json::array({at(0, 0), at(150, 0), at(150, 100), at(0, 100), at(0, 0)})})}}},
           {"spacing_m", 25},
           {"altitude_m", 20},
           {"uavs", uavs},
           {"seed", 7}};
  return doc.dump();
}

class FlightApiTest : public ApiTest {
 protected:
  /// A done plan job of the small field; its id.
  store::Id done_plan() { return done_plan(create_mission(small_field())); }
  /// A done plan job of the mission `mission_id`; its id.
  store::Id done_plan(store::Id mission_id) {
    const Answer a = call("POST", "/api/v1/missions/" + std::to_string(mission_id) + "/plans", "{}");
    EXPECT_EQ(a.status, 202) << a.body;
    const auto id = a.json().at("id").get<store::Id>();
    WorkerConfig config;
    config.lease = 2000ms;
    config.heartbeat = 100ms;
    config.idle = 20ms;
    WorkerPool pool(*store_, config);
    pool.start();
    const auto cap = Clock::now() + 120s;
    while (Clock::now() < cap && call("GET", plan_url(id)).json().at("state") != "done")
      std::this_thread::sleep_for(20ms);
    pool.stop();
    EXPECT_EQ(call("GET", plan_url(id)).json().at("state"), "done");
    return id;
  }
  static std::string plan_url(store::Id id) { return "/api/v1/plans/" + std::to_string(id); }

  /// Polls the flight until `until` holds (or a wall-time cap against hangs); the last Flight JSON.
  json wait_flight(store::Id id, const std::function<bool(const json&)>& until,
                   std::chrono::seconds cap = 120s) {
    const auto end = Clock::now() + cap;
    json f;
    while (Clock::now() < end) {
      const Answer a = call("GET", "/api/v1/flights/" + std::to_string(id));
      EXPECT_EQ(a.status, 200) << a.body;
      f = a.json();
      if (until(f)) break;
      std::this_thread::sleep_for(20ms);
    }
    return f;
  }

  Answer post_flight(store::Id plan, const json& body) {
    return call("POST", plan_url(plan) + "/flights", body.dump());
  }
};

TEST_P(FlightApiTest, RequestsAreValidatedWithTheFieldNamed) {
  const store::Id plan = done_plan();
  auto expect_error = [&](const Answer& a, int status, const std::string& field) {
    EXPECT_EQ(a.status, status) << a.body;
    if (a.status == status) {
      EXPECT_EQ(a.error_field(), field) << a.body;
    }
  };
  expect_error(post_flight(987654, {{"simulate", json::object()}}), 404, "id");
  expect_error(call("POST", plan_url(plan) + "/flights", ""), 400, "body");
  expect_error(post_flight(plan, json::array()), 422, "");
  expect_error(post_flight(plan, {{"simulate", {{"speedup", 0}}}}), 422, "simulate.speedup");
  expect_error(post_flight(plan, {{"simulate", {{"loss", 0.95}}}}), 422, "simulate.loss");
  expect_error(post_flight(plan, {{"simulate", {{"fail", "9@0.5"}}}}), 422, "simulate.fail");
  expect_error(post_flight(plan, {{"simulate", {{"fail", "1@1.5"}}}}), 422, "simulate.fail");
  expect_error(post_flight(plan, {{"simulate", {{"battery_min", 0.1}}}}), 422, "simulate.battery_min");
  expect_error(post_flight(plan, {{"simulate", {{"colour", "red"}}}}), 422, "simulate.colour");
  expect_error(post_flight(plan, {{"simulate", {{"transport", "serial"}}}}), 422, "simulate.transport");
  expect_error(post_flight(plan, {{"vehicles", {{{"uav", "A"}, {"endpoint", "serial:/dev/ttyUSB0:1234"}}}}}),
               422, "vehicles[0].endpoint");
  expect_error(post_flight(plan, {{"vehicles", {{{"uav", "A"}, {"endpoint", "serial:/tmp/tty:57600"}}}}}),
               422, "vehicles[0].endpoint");
  expect_error(
      post_flight(plan,
                  {{"vehicles", {{{"uav", "A"}, {"endpoint", "tcpin:127.0.0.1:5760"}, {"listen", false}}}}}),
      422, "vehicles[0].listen");
  expect_error(post_flight(plan, {{"simulate", json::object()},
                                  {"vehicles", {{{"uav", "A"}, {"endpoint", "udp:127.0.0.1:14550"}}}}}),
               422, "simulate");
  expect_error(post_flight(plan, {{"vehicles", {{{"uav", "Z"}, {"endpoint", "udp:127.0.0.1:14550"}}}}}), 422,
               "vehicles[0].uav");
  expect_error(post_flight(plan, {{"vehicles",
                                   {{{"uav", "A"}, {"endpoint", "udp:127.0.0.1:14550"}},
                                    {{"uav", "B"}, {"endpoint", "ftp:127.0.0.1:1"}}}}}),
               422, "vehicles[1].endpoint");
  // the server has no token here: vehicles beyond loopback are refused
  expect_error(post_flight(plan, {{"vehicles", {{{"uav", "A"}, {"endpoint", "udp:10.1.2.3:14550"}}}}}), 422,
               "vehicles[0].endpoint");
  expect_error(post_flight(plan, {{"simulate", json::object()}, {"link_timeout_s", -1}}), 422,
               "link_timeout_s");
  // issue 33: the task manager's fields
  expect_error(post_flight(plan, {{"simulate", json::object()}, {"waypoint_retries", 11}}), 422,
               "waypoint_retries");
  expect_error(post_flight(plan, {{"simulate", json::object()}, {"reassign_from", "sky"}}), 422,
               "reassign_from");
  expect_error(post_flight(plan, {{"simulate", {{"fail", "1@0.5:jam"}}}}), 422, "simulate.fail");
  EXPECT_TRUE(call("GET", plan_url(plan) + "/flights").json().at("items").empty()) << "nothing was stored";

  // a plan that is not done cannot fly
  const auto mission_id = create_mission(small_field());
  const Answer queued = call("POST", "/api/v1/missions/" + std::to_string(mission_id) + "/plans", "{}");
  expect_error(post_flight(queued.json().at("id").get<store::Id>(), {{"simulate", json::object()}}), 409,
               "state");

  expect_error(call("GET", "/api/v1/flights/987654"), 404, "id");
  expect_error(call("GET", "/api/v1/flights/x"), 400, "id");
  expect_error(call("GET", "/api/v1/flights/987654/log"), 404, "id");
  expect_error(call("GET", "/api/v1/flights/987654/log.csv"), 404, "id");
  expect_error(call("DELETE", "/api/v1/flights/987654"), 404, "id");
  expect_error(call("POST", "/api/v1/flights/987654/commands", R"({"command": "start"})"), 404, "id");
  expect_error(call("GET", "/api/v1/plans/987654/flights"), 404, "id");
}

TEST_P(FlightApiTest, CommandsAreCheckedAgainstTheFlightsState) {
  const store::Id plan = done_plan();
  const Answer created = post_flight(plan, {{"simulate", {{"speedup", 20}, {"fail", "1@0.5:stuck"}}},
                                            {"waypoint_retries", 3},
                                            {"reassign_from", "air"}});
  ASSERT_EQ(created.status, 201) << created.body;
  const json flight = created.json();
  EXPECT_EQ(flight.at("config").at("waypoint_retries"), 3);
  EXPECT_EQ(flight.at("config").at("reassign_from"), "air");
  EXPECT_EQ(flight.at("uavs")[0].at("retries").at("total"), 0);
  const auto id = flight.at("id").get<store::Id>();
  EXPECT_EQ(created.header("Location"), "/api/v1/flights/" + std::to_string(id));
  EXPECT_EQ(flight.at("plan_id"), plan);
  EXPECT_EQ(flight.at("simulated"), true);
  EXPECT_EQ(flight.at("state"), "created");
  ASSERT_EQ(flight.at("uavs").size(), 2u);
  for (const auto& v : flight.at("config").at("vehicles"))
    EXPECT_TRUE(v.at("endpoint").get<std::string>().starts_with("udp:127.0.0.1:")) << v;
  const std::string url = "/api/v1/flights/" + std::to_string(id);

  Answer a = call("POST", url + "/commands", R"({"command": "fly"})");
  EXPECT_EQ(a.status, 422);
  EXPECT_EQ(a.error_field(), "command");
  a = call("POST", url + "/commands", R"({"command": "pause"})");
  EXPECT_EQ(a.status, 409) << "nothing flies yet: " << a.body;
  EXPECT_EQ(a.error_field(), "command");
  a = call("POST", url + "/commands", R"({"command": "upload", "uav": "Q"})");
  EXPECT_EQ(a.status, 422) << a.body;
  // the reassignment's choice goes with reassign only, and must be home or air; nothing is offered yet
  a = call("POST", url + "/commands", R"({"command": "start", "reassign_from": "air"})");
  EXPECT_EQ(a.status, 422) << a.body;
  EXPECT_EQ(a.error_field(), "reassign_from");
  a = call("POST", url + "/commands", R"({"command": "reassign", "reassign_from": "up"})");
  EXPECT_EQ(a.status, 422) << a.body;
  EXPECT_EQ(a.error_field(), "reassign_from");
  a = call("POST", url + "/commands", R"({"command": "reassign", "reassign_from": "air"})");
  EXPECT_EQ(a.status, 409) << a.body;

  const json listed = call("GET", plan_url(plan) + "/flights").json();
  ASSERT_EQ(listed.at("items").size(), 1u);
  EXPECT_EQ(listed["items"][0].at("id"), id);
  EXPECT_FALSE(listed["items"][0].at("uavs")[0].contains("waypoints")) << "the listing leaves them out";

  // DELETE stops following: the flight ends aborted and commands are refused
  a = call("DELETE", url);
  ASSERT_EQ(a.status, 200) << a.body;
  EXPECT_EQ(a.json().at("state"), "aborted");
  EXPECT_EQ(flights_->live_count(), 0u);
  EXPECT_EQ(call("GET", url).json().at("state"), "aborted");
  a = call("POST", url + "/commands", R"({"command": "upload"})");
  EXPECT_EQ(a.status, 409) << a.body;
  bool aborted_record = false;
  const json log = call("GET", url + "/log?limit=1000").json();
  for (const auto& r : log.at("items"))
    aborted_record = aborted_record || (r.at("kind") == "state" && r.at("data").at("state") == "aborted");
  EXPECT_TRUE(aborted_record);
  // a second DELETE removes the ended flight and its log
  EXPECT_EQ(call("DELETE", url).status, 200);
  EXPECT_EQ(call("GET", url).status, 404);
  EXPECT_EQ(call("GET", url + "/log").status, 404);
}

// A server that starts again follows its stored flights that had not ended (from their snapshots); a
// simulated one cannot be (its fleet ran in the stopped server): it ends aborted, saying why.
TEST_P(FlightApiTest, AtStartFlightsThatHadNotEndedAreFollowedAgainOrAbortedWhenSimulated) {
  const store::Id plan = done_plan();
  const Answer sim = post_flight(plan, {{"simulate", json::object()}});
  ASSERT_EQ(sim.status, 201) << sim.body;
  const Answer real = post_flight(plan, {{"vehicles",
                                          {{{"uav", "A"}, {"endpoint", "udp:127.0.0.1:9"}, {"sysid", 1}},
                                           {{"uav", "B"}, {"endpoint", "udp:127.0.0.1:9"}, {"sysid", 2}}}}});
  ASSERT_EQ(real.status, 201) << real.body;
  const auto sim_id = sim.json().at("id").get<store::Id>();
  const auto real_id = real.json().at("id").get<store::Id>();
  EXPECT_EQ(flights_->live_count(), 2u);

  // the server stops (the vehicles would keep flying) and starts again on the same database
  flights_->stop();
  FlightLimits limits;
  limits.flush_period = 50ms;
  flights_ = std::make_unique<FlightManager>(*store_, limits);
  ctx_->flights = flights_.get();
  flights_->start();

  EXPECT_EQ(flights_->live_count(), 1u);
  const json again = call("GET", "/api/v1/flights/" + std::to_string(real_id)).json();
  EXPECT_EQ(again.at("state"), "created");
  EXPECT_EQ(again.at("config"), real.json().at("config"));
  EXPECT_EQ(
      call("POST", "/api/v1/flights/" + std::to_string(real_id) + "/commands", R"({"command": "pause"})")
          .status,
      409)
      << "followed: its commands are checked against its state";

  EXPECT_EQ(call("GET", "/api/v1/flights/" + std::to_string(sim_id)).json().at("state"), "aborted");
  const json log = call("GET", "/api/v1/flights/" + std::to_string(sim_id) + "/log?limit=1000").json();
  ASSERT_FALSE(log.at("items").empty());
  const json& last = log.at("items").back();
  EXPECT_EQ(last.at("kind"), "state");
  EXPECT_EQ(last.at("data").at("state"), "aborted");
  EXPECT_NE(last.at("data").at("reason").get<std::string>().find("simulated fleet"), std::string::npos);
}

TEST_P(FlightApiTest, AMissionListsItsFlightsThatHaveNotEndedWhateverTheirPlan) {
  const auto mission = create_mission(small_field());
  const store::Id first = done_plan(mission);
  const auto vehicles = json{{"vehicles",
                              {{{"uav", "A"}, {"endpoint", "udp:127.0.0.1:9"}, {"sysid", 1}},
                               {{"uav", "B"}, {"endpoint", "udp:127.0.0.1:9"}, {"sysid", 2}}}}};
  const Answer a = post_flight(first, vehicles);
  ASSERT_EQ(a.status, 201) << a.body;
  const auto flight_a = a.json().at("id").get<store::Id>();
  // the mission is planned again: the flight of its first plan is still the mission's
  const store::Id second = done_plan(mission);
  ASSERT_NE(second, first);
  const Answer b = post_flight(second, vehicles);
  ASSERT_EQ(b.status, 201) << b.body;
  const auto flight_b = b.json().at("id").get<store::Id>();
  const auto other = create_mission(small_field());

  const std::string url = "/api/v1/missions/" + std::to_string(mission) + "/flights";
  auto ids = [&](const std::string& u) {
    const Answer r = call("GET", u);
    EXPECT_EQ(r.status, 200) << r.body;
    std::vector<store::Id> out;
    const json body = r.json();  // kept: a range-for over a temporary's member would dangle
    for (const auto& f : body.at("items")) {
      EXPECT_EQ(f.at("mission_id").get<store::Id>(), mission) << f.dump();
      EXPECT_TRUE(f.contains("plan_id")) << f.dump();
      for (const auto& u : f.at("uavs"))
        EXPECT_FALSE(u.contains("waypoints")) << "the listing leaves them out";
      out.push_back(f.at("id").get<store::Id>());
    }
    return out;
  };
  EXPECT_EQ(ids(url), (std::vector<store::Id>{flight_b, flight_a})) << "newest first, both plans";
  EXPECT_TRUE(ids("/api/v1/missions/" + std::to_string(other) + "/flights").empty());

  // a flight that ended (DELETE: aborted) is no longer listed
  ASSERT_EQ(call("DELETE", "/api/v1/flights/" + std::to_string(flight_a)).status, 200);
  EXPECT_EQ(ids(url), (std::vector<store::Id>{flight_b}));
  ASSERT_EQ(call("DELETE", "/api/v1/flights/" + std::to_string(flight_b)).status, 200);
  EXPECT_TRUE(ids(url).empty());

  const Answer missing = call("GET", "/api/v1/missions/987654/flights");
  EXPECT_EQ(missing.status, 404) << missing.body;
  EXPECT_EQ(missing.error_field(), "id") << missing.body;
  EXPECT_EQ(call("GET", "/api/v1/missions/x/flights").status, 400);
}

TEST_P(FlightApiTest, ASimulatedFlightEndsDoneWithEveryWaypointReachedInItsLog) {
  const store::Id plan = done_plan();
  const Answer created = post_flight(plan, {{"simulate", {{"speedup", 50}}}, {"log_period_s", 0.05}});
  ASSERT_EQ(created.status, 201) << created.body;
  const auto id = created.json().at("id").get<store::Id>();
  const std::string url = "/api/v1/flights/" + std::to_string(id);

  ASSERT_EQ(call("POST", url + "/commands", R"({"command": "upload"})").status, 202);
  json f = wait_flight(id, [](const json& j) { return j.at("state") == "ready"; });
  ASSERT_EQ(f.at("state"), "ready") << f.dump();
  const Answer started = call("POST", url + "/commands", R"({"command": "start"})");
  ASSERT_EQ(started.status, 202) << started.body;
  f = wait_flight(id, [](const json& j) { return j.at("state") == "done" || j.at("state") == "aborted"; });
  ASSERT_EQ(f.at("state"), "done") << f.dump();
  std::map<std::string, std::size_t> waypoints;  // per UAV: its coverage waypoints, every one reached
  for (const auto& u : f.at("uavs")) {
    const std::string w = u.at("waypoints");
    EXPECT_FALSE(w.empty());
    EXPECT_EQ(w, std::string(w.size(), 'R')) << u.at("uav");
    waypoints[u.at("uav")] = w.size();
  }

  // the writer stores the end: the flight is no longer followed, its stored state is done
  const auto cap = Clock::now() + 30s;
  while (flights_->live_count() > 0 && Clock::now() < cap) std::this_thread::sleep_for(20ms);
  EXPECT_EQ(flights_->live_count(), 0u);
  EXPECT_EQ(store_->get_flight(id)->state, "done");

  // the log, page by page: every coverage waypoint of every UAV reached, telemetry per UAV, seqs in order
  std::map<std::string, std::set<int>> reached;
  std::map<std::string, int> telemetry;
  std::int64_t last_seq = 0, after = 0;
  int pages = 0;
  for (;;) {
    const Answer page = call("GET", url + "/log?limit=20&after=" + std::to_string(after));
    ASSERT_EQ(page.status, 200) << page.body;
    ++pages;
    const json body = page.json();
    for (const auto& r : body.at("items")) {
      EXPECT_GT(r.at("seq").get<std::int64_t>(), last_seq);
      last_seq = r.at("seq");
      if (r.at("kind") == "waypoint" && r.at("data").at("status") == "R")
        reached[r.at("uav")].insert(r.at("data").at("waypoint").get<int>());
      // (before its first position a UAV's telemetry has no lon/lat: not a track point)
      if (r.at("kind") == "telemetry" && r.at("data").at("lon").is_number()) ++telemetry[r.at("uav")];
    }
    if (body.at("next_after").is_null()) break;
    after = body.at("next_after");
  }
  EXPECT_GT(pages, 1);
  for (const auto& [uav, n] : waypoints) {
    EXPECT_EQ(reached[uav].size(), n) << uav;
    EXPECT_GT(telemetry[uav], 2) << uav;
  }

  const Answer csv = call("GET", url + "/log.csv");
  ASSERT_EQ(csv.status, 200);
  EXPECT_EQ(csv.content_type, "text/csv");
  EXPECT_TRUE(csv.body.starts_with("seq,time,uav,kind,lon,lat,alt_m,speed_mps,battery_pct,data\n"));
  EXPECT_EQ(static_cast<std::int64_t>(std::count(csv.body.begin(), csv.body.end(), '\n')), last_seq + 1)
      << "one line per record and the header";

  const Answer geo = call("GET", url + "/log.geojson");
  ASSERT_EQ(geo.status, 200);
  std::set<std::string> tracks;
  int points = 0;
  const json collection = geo.json();
  for (const auto& feature : collection.at("features")) {
    if (feature.at("properties").at("kind") == "track") {
      EXPECT_EQ(feature.at("geometry").at("type"), "LineString");
      EXPECT_EQ(feature.at("geometry").at("coordinates").size(),
                static_cast<std::size_t>(telemetry[feature.at("properties").at("uav")]));
      tracks.insert(feature.at("properties").at("uav"));
    } else if (!feature.at("geometry").is_null()) {
      EXPECT_EQ(feature.at("geometry").at("type"), "Point");
      ++points;
    }
  }
  EXPECT_EQ(tracks, (std::set<std::string>{"A", "B"}));
  EXPECT_GT(points, 0);
  const Tracks flown = flights_->tracks(id);
  ASSERT_EQ(flown.size(), 2u) << "tracks of an ended flight come from its log";

  // flown coverage through the plan's evaluator: the nominal flight covers what the plan covers (issue 12:
  // flown PoC at least planned PoC - 1 point). The flight ended: its tracks come from the log's telemetry,
  // kept every log_period_s of wall time (0.05 s here: 2.5 simulated s at speedup 50)
  const Answer cov = call("GET", url + "/coverage");
  ASSERT_EQ(cov.status, 200) << cov.body;
  const json c = cov.json();
  EXPECT_GT(c.at("planned_poc").get<double>(), 0.5);
  EXPECT_GE(c.at("flown_poc").get<double>(), c.at("planned_poc").get<double>() - 0.01) << c.dump();
  const auto& b = c.at("bounds");
  EXPECT_LT(b[0][0].get<double>(), b[1][0].get<double>());
  EXPECT_LT(b[0][1].get<double>(), b[1][1].get<double>());
  const Answer png = call("GET", url + "/coverage.png");
  ASSERT_EQ(png.status, 200);
  EXPECT_EQ(png.content_type, "image/png");
  EXPECT_TRUE(png.body.starts_with("\x89PNG")) << png.body.substr(0, 8);
  EXPECT_EQ(call("GET", "/api/v1/flights/987654/coverage").status, 404);
}

// Issue 34: the same flight with the simulated vehicles listening on TCP and the server connecting.
TEST_P(FlightApiTest, ASimulatedFlightOverTcpEndsDone) {
  const store::Id plan = done_plan();
  const Answer created = post_flight(plan, {{"simulate", {{"speedup", 50}, {"transport", "tcp"}}}});
  ASSERT_EQ(created.status, 201) << created.body;
  const json flight = created.json();
  for (const auto& v : flight.at("config").at("vehicles"))
    EXPECT_TRUE(v.at("endpoint").get<std::string>().starts_with("tcp:127.0.0.1:")) << v.dump();
  const auto id = flight.at("id").get<store::Id>();
  const std::string url = "/api/v1/flights/" + std::to_string(id);
  ASSERT_EQ(call("POST", url + "/commands", R"({"command": "upload"})").status, 202);
  json f = wait_flight(id, [](const json& j) { return j.at("state") == "ready"; });
  ASSERT_EQ(f.at("state"), "ready") << f.dump();
  ASSERT_EQ(call("POST", url + "/commands", R"({"command": "start"})").status, 202);
  f = wait_flight(id, [](const json& j) { return j.at("state") == "done" || j.at("state") == "aborted"; });
  ASSERT_EQ(f.at("state"), "done") << f.dump();
  for (const auto& u : f.at("uavs")) {
    const std::string w = u.at("waypoints");
    EXPECT_FALSE(w.empty());
    EXPECT_EQ(w, std::string(w.size(), 'R')) << u.at("uav");
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, FlightApiTest, ::testing::ValuesIn(uavcover::testing::store_test_urls()),
                         backend_name);

}  // namespace
}  // namespace uavcover::server::testing

namespace uavcover::server::testing {
namespace {

/// A plan's paths as a flight log would record them (coverage at the mission's altitude, transit above).
flight::Track planned_track(const Plan& p, const UavPlan& u) {
  flight::Track t{u.id, {}};
  for (const auto& part : u.parts)
    for (const auto& v : part.wgs84)
      t.second.push_back(
          {v.lon, v.lat, part.kind == PartKind::Coverage ? p.mission.altitude_m : u.transition_altitude_m});
  return t;
}

TEST_P(FlightApiTest, AReflyPlansTheGapAFailedUavLeftAndTheTwoCoverTheField) {
  const store::Id plan = done_plan();
  // B's link fails after 40 % of its mission; nobody takes its work over (no reassignment)
  const Answer created =
      post_flight(plan, {{"simulate", {{"speedup", 50}, {"fail", "2@0.4:link"}}}, {"log_period_s", 0.05}});
  ASSERT_EQ(created.status, 201) << created.body;
  const auto id = created.json().at("id").get<store::Id>();
  const std::string url = "/api/v1/flights/" + std::to_string(id);
  ASSERT_EQ(call("POST", url + "/commands", R"({"command": "upload"})").status, 202);
  json f = wait_flight(id, [](const json& j) { return j.at("state") == "ready"; });
  ASSERT_EQ(f.at("state"), "ready") << f.dump();
  ASSERT_EQ(call("POST", url + "/commands", R"({"command": "start"})").status, 202);
  // until A has reached every coverage waypoint
  f = wait_flight(id, [](const json& j) {
    for (const auto& u : j.at("uavs"))
      if (u.at("uav") == "A") {
        const std::string w = u.at("waypoints");
        return !w.empty() && w == std::string(w.size(), 'R');
      }
    return false;
  });

  auto expect_error = [&](const Answer& a, int status, const std::string& field) {
    EXPECT_EQ(a.status, status) << a.body;
    if (a.status == status) {
      EXPECT_EQ(a.error_field(), field) << a.body;
    }
  };
  expect_error(call("POST", url + "/refly", R"({"uavs": ["Z"]})"), 422, "uavs");
  expect_error(call("POST", url + "/refly", R"({"uavs": "A"})"), 422, "uavs");
  expect_error(call("POST", "/api/v1/flights/987654/refly", "{}"), 404, "id");
  const Answer refly = call("POST", url + "/refly", R"({"uavs": ["A"]})");
  ASSERT_EQ(refly.status, 202) << refly.body;
  const auto refly_id = refly.json().at("id").get<store::Id>();
  const store::Job queued = *store_->get_job(refly_id);
  EXPECT_EQ(queued.mission_id, store_->get_job(plan)->mission_id) << "a plan of the same mission";
  const json& r = queued.params.at("refly");
  EXPECT_EQ(r.at("flight_id"), id);
  EXPECT_LT(r.at("flown_poc").get<double>(), 0.95);
  EXPECT_GT(r.at("gaps_m2").get<double>(), 0.0);
  ASSERT_EQ(r.at("mission").at("uavs").size(), 1u);
  EXPECT_EQ(r.at("mission").at("uavs")[0].at("id"), "A");

  // the worker plans it; the flight and the refly's paths cover the field
  WorkerConfig config;
  config.lease = 2000ms;
  config.idle = 20ms;
  WorkerPool pool(*store_, config);
  pool.start();
  const auto cap = Clock::now() + 120s;
  while (Clock::now() < cap && call("GET", plan_url(refly_id)).json().at("state") != "done")
    std::this_thread::sleep_for(20ms);
  pool.stop();
  ASSERT_EQ(call("GET", plan_url(refly_id)).json().at("state"), "done");
  const Plan first = load_job_plan(*store_, *store_->get_job(plan));
  const Plan second = load_job_plan(*store_, *store_->get_job(refly_id));
  EXPECT_NE(second.mission.name.find("(refly)"), std::string::npos);
  auto tracks = flights_->tracks(id);
  for (const auto& u : second.uavs) tracks.push_back(planned_track(second, u));
  const auto after = usecases::coverage_gaps(first, tracks);
  EXPECT_GE(after.flown_poc, 0.99) << "flown + refly";
  ASSERT_EQ(call("POST", url + "/commands", R"({"command": "abort"})").status / 100, 2);
}

/// A nadir photo 20 m above take-off at (x, y) metres from the small field's south-west corner, facing
/// north, 24 mm equivalent: a 30 m x 20 m footprint.
std::string field_photo(double x, double y) {
  return uavcover::testing::photo_jpeg(
      uavcover::testing::nadir_photo(geodesy::LocalFrame({22.95, 40.60}).to_wgs84(Point(x, y)), 20.0));
}

TEST_P(FlightApiTest, PhotosTagsCoverageAndAReflyFromThem) {
  const store::Id plan = done_plan();
  const Answer created = post_flight(plan, {{"simulate", {{"speedup", 50}}}});
  ASSERT_EQ(created.status, 201) << created.body;
  const auto id = created.json().at("id").get<store::Id>();
  const std::string url = "/api/v1/flights/" + std::to_string(id);
  auto upload = [&](const std::string& body, std::map<std::string, std::string> headers = kHeaders) {
    return call("POST", "/api/v1/photos/tags", body, std::move(headers));
  };

  // the tags of whole files and of a file's head (what the app sends: the tags come before the image)
  const std::string a = field_photo(10, 5), b = field_photo(35, 5);
  const std::size_t sos = b.find("\xFF\xDA");
  ASSERT_NE(sos, std::string::npos);
  Answer r = upload(form(part("photos", "a.jpg", a) + part("photos", "b.jpg", b.substr(0, sos + 20))));
  ASSERT_EQ(r.status, 200) << r.body;
  ASSERT_EQ(r.json().at("items").size(), 2u);
  EXPECT_EQ(r.json()["items"][1]["name"], "b.jpg");
  EXPECT_NEAR(r.json()["items"][1]["relative_altitude_m"].get<double>(), 20.0, 1e-9);
  EXPECT_EQ(upload(form(part("photos", "bad.jpg", "no jpeg"))).status, 422);
  EXPECT_EQ(upload(form(part("photos", "bad.jpg", "no jpeg"))).error_field(), "bad.jpg");
  EXPECT_EQ(upload(form(part("file", "a.jpg", a))).status, 400);
  EXPECT_EQ(upload(form(part("photos", "a.jpg", a)), {{"content-type", "application/json"}}).status / 100, 4);

  // a grid of photos over the field (x 10..160 every 25 m, y 5..95 every 15 m) less the 4 around (72.5, 50)
  json photos = json::array();
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 7; ++j) {
      if ((i == 2 || i == 3) && (j == 3 || j == 4)) continue;
      const std::string bytes = field_photo(10.0 + 25.0 * i, 5.0 + 15.0 * j);
      photos.push_back(io::to_json(io::read_photo_tags(reinterpret_cast<const std::uint8_t*>(bytes.data()),
                                                       bytes.size(), fmt::format("p{}_{}.jpg", i, j))));
    }
  r = call("POST", url + "/photos", json({{"photos", photos}}).dump());
  ASSERT_EQ(r.status, 200) << r.body;
  const json seen = r.json();
  EXPECT_EQ(seen.at("photos"), 45);
  EXPECT_LT(seen.at("poc").get<double>(), 0.97);
  EXPECT_GT(seen.at("poc").get<double>(), 0.85);
  EXPECT_GT(seen.at("gaps_m2").get<double>(), 0.0);
  EXPECT_EQ(seen.at("geojson").at("features").size(), 46u);
  json bad = photos;
  bad[0]["lat"] = 123;
  EXPECT_EQ(call("POST", url + "/photos", json({{"photos", bad}}).dump()).error_field(), "photos[0].lat");
  EXPECT_EQ(call("POST", url + "/photos", json({{"photos", photos}, {"x", 1}}).dump()).error_field(), "x");
  EXPECT_EQ(call("POST", url + "/photos", R"({"photos": []})").error_field(), "photos");
  EXPECT_EQ(call("POST", "/api/v1/flights/987654/photos", json({{"photos", photos}}).dump()).status, 404);

  // the refly of what no photo saw
  const Answer refly = call("POST", url + "/refly", json({{"photos", photos}, {"uavs", {"A"}}}).dump());
  ASSERT_EQ(refly.status, 202) << refly.body;
  const json p = store_->get_job(refly.json().at("id").get<store::Id>())->params.at("refly");
  EXPECT_EQ(p.at("source"), "photos");
  EXPECT_NEAR(p.at("flown_poc").get<double>(), seen.at("poc").get<double>(), 1e-9);
  EXPECT_NEAR(p.at("gaps_m2").get<double>(), seen.at("gaps_m2").get<double>(), 1e-6);
}

}  // namespace
}  // namespace uavcover::server::testing
