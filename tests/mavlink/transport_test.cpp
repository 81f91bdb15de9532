// MAVLink over TCP (connect and listen) and a serial port (a pseudo-terminal pair, no hardware), endpoint
// parsing, byte-stream resynchronisation, and what a refused or broken upload leaves on the vehicle
// (issue 34: MISSION_CLEAR_ALL after a failure, or a loud warning).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <pty.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <functional>
#include <thread>

#include "mavlink/mission_protocol.hpp"
#include "mavlink/stream.hpp"
#include "mavlink/test_util.hpp"
#include "mavlink/udp.hpp"
#include "support/errors.hpp"
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
  for (std::size_t i = 0; items.size() + 2 < n; ++i) {
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

VehicleOptions quiet_vehicle() {
  VehicleOptions o;
  o.heartbeat_period = 1h;
  return o;
}

/// Our vehicle over any link, in a thread. `filter` (optional) sees each message first and may swallow
/// it (return false): a vehicle that goes deaf at a known point, without timing.
struct VehicleThread {
  std::unique_ptr<Link> link;
  Vehicle vehicle;
  std::function<bool(const Received&)> filter;
  std::atomic<bool> stop{false};
  std::thread thread;
  VehicleThread(std::unique_ptr<Link> l, VehicleOptions opt, std::function<bool(const Received&)> f = {})
      : link(std::move(l)), vehicle(*link, opt), filter(std::move(f)) {
    thread = std::thread([this] {
      const auto end = std::chrono::steady_clock::now() + 20s;
      while (!stop && std::chrono::steady_clock::now() < end) {
        if (auto r = link->receive(20ms))
          if (!filter || filter(*r)) vehicle.handle(*r);
        vehicle.on_timeout();
      }
    });
  }
  ~VehicleThread() { join(); }
  void join() {
    stop = true;
    if (thread.joinable()) thread.join();
  }
};

/// A Link over a raw descriptor: the master side of a pseudo-terminal (the "autopilot" end of the cable).
class FdLink final : public Link {
 public:
  FdLink(int fd, std::uint8_t sysid) : Link(sysid, 1), fd_(fd) {}
  [[nodiscard]] bool has_peer() const override { return true; }
  [[nodiscard]] std::vector<int> poll_handles() const override { return {fd_}; }
  [[nodiscard]] std::string describe() const override { return "pty master"; }
  bool send_raw(const std::vector<std::uint8_t>& bytes) override {
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
      if (n <= 0) return false;
      done += static_cast<std::size_t>(n);
    }
    return true;
  }

 protected:
  bool read_some(std::chrono::milliseconds timeout) override {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return false;
    std::uint8_t buf[1024];
    const ssize_t n = ::read(fd_, buf, sizeof buf);
    if (n <= 0) return false;
    feed(buf, static_cast<std::size_t>(n), false, sockaddr_in{});
    return true;
  }

 private:
  int fd_;
};

using uavcover::testing::field_of;

}  // namespace

TEST(LinkAddress, ParsesEveryFormAndNamesTheFieldOnBadInput) {
  EXPECT_EQ(parse_link_address("udp:127.0.0.1:14550", "--to").transport, Transport::Udp);
  EXPECT_EQ(parse_link_address("udpout:127.0.0.1:14550", "--to").transport, Transport::Udp);
  EXPECT_EQ(parse_link_address("udpin:0.0.0.0:14550", "--to").transport, Transport::UdpListen);
  const auto tcp = parse_link_address("tcp:localhost:5760", "--to");
  EXPECT_EQ(tcp.transport, Transport::Tcp);
  EXPECT_EQ(tcp.endpoint, (Endpoint{"localhost", 5760}));
  EXPECT_EQ(tcp.text(), "tcp:localhost:5760");
  const auto in = parse_link_address("tcpin:0.0.0.0:5760", "--to");
  EXPECT_EQ(in.transport, Transport::TcpListen);
  EXPECT_TRUE(in.listens());
  EXPECT_EQ(parse_link_address("tcpin:127.0.0.1:0", "--to", true).endpoint.port, 0);
  const auto serial = parse_link_address("serial:/dev/ttyUSB0:57600", "--to");
  EXPECT_EQ(serial.transport, Transport::Serial);
  EXPECT_EQ(serial.device, "/dev/ttyUSB0");
  EXPECT_EQ(serial.baud, 57600U);
  EXPECT_EQ(serial.text(), "serial:/dev/ttyUSB0:57600");
  EXPECT_EQ(parse_link_address("serial:/dev/ttyACM0,115200", "--to"),
            parse_link_address("serial:/dev/ttyACM0:115200", "--to"));  // MAVProxy's DEVICE,BAUD
  for (const char* bad :
       {"", "tcp", "tcp:", "tcp:127.0.0.1", "tcp::5760", "tcp:127.0.0.1:0", "tcp:127.0.0.1:65536",
        "tcp:example.com:5760", "tcpin:127.0.0.1:0", "ftp:127.0.0.1:21", "serial:", "serial:/dev/ttyUSB0",
        "serial:/dev/ttyUSB0:57601", "serial:/dev/ttyUSB0:fast", "serial:ttyUSB0:57600", "/dev/ttyUSB0:57600",
        "127.0.0.1:5760"}) {
    EXPECT_EQ(field_of([&] { parse_link_address(bad, "--to"); }), "--to") << bad;
  }
  try {
    parse_link_address("serial:/dev/ttyUSB0:57601", "vehicles[0].endpoint");
    FAIL();
  } catch (const uavcover::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("vehicles[0].endpoint: baud rate must be one of"), std::string::npos)
        << e.what();
  }
}

