// Mission upload between our GCS and our vehicle over UDP on loopback (127.0.0.1), with and without
// injected packet loss, out-of-order requests from a scripted vehicle, errors, and a small fleet.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <thread>

#include "mavlink/mission_protocol.hpp"
#include "mavlink/test_util.hpp"
#include "uavcover/error.hpp"

using namespace uavcover::mavlink;
using namespace std::chrono_literals;
namespace wp = uavcover::waypoints;

namespace {

const Endpoint kLoopback{"127.0.0.1", 0};

std::vector<MissionItemInt> make_items(std::size_t n) {
  std::vector<wp::MissionItem> items;
  wp::MissionItem takeoff;
  takeoff.command = wp::kNavTakeoff;
  takeoff.alt = 60;
  items.push_back(takeoff);
  wp::MissionItem speed;
  speed.command = wp::kDoChangeSpeed;
  speed.frame = wp::kFrameMission;
  speed.param1 = 1;
  speed.param2 = 5.5F;
  speed.param3 = -1;
  items.push_back(speed);
  for (std::size_t i = 0; items.size() + 2 < n; ++i) {  // n items with home and RTL
    wp::MissionItem wp;
    wp.lat = 47.3977420 + 1e-5 * static_cast<double>(i);
    wp.lon = 8.5455940 - 2e-5 * static_cast<double>(i);
    wp.alt = 40.0F + static_cast<float>(i % 3);
    items.push_back(wp);
  }
  wp::MissionItem rtl;
  rtl.command = wp::kNavReturnToLaunch;
  rtl.frame = wp::kFrameMission;
  items.push_back(rtl);
  return to_mission_items(items, uavcover::LonLat{8.5455, 47.3977});
}

using mavtest::expect_same_items;

struct VehicleThread {
  UdpLink link;
  Vehicle vehicle;
  std::atomic<bool> stop{false};
  std::thread thread;
  VehicleThread(std::uint8_t sysid, VehicleOptions opt, double loss = 0.0, std::uint64_t seed = 0)
      : link(kLoopback, sysid, 1), vehicle(link, opt) {
    if (loss > 0) link.set_loss(loss, seed);
    thread = std::thread([this] { vehicle.run(20s, &stop); });
  }
  ~VehicleThread() { join(); }
  void join() {
    stop = true;
    if (thread.joinable()) thread.join();
  }
  [[nodiscard]] Endpoint endpoint() const { return Endpoint{"127.0.0.1", link.local_port()}; }
};

VehicleOptions quiet_vehicle() {
  VehicleOptions o;
  o.heartbeat_period = 1h;  // keep the loss RNG's draws to the protocol's own messages
  return o;
}

}  // namespace

TEST(MissionItems, ConversionScalesGlobalFramesAndPutsHomeFirst) {
  wp::MissionItem wp;
  wp.lat = 47.39774204;
  wp.lon = -8.54559406;
  wp.alt = 35.5F;
  wp.param4 = 90;
  wp::MissionItem speed;
  speed.command = wp::kDoChangeSpeed;
  speed.frame = wp::kFrameMission;
  speed.param2 = 7;
  speed.autocontinue = false;
  const auto items = to_mission_items({wp, speed}, uavcover::LonLat{8.5, 47.25});
  ASSERT_EQ(items.size(), 3U);
  EXPECT_EQ(items[0].command, 16);  // ArduPilot: seq 0 is home
  EXPECT_EQ(items[0].frame, 0);
  EXPECT_EQ(items[0].x, 472500000);
  EXPECT_EQ(items[0].y, 85000000);
  EXPECT_EQ(items[1].seq, 1);
  EXPECT_EQ(items[1].frame, 3);
  EXPECT_EQ(items[1].x, 473977420);
  EXPECT_EQ(items[1].y, -85455941);  // rounded, not truncated
  EXPECT_FLOAT_EQ(items[1].z, 35.5F);
  EXPECT_FLOAT_EQ(items[1].param4, 90.0F);
  EXPECT_EQ(items[2].seq, 2);
  EXPECT_EQ(items[2].frame, 2);
  EXPECT_EQ(items[2].x, 0);
  EXPECT_EQ(items[2].autocontinue, 0);
  EXPECT_FLOAT_EQ(items[2].param2, 7.0F);
  EXPECT_EQ(to_mission_items({wp}, std::nullopt).size(), 1U);
}