TEST(StreamLink, FramesSplitAndJoinedArbitrarilyWithGarbageAreAllDecoded) {
  TcpListenLink server(kLoopback, 1, 1);
  TcpClientLink client(Endpoint{"127.0.0.1", server.local_port()}, 255, 190);
  ASSERT_EQ(client.connect(2s), "");
  // the listener accepts inside receive(); nothing has been sent yet
  EXPECT_FALSE(server.receive(100ms));
  ASSERT_TRUE(server.has_peer());
  EXPECT_EQ(server.stats().connections, 1U);

  auto frame = [](std::uint16_t seq) {
    MissionRequestInt r;
    r.target_system = 255;
    r.seq = seq;
    return encode(r, Header{static_cast<std::uint8_t>(seq), 1, 1, 0, 0});
  };
  // half a frame: nothing decodable yet, the parser keeps it
  const auto f0 = frame(0);
  client.send_raw(std::vector<std::uint8_t>(f0.begin(), f0.begin() + 5));
  EXPECT_FALSE(server.receive(100ms));
  // the rest, joined with garbage (a false start byte too) and two more frames in one write
  std::vector<std::uint8_t> joined(f0.begin() + 5, f0.end());
  for (std::uint8_t g : {0x00, 0xFD, 0x13, 0x37, 0xFE}) joined.push_back(g);
  for (std::uint16_t s : {1, 2}) {
    const auto f = frame(s);
    joined.insert(joined.end(), f.begin(), f.end());
  }
  // and a fourth frame byte by byte
  const auto f3 = frame(3);
  client.send_raw(joined);
  for (std::uint8_t b : f3) client.send_raw({b});
  std::vector<std::uint16_t> seqs;
  for (int i = 0; i < 4; ++i) {
    auto r = server.receive(2s);
    ASSERT_TRUE(r) << "frame " << i;
    const auto* req = std::get_if<MissionRequestInt>(&r->message);
    ASSERT_NE(req, nullptr);
    seqs.push_back(req->seq);
  }
  EXPECT_EQ(seqs, (std::vector<std::uint16_t>{0, 1, 2, 3}));
  EXPECT_GT(server.parser_stats().bytes_skipped, 0U);

  // the client goes away: the listener notices, and takes the next client
  client.send_raw({});  // nothing
  {
    TcpClientLink second(Endpoint{"127.0.0.1", server.local_port()}, 255, 191);
    ASSERT_EQ(second.connect(2s), "");
    second.send(Heartbeat{});
    auto r = server.receive(2s);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->header.compid, 191);  // from the new client: it replaced the first
    EXPECT_EQ(server.stats().connections, 2U);
  }
  EXPECT_FALSE(server.receive(200ms));  // EOF of the second client
  EXPECT_FALSE(server.has_peer());
}

TEST(StreamLink, TcpClientReportsARefusedConnectionAndReconnectsLater) {
  std::uint16_t port = 0;
  {
    TcpListenLink probe(kLoopback, 1, 1);  // a free port, closed again
    port = probe.local_port();
  }
  TcpClientLink client(Endpoint{"127.0.0.1", port}, 255, 190);
  EXPECT_NE(client.connect(2s), "");
  EXPECT_FALSE(client.has_peer());
  EXPECT_FALSE(client.send(Heartbeat{}));  // nowhere to go
  // the vehicle comes up later: receive() reconnects (at most once a second) and hears it
  TcpListenLink vehicle(Endpoint{"127.0.0.1", port}, 1, 1);
  std::optional<Received> got;
  for (int i = 0; i < 100 && !got; ++i) {
    vehicle.receive(0ms);  // accepts
    if (vehicle.has_peer()) vehicle.send(Heartbeat{});
    got = client.receive(50ms);
  }
  ASSERT_TRUE(got);
  EXPECT_TRUE(client.has_peer());
  EXPECT_EQ(client.stats().connections, 1U);
}