TEST(UdpEndpoint, ParsesAndRejects) {
  EXPECT_EQ(parse_udp_endpoint("udp:127.0.0.1:14550"), (Endpoint{"127.0.0.1", 14550}));
  EXPECT_EQ(parse_udp_endpoint("udp:localhost:1"), (Endpoint{"localhost", 1}));
  for (const char* bad :
       {"127.0.0.1:14550", "tcp:127.0.0.1:5760", "udp:127.0.0.1", "udp::14550", "udp:127.0.0.1:0",
        "udp:127.0.0.1:65536", "udp:127.0.0.1:12ab", "udp:no.such.host:14550", "udp:300.1.1.1:14550", ""}) {
    EXPECT_THROW(parse_udp_endpoint(bad), uavcover::InputError) << bad;
  }
}

TEST(MissionUpload, LoopbackNoLoss) {
  VehicleThread v(1, quiet_vehicle());
  UdpLink gcs(kLoopback, 255, 190);
  gcs.set_peer(v.endpoint());
  const auto items = make_items(25);
  std::vector<std::size_t> progress;
  const auto res = upload_mission(gcs, items, UploadOptions{}, [&](std::size_t done, std::size_t total) {
    EXPECT_EQ(total, items.size());
    progress.push_back(done);
  });
  v.join();
  ASSERT_TRUE(res.ok) << res.error;
  EXPECT_EQ(res.ack, kMissionAccepted);
  EXPECT_EQ(res.unique_items, items.size());
  EXPECT_EQ(res.items_sent, items.size());
  EXPECT_EQ(res.count_sent, 1U);
  EXPECT_EQ(res.out_of_order, 0U);
  EXPECT_EQ(progress.size(), items.size());
  EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end()));
  expect_same_items(v.vehicle.mission(), items, 1);
  EXPECT_EQ(v.vehicle.stats().uploads_accepted, 1U);
  EXPECT_EQ(v.vehicle.stats().rerequests, 0U);
}

TEST(MissionUpload, CompletesDespitePacketLossBothWays) {
  // Each end drops 20 % of the datagrams it sends and 20 % of those it receives (seeded), so 36 % are
  // lost in each direction and ~59 % of request/item exchanges fail. Short timeouts keep the test fast; the
  // retry budgets are raised because six losses in a row are not that rare at this rate, and so that
  // a thread starved for a while on a loaded machine does not make the vehicle give up.
  for (std::uint64_t seed : {1U, 2U}) {
    SCOPED_TRACE(seed);
    VehicleOptions vo = quiet_vehicle();
    vo.item_timeout = 20ms;
    vo.retries = 25;
    VehicleThread v(7, vo, 0.2, seed);
    UdpLink gcs(kLoopback, 255, 190);
    gcs.set_loss(0.2, seed + 100);
    gcs.set_peer(v.endpoint());
    UploadOptions uo;
    uo.timeout = 100ms;
    uo.retries = 12;
    uo.target_system = 7;
    const auto items = make_items(30);
    const auto res = upload_mission(gcs, items, uo);
    v.join();
    ASSERT_TRUE(res.ok) << res.error;
    std::printf("seed %d: %.2f s, %zu timeouts, %zu items sent for %zu, vehicle re-requests %zu\n", int(seed),
                res.elapsed_s, res.timeouts, res.items_sent, items.size(), v.vehicle.stats().rerequests);
    expect_same_items(v.vehicle.mission(), items, 7);
    // the loss really happened and was recovered from
    EXPECT_GT(gcs.stats().dropped_tx + gcs.stats().dropped_rx, 0U);
    EXPECT_GT(v.link.stats().dropped_tx + v.link.stats().dropped_rx, 0U);
    EXPECT_GT(v.vehicle.stats().rerequests + res.timeouts, 0U);
    EXPECT_GE(res.items_sent, items.size());
  }
}