TEST(MissionUploadOverTcp, ToAListeningVehicleAndFromAListeningGcs) {
  const auto items = make_items(40);
  {  // the vehicle listens (SITL, MAVProxy --out tcpin:...): we connect
    auto link = std::make_unique<TcpListenLink>(kLoopback, 3, 1);
    const auto port = link->local_port();
    VehicleThread v(std::move(link), quiet_vehicle());
    auto gcs = open_link(parse_link_address("tcp:127.0.0.1:" + std::to_string(port), "--to"), 255, 190);
    ASSERT_EQ(dynamic_cast<TcpClientLink&>(*gcs).connect(2s), "");
    UploadOptions opt;
    opt.target_system = 3;
    const auto res = upload_mission(*gcs, items, opt);
    ASSERT_TRUE(res.ok) << res.error;
    EXPECT_EQ(res.timeouts, 0U);  // a stream loses nothing
    EXPECT_EQ(res.unique_items, items.size());
    v.join();
    expect_same_items(v.vehicle.mission(), items, 3);
  }
  {  // we listen (tcpin:), the vehicle connects (a companion computer dialling in)
    auto gcs = open_link(parse_link_address("tcpin:127.0.0.1:0", "--to", true), 255, 190);
    auto link = std::make_unique<TcpClientLink>(Endpoint{"127.0.0.1", gcs->local_port()}, 4, 1);
    VehicleThread v(std::move(link), quiet_vehicle());
    for (int i = 0; i < 200 && !gcs->has_peer(); ++i) gcs->receive(20ms);
    ASSERT_TRUE(gcs->has_peer());
    UploadOptions opt;
    opt.target_system = 4;
    const auto res = upload_mission(*gcs, items, opt);
    ASSERT_TRUE(res.ok) << res.error;
    v.join();
    expect_same_items(v.vehicle.mission(), items, 4);
  }
}

TEST(MissionUploadOverSerial, ThroughAPseudoTerminalPair) {
  int master = -1, slave = -1;
  char name[256] = {};
  ASSERT_EQ(::openpty(&master, &slave, name, nullptr, nullptr), 0) << std::strerror(errno);
  // the vehicle at the master end; we open the slave by its path, as a telemetry radio's /dev/ttyUSB0
  VehicleThread v(std::make_unique<FdLink>(master, 2), quiet_vehicle());
  const auto address = parse_link_address(std::string("serial:") + name + ":57600", "--to");
  auto gcs = open_link(address, 255, 190);
  EXPECT_TRUE(gcs->has_peer());
  EXPECT_EQ(gcs->describe(), address.text());
  const auto items = make_items(25);
  UploadOptions opt;
  opt.target_system = 2;
  const auto res = upload_mission(*gcs, items, opt);
  ASSERT_TRUE(res.ok) << res.error;
  v.join();
  expect_same_items(v.vehicle.mission(), items, 2);
  gcs.reset();
  ::close(slave);
  ::close(master);
  // a device that is not there: said, naming it
  try {
    SerialLink nowhere("/dev/uavcover-no-such-tty", 57600, 255, 190);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/uavcover-no-such-tty"), std::string::npos) << e.what();
  }
}

TEST(MissionUploadFailure, ARefusedItemIsFollowedByClearAllAndLeavesNoMission) {
  const auto items = make_items(12);
  VehicleOptions vo = quiet_vehicle();
  vo.store_as_received = true;  // ArduPilot: items 0..2 are stored when item 3 is refused
  vo.refuse_item = 3;
  vo.refuse_result = 8;  // MAV_MISSION_INVALID_PARAM3, what ArduPilot answered in issue 34
  auto link = std::make_unique<TcpListenLink>(kLoopback, 1, 1);
  const auto port = link->local_port();
  VehicleThread v(std::move(link), vo);
  TcpClientLink gcs(Endpoint{"127.0.0.1", port}, 255, 190);
  ASSERT_EQ(gcs.connect(2s), "");
  const auto res = upload_mission(gcs, items, UploadOptions{});
  v.join();
  EXPECT_FALSE(res.ok);
  EXPECT_EQ(res.ack, 8);
  EXPECT_EQ(v.vehicle.stats().refused, 1U);
  EXPECT_TRUE(res.clear_sent);
  EXPECT_TRUE(res.cleared);
  EXPECT_FALSE(res.partial_possible());
  EXPECT_NE(res.error.find("MAV_MISSION_INVALID_PARAM3"), std::string::npos) << res.error;
  EXPECT_NE(res.error.find("mission was cleared"), std::string::npos) << res.error;
  EXPECT_EQ(v.vehicle.stats().clears, 1U);
  EXPECT_TRUE(v.vehicle.mission().empty());
}