TEST(MissionUpload, ServesOutOfOrderAndRepeatedRequests) {
  // A scripted vehicle asks for items in a scrambled order, with repeats, then acks.
  // Half of its requests are the deprecated MISSION_REQUEST, answered with MISSION_ITEM_INT too.
  UdpLink vehicle(kLoopback, 3, 1);
  vehicle.learn_peer(true);
  const auto items = make_items(8);
  const std::vector<std::uint16_t> order{0, 2, 2, 1, 7, 3, 0, 4, 6, 5, 5};
  std::vector<MissionItemInt> got(items.size());
  std::vector<int> times(items.size(), 0);
  std::thread script([&] {
    std::optional<Received> r;
    while ((r = vehicle.receive(3s)) && !std::holds_alternative<MissionCount>(r->message)) {
    }
    if (!r) return;
    EXPECT_EQ(std::get<MissionCount>(r->message).count, items.size());
    bool deprecated = false;  // every other request is the deprecated MISSION_REQUEST
    for (std::uint16_t s : order) {
      if (deprecated)
        vehicle.send(MissionRequest{r->header.sysid, r->header.compid, s, 0});
      else
        vehicle.send(MissionRequestInt{r->header.sysid, r->header.compid, s, 0});
      deprecated = !deprecated;
      std::optional<Received> it;
      while ((it = vehicle.receive(3s)) && !std::holds_alternative<MissionItemInt>(it->message)) {
      }
      if (!it) return;
      const auto& item = std::get<MissionItemInt>(it->message);
      EXPECT_EQ(item.seq, s);
      got[item.seq] = item;
      ++times[item.seq];
    }
    vehicle.send(MissionAck{255, 190, kMissionAccepted, 0, 0});
  });
  UdpLink gcs(kLoopback, 255, 190);
  gcs.set_peer(Endpoint{"127.0.0.1", vehicle.local_port()});
  UploadOptions uo;
  uo.target_system = 3;
  const auto res = upload_mission(gcs, items, uo);
  script.join();
  ASSERT_TRUE(res.ok) << res.error;
  EXPECT_EQ(res.items_sent, order.size());
  EXPECT_EQ(res.unique_items, items.size());
  EXPECT_GT(res.out_of_order, 0U);
  expect_same_items(got, items, 3);
  EXPECT_EQ(times[2], 2);
  EXPECT_EQ(times[5], 2);
}

TEST(MissionUpload, LostAckRecoveredByRepeatingTheLastItem) {
  // Scripted vehicle ignores the first copy of the final item (as if its ACK was lost);
  // the GCS times out, repeats the final item, and gets the ACK.
  UdpLink vehicle(kLoopback, 1, 1);
  vehicle.learn_peer(true);
  const auto items = make_items(3);
  int final_copies = 0;
  std::thread script([&] {
    std::optional<Received> r;
    while ((r = vehicle.receive(3s)) && !std::holds_alternative<MissionCount>(r->message)) {
    }
    if (!r) return;
    for (std::uint16_t s = 0; s < items.size(); ++s) vehicle.send(MissionRequestInt{255, 190, s, 0});
    const auto end = std::chrono::steady_clock::now() + 5s;
    while (std::chrono::steady_clock::now() < end) {
      auto it = vehicle.receive(200ms);
      if (!it || !std::holds_alternative<MissionItemInt>(it->message)) continue;
      if (std::get<MissionItemInt>(it->message).seq + 1U == items.size() && ++final_copies == 2) {
        vehicle.send(MissionAck{255, 190, kMissionAccepted, 0, 0});
        return;
      }
    }
  });
  UdpLink gcs(kLoopback, 255, 190);
  gcs.set_peer(Endpoint{"127.0.0.1", vehicle.local_port()});
  UploadOptions uo;
  uo.timeout = 100ms;
  const auto res = upload_mission(gcs, items, uo);
  script.join();
  ASSERT_TRUE(res.ok) << res.error;
  EXPECT_EQ(final_copies, 2);
  EXPECT_GE(res.timeouts, 1U);
}

TEST(MissionUpload, VehicleRepeatsAckAndReRequestsOutOfSequenceItems) {
  VehicleThread v(1, quiet_vehicle());
  UdpLink gcs(kLoopback, 255, 190);
  gcs.set_peer(v.endpoint());
  auto items = make_items(3);
  for (std::size_t i = 0; i < items.size(); ++i) {
    items[i].seq = static_cast<std::uint16_t>(i);
    items[i].target_system = 1;
    items[i].target_component = 1;
  }
  auto next_of = [&](auto pred) -> std::optional<Received> {
    for (int i = 0; i < 50; ++i) {
      auto r = gcs.receive(200ms);
      if (r && pred(*r)) return r;
    }
    return std::nullopt;
  };
  auto is_request = [](const Received& r) { return std::holds_alternative<MissionRequestInt>(r.message); };
  auto is_ack = [](const Received& r) { return std::holds_alternative<MissionAck>(r.message); };
  gcs.send(MissionCount{1, 1, 3, 0, 0});
  auto r = next_of(is_request);
  ASSERT_TRUE(r);
  EXPECT_EQ(std::get<MissionRequestInt>(r->message).seq, 0);
  gcs.send(items[1]);  // out of sequence: dropped, 0 requested again
  r = next_of(is_request);
  ASSERT_TRUE(r);
  EXPECT_EQ(std::get<MissionRequestInt>(r->message).seq, 0);
  for (std::uint16_t s = 0; s < 3; ++s) {
    gcs.send(items[s]);
    r = next_of([&](const Received& x) { return s < 2 ? is_request(x) : is_ack(x); });
    ASSERT_TRUE(r);
  }
  EXPECT_EQ(std::get<MissionAck>(r->message).type, kMissionAccepted);
  gcs.send(items[2]);  // our ACK "was lost": the vehicle acks again
  r = next_of(is_ack);
  ASSERT_TRUE(r);
  EXPECT_EQ(std::get<MissionAck>(r->message).type, kMissionAccepted);
  gcs.send(MissionClearAll{1, 1, 0});
  r = next_of(is_ack);
  ASSERT_TRUE(r);
  v.join();
  EXPECT_TRUE(v.vehicle.mission().empty());
  EXPECT_EQ(v.vehicle.stats().out_of_sequence, 1U);
  EXPECT_EQ(v.vehicle.stats().acks_resent, 1U);
}

TEST(MissionUpload, ErrorsAreReported) {
  {  // the vehicle has no room
    VehicleOptions vo = quiet_vehicle();
    vo.max_items = 5;
    VehicleThread v(1, vo);
    UdpLink gcs(kLoopback, 255, 190);
    gcs.set_peer(v.endpoint());
    const auto res = upload_mission(gcs, make_items(10), UploadOptions{});
    EXPECT_FALSE(res.ok);
    EXPECT_EQ(res.ack, kMissionNoSpace);
    EXPECT_NE(res.error.find("MAV_MISSION_NO_SPACE"), std::string::npos) << res.error;
  }
  {  // nobody listening: bounded by the retries
    UdpLink silent(kLoopback, 1, 1);
    UdpLink gcs(kLoopback, 255, 190);
    gcs.set_peer(Endpoint{"127.0.0.1", silent.local_port()});
    UploadOptions uo;
    uo.timeout = 30ms;
    uo.retries = 3;
    const auto res = upload_mission(gcs, make_items(4), uo);
    EXPECT_FALSE(res.ok);
    EXPECT_EQ(res.count_sent, 4U);  // first send + 3 retries
    EXPECT_EQ(res.timeouts, 4U);
    EXPECT_NE(res.error.find("3 retries"), std::string::npos) << res.error;
  }
  {  // a silent vehicle and a stop: the upload ends without waiting out the retries
    UdpLink silent(kLoopback, 1, 1);
    UdpLink gcs(kLoopback, 255, 190);
    gcs.set_peer(Endpoint{"127.0.0.1", silent.local_port()});
    std::stop_source stopped;
    stopped.request_stop();
    UploadOptions uo;
    uo.timeout = std::chrono::hours(1);  // without the stop, this upload would wait an hour per retry
    uo.stop = stopped.get_token();
    const auto res = upload_mission(gcs, make_items(4), uo);
    EXPECT_FALSE(res.ok);
    EXPECT_EQ(res.error, "stopped");
    EXPECT_EQ(res.timeouts, 0U);
    EXPECT_EQ(res.count_sent, 1U);
    // stopped while it waits for the first request (from another thread)
    std::stop_source later;
    uo.stop = later.get_token();
    std::thread stopper([&] {
      // the hook: the MISSION_COUNT has reached the silent vehicle, so the upload is waiting
      for (int i = 0; i < 100; ++i)
        if (const auto r = silent.receive(100ms); r && std::holds_alternative<MissionCount>(r->message))
          break;
      later.request_stop();
    });
    const auto waited = upload_mission(gcs, make_items(4), uo);
    stopper.join();
    EXPECT_FALSE(waited.ok);
    EXPECT_EQ(waited.error, "stopped");
    EXPECT_EQ(waited.timeouts, 0U);  // not one of the hour-long timeouts ran out
  }
  {  // the vehicle gives up when the GCS stops answering, and keeps its old mission
    VehicleOptions vo = quiet_vehicle();
    vo.item_timeout = 10ms;
    vo.retries = 2;
    VehicleThread v(1, vo);
    UdpLink gcs(kLoopback, 255, 190);
    gcs.set_peer(v.endpoint());
    gcs.send(MissionCount{1, 1, 4, 0, 0});
    std::size_t requests = 0;
    std::optional<std::uint8_t> ack;
    for (int i = 0; i < 40 && !ack; ++i) {
      auto r = gcs.receive(100ms);
      if (!r) continue;
      if (std::holds_alternative<MissionRequestInt>(r->message)) ++requests;
      if (const auto* a = std::get_if<MissionAck>(&r->message)) ack = a->type;
    }
    v.join();
    EXPECT_EQ(requests, 3U);  // first request + 2 retries
    EXPECT_EQ(ack, kMissionOperationCancelled);
    EXPECT_EQ(v.vehicle.stats().cancelled, 1U);
    EXPECT_TRUE(v.vehicle.mission().empty());
  }
}