TEST(MissionUploadFailure, AnUnacknowledgedClearSaysThePartialMissionLoudly) {
  const auto items = make_items(12);
  VehicleOptions vo = quiet_vehicle();
  vo.store_as_received = true;
  vo.refuse_item = 5;
  // a vehicle that ignores MISSION_CLEAR_ALL: the truncated mission stays, and the result says so
  auto link = std::make_unique<TcpListenLink>(kLoopback, 1, 1);
  const auto port = link->local_port();
  VehicleThread v(std::move(link), vo,
                  [](const Received& r) { return !std::holds_alternative<MissionClearAll>(r.message); });
  TcpClientLink gcs(Endpoint{"127.0.0.1", port}, 255, 190);
  ASSERT_EQ(gcs.connect(2s), "");
  UploadOptions uo;
  uo.timeout = 50ms;
  uo.retries = 2;
  const auto res = upload_mission(gcs, items, uo);
  v.join();
  EXPECT_FALSE(res.ok);
  EXPECT_TRUE(res.clear_sent);
  EXPECT_FALSE(res.cleared);
  EXPECT_TRUE(res.partial_possible());
  EXPECT_NE(res.error.find("WARNING"), std::string::npos) << res.error;
  EXPECT_NE(res.error.find("may hold a partial mission"), std::string::npos) << res.error;
  EXPECT_EQ(v.vehicle.mission().size(), 5U);  // items 0..4: what the clear was for
}

TEST(MissionUploadFailure, ATimeoutMidwayIsFollowedByClearAll) {
  const auto items = make_items(20);
  VehicleOptions vo = quiet_vehicle();
  vo.store_as_received = true;
  vo.item_timeout = 1h;  // the vehicle waits; the GCS gives up first
  std::atomic<int> items_seen{0};
  // deaf to everything but the clear after its 7th item (UDP here: the same protocol, another transport)
  auto link = std::make_unique<UdpLink>(kLoopback, 1, 1);
  link->learn_peer(true);
  const auto port = link->local_port();
  VehicleThread v(std::move(link), vo, [&](const Received& r) {
    if (std::holds_alternative<MissionClearAll>(r.message)) return true;
    if (items_seen >= 7) return false;
    if (std::holds_alternative<MissionItemInt>(r.message)) ++items_seen;
    return true;
  });
  UdpLink gcs(kLoopback, 255, 190);
  gcs.set_peer(Endpoint{"127.0.0.1", port});
  UploadOptions uo;
  uo.timeout = 50ms;
  uo.retries = 2;
  const auto res = upload_mission(gcs, items, uo);
  EXPECT_FALSE(res.ok);
  EXPECT_GE(res.timeouts, 3U);
  EXPECT_TRUE(res.cleared) << res.error;
  EXPECT_NE(res.error.find("no answer from the vehicle"), std::string::npos) << res.error;
  EXPECT_NE(res.error.find("mission was cleared"), std::string::npos) << res.error;
  v.join();
  EXPECT_TRUE(v.vehicle.mission().empty());
  EXPECT_FALSE(v.vehicle.receiving());
}

TEST(MissionUploadFailure, ASilentVehicleIsNotClearedNorWaitedForTwice) {
  UdpLink silent(kLoopback, 1, 1);
  UdpLink gcs(kLoopback, 255, 190);
  gcs.set_peer(Endpoint{"127.0.0.1", silent.local_port()});
  UploadOptions uo;
  uo.timeout = 30ms;
  uo.retries = 1;
  const auto res = upload_mission(gcs, make_items(4), uo);
  EXPECT_FALSE(res.ok);
  EXPECT_FALSE(res.clear_sent);  // it never answered: it holds nothing of this upload
  std::size_t clears = 0;
  while (auto r = silent.receive(0ms)) clears += std::holds_alternative<MissionClearAll>(r->message) ? 1 : 0;
  EXPECT_EQ(clears, 0U);
}