TEST(MissionUpload, StaleAckIgnoredAndEmptyMissionClears) {
  VehicleThread v(1, quiet_vehicle());
  UdpLink gcs(kLoopback, 255, 190);
  gcs.set_peer(v.endpoint());
  const auto items = make_items(5);
  ASSERT_TRUE(upload_mission(gcs, items, UploadOptions{}).ok);
  // A stale acceptance (the vehicle repeating its ack for a repeated final item) arriving at the start
  // of the next upload is not taken for that upload's result.
  auto last = items.back();
  last.seq = 4;
  last.target_system = 1;
  last.target_component = 1;
  gcs.send(last);
  std::this_thread::sleep_for(100ms);
  const auto again = upload_mission(gcs, items, UploadOptions{});
  EXPECT_TRUE(again.ok) << again.error;
  EXPECT_EQ(again.unique_items, items.size());
  const auto res = upload_mission(gcs, {}, UploadOptions{});
  v.join();
  EXPECT_TRUE(res.ok) << res.error;
  EXPECT_TRUE(v.vehicle.mission().empty());
  EXPECT_EQ(v.vehicle.stats().uploads_accepted, 3U);
  EXPECT_EQ(v.vehicle.stats().acks_resent, 1U);
}

TEST(SimulatedFleet, UploadThenFlyReportsProgress) {
  constexpr int kUavs = 3;
  std::vector<std::unique_ptr<UdpLink>> vlinks;
  std::vector<std::unique_ptr<Vehicle>> vehicles;
  std::vector<std::unique_ptr<UdpLink>> gcs;
  std::vector<std::vector<MissionItemInt>> missions;
  for (int i = 0; i < kUavs; ++i) {
    const auto sysid = static_cast<std::uint8_t>(i + 1);
    vlinks.push_back(std::make_unique<UdpLink>(kLoopback, sysid, 1));
    vehicles.push_back(std::make_unique<Vehicle>(*vlinks.back(), quiet_vehicle()));
    gcs.push_back(std::make_unique<UdpLink>(kLoopback, 255, 190));
    gcs.back()->set_peer(Endpoint{"127.0.0.1", vlinks.back()->local_port()});
    missions.push_back(make_items(6 + 3 * static_cast<std::size_t>(i)));
  }
  // Each vehicle: receive one upload, then fly it (items 1.. : seq 0 is home).
  std::vector<std::thread> threads;
  for (int i = 0; i < kUavs; ++i) {
    threads.emplace_back([&, i] {
      vehicles[i]->run(10s, nullptr, true);
      std::this_thread::sleep_for(50ms);
      vehicles[i]->fly(1, 2ms);
    });
  }
  for (int i = 0; i < kUavs; ++i) {
    UploadOptions uo;
    uo.target_system = static_cast<std::uint8_t>(i + 1);
    const auto res = upload_mission(*gcs[i], missions[i], uo);
    ASSERT_TRUE(res.ok) << "uav " << i << ": " << res.error;
  }
  std::vector<ProgressLog> logs;
  for (int i = 0; i < kUavs; ++i) {
    logs.push_back(monitor_progress(*gcs[i], static_cast<std::uint8_t>(i + 1),
                                    static_cast<std::uint16_t>(missions[i].size() - 1), 3s));
  }
  for (auto& t : threads) t.join();
  for (int i = 0; i < kUavs; ++i) {
    SCOPED_TRACE(i);
    expect_same_items(vehicles[i]->mission(), missions[i], static_cast<std::uint8_t>(i + 1));
    std::vector<std::uint16_t> want;
    for (std::size_t s = 1; s < missions[i].size(); ++s) want.push_back(static_cast<std::uint16_t>(s));
    EXPECT_EQ(logs[i].reached, want);
    EXPECT_EQ(logs[i].current.front(), 1);
  }
}
