// Interoperability with an independent implementation: node-mavlink (npm, pinned in tests/node).
// Our frames are decoded by tests/node/decode.js; frames encoded by tests/node/encode.js are decoded
// by us. Skipped only when node or tests/node/node_modules is missing (scripts/setup installs both).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "autopilot/fence.hpp"
#include "export/fixture.hpp"
#include "mavlink/frame.hpp"
#include "mavlink/messages.hpp"
#include "mavlink/mission_protocol.hpp"
#include "mavlink/stream.hpp"
#include "mavlink/test_util.hpp"
#include "waypoints/waypoints.hpp"

using namespace uavcover::mavlink;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const fs::path kNodeDir = fs::path(UAVCOVER_SOURCE_DIR) / "tests" / "node";

bool have_node() { return std::system("node --version > /dev/null 2>&1") == 0; }
bool have_node_modules() { return fs::exists(kNodeDir / "node_modules" / "node-mavlink" / "package.json"); }

#define SKIP_WITHOUT_NODE()                                                                     \
  do {                                                                                          \
    if (!have_node()) GTEST_SKIP() << "node is not installed";                                  \
    if (!have_node_modules()) GTEST_SKIP() << "tests/node/node_modules missing (npm ci there)"; \
  } while (0)

// Runs `node SCRIPT < input` and returns stdout; fails the test on a non-zero exit.
std::string run_node(const std::string& script, const std::string& input) {
  static int counter = 0;
  const fs::path dir = fs::temp_directory_path() /
                       ("uavcover-mavlink-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  fs::create_directories(dir);
  const fs::path in = dir / "in.txt", out = dir / "out.txt", err = dir / "err.txt";
  std::ofstream(in) << input;
  const std::string cmd = "node '" + (kNodeDir / script).string() + "' < '" + in.string() + "' > '" +
                          out.string() + "' 2> '" + err.string() + "'";
  const int rc = std::system(cmd.c_str());
  std::stringstream o, e;
  o << std::ifstream(out).rdbuf();
  e << std::ifstream(err).rdbuf();
  fs::remove_all(dir);
  EXPECT_EQ(rc, 0) << script << " failed: " << e.str();
  return o.str();
}

std::vector<json> json_lines(const std::string& text) {
  std::vector<json> out;
  std::istringstream ss(text);
  std::string line;
  while (std::getline(ss, line))
    if (!line.empty()) out.push_back(json::parse(line));
  return out;
}

float f32(const json& j) { return static_cast<float>(j.get<double>()); }

// A field's value; fields node-mavlink was not given default to zero.
json at(const json& f, const char* key) { return f.contains(key) ? f[key] : json(0); }

// Compares node-mavlink's decoded fields (camelCase) with our message.
void expect_fields(const json& f, const Message& m) {
  if (const auto* h = std::get_if<Heartbeat>(&m)) {
    EXPECT_EQ(at(f, "customMode"), h->custom_mode);
    EXPECT_EQ(at(f, "type"), h->type);
    EXPECT_EQ(at(f, "autopilot"), h->autopilot);
    EXPECT_EQ(at(f, "baseMode"), h->base_mode);
    EXPECT_EQ(at(f, "systemStatus"), h->system_status);
    EXPECT_EQ(at(f, "mavlinkVersion"), h->mavlink_version);
  } else if (const auto* c = std::get_if<MissionCount>(&m)) {
    EXPECT_EQ(at(f, "targetSystem"), c->target_system);
    EXPECT_EQ(at(f, "targetComponent"), c->target_component);
    EXPECT_EQ(at(f, "count"), c->count);
    EXPECT_EQ(at(f, "missionType"), c->mission_type);
    EXPECT_EQ(at(f, "opaqueId"), c->opaque_id);
  } else if (const auto* r = std::get_if<MissionRequestInt>(&m)) {
    EXPECT_EQ(at(f, "targetSystem"), r->target_system);
    EXPECT_EQ(at(f, "targetComponent"), r->target_component);
    EXPECT_EQ(at(f, "seq"), r->seq);
    EXPECT_EQ(at(f, "missionType"), r->mission_type);
  } else if (const auto* rq = std::get_if<MissionRequest>(&m)) {
    EXPECT_EQ(at(f, "targetSystem"), rq->target_system);
    EXPECT_EQ(at(f, "targetComponent"), rq->target_component);
    EXPECT_EQ(at(f, "seq"), rq->seq);
    EXPECT_EQ(at(f, "missionType"), rq->mission_type);
  } else if (const auto* i = std::get_if<MissionItemInt>(&m)) {
    EXPECT_EQ(at(f, "targetSystem"), i->target_system);
    EXPECT_EQ(at(f, "targetComponent"), i->target_component);
    EXPECT_EQ(at(f, "seq"), i->seq);
    EXPECT_EQ(at(f, "frame"), i->frame);
    EXPECT_EQ(at(f, "command"), i->command);
    EXPECT_EQ(at(f, "current"), i->current);
    EXPECT_EQ(at(f, "autocontinue"), i->autocontinue);
    EXPECT_EQ(f32(at(f, "param1")), i->param1);
    EXPECT_EQ(f32(at(f, "param2")), i->param2);
    EXPECT_EQ(f32(at(f, "param3")), i->param3);
    EXPECT_EQ(f32(at(f, "param4")), i->param4);
    EXPECT_EQ(at(f, "x"), i->x);
    EXPECT_EQ(at(f, "y"), i->y);
    EXPECT_EQ(f32(at(f, "z")), i->z);
    EXPECT_EQ(at(f, "missionType"), i->mission_type);
  } else if (const auto* a = std::get_if<MissionAck>(&m)) {
    EXPECT_EQ(at(f, "targetSystem"), a->target_system);
    EXPECT_EQ(at(f, "targetComponent"), a->target_component);
    EXPECT_EQ(at(f, "type"), a->type);
    EXPECT_EQ(at(f, "missionType"), a->mission_type);
    EXPECT_EQ(at(f, "opaqueId"), a->opaque_id);
  } else if (const auto* x = std::get_if<MissionClearAll>(&m)) {
    EXPECT_EQ(at(f, "targetSystem"), x->target_system);
    EXPECT_EQ(at(f, "targetComponent"), x->target_component);
    EXPECT_EQ(at(f, "missionType"), x->mission_type);
  } else if (const auto* cur = std::get_if<MissionCurrent>(&m)) {
    EXPECT_EQ(at(f, "seq"), cur->seq);
    EXPECT_EQ(at(f, "total"), cur->total);
    EXPECT_EQ(at(f, "missionState"), cur->mission_state);
    EXPECT_EQ(at(f, "missionMode"), cur->mission_mode);
    EXPECT_EQ(at(f, "missionId"), cur->mission_id);
    EXPECT_EQ(at(f, "fenceId"), cur->fence_id);
    EXPECT_EQ(at(f, "rallyPointsId"), cur->rally_points_id);
  } else if (const auto* reached = std::get_if<MissionItemReached>(&m)) {
    EXPECT_EQ(at(f, "seq"), reached->seq);
  } else {
    ADD_FAILURE() << "message not covered";
  }
}

std::vector<Message> our_messages() {
  MissionItemInt item;
  item.target_system = 1;
  item.target_component = 1;
  item.seq = 513;
  item.frame = 3;
  item.command = 16;
  item.current = 0;
  item.autocontinue = 1;
  item.param1 = 0.5F;
  item.param2 = 2.0F;
  item.param3 = -1.25F;
  item.param4 = 270.0F;
  item.x = -335000123;
  item.y = 1511234567;
  item.z = 42.75F;
  MissionItemInt speed{1, 1, 2, 2, 178, 0, 1, 1.0F, 8.5F, -1.0F, 0.0F, 0, 0, 0.0F, 0};
  return {Heartbeat{0, 6, 8, 0, 4, 3},
          Heartbeat{0x00ABCDEF, 2, 3, 0x59, 3, 3},
          MissionCount{1, 1, 321, 0, 0},
          MissionCount{2, 3, 7, 1, 0xA1B2C3D4},
          MissionRequestInt{255, 190, 0, 0},
          MissionRequestInt{255, 190, 4097, 2},
          MissionRequest{255, 190, 12, 0},
          item,
          speed,
          MissionAck{255, 190, kMissionAccepted, 0, 0},
          MissionAck{255, 190, kMissionInvalidSequence, 0, 77},
          MissionClearAll{1, 1, 0},
          MissionCurrent{12, 40, 3, 0, 0, 0, 0},
          MissionCurrent{0, 0, 0, 0, 0, 0, 0},
          MissionCurrent{65535, 65535, 5, 2, 1, 2, 3},
          MissionItemReached{0},
          MissionItemReached{39}};
}

}  // namespace

TEST(NodeMavlinkPeer, DecodesOurFrames) {
  SKIP_WITHOUT_NODE();
  const auto msgs = our_messages();
  std::string hex;
  std::vector<Header> headers;
  for (std::size_t i = 0; i < msgs.size(); ++i) {
    const Header h{static_cast<std::uint8_t>(250 + i), static_cast<std::uint8_t>(i + 1),
                   static_cast<std::uint8_t>(200 - i), 0, 0};
    headers.push_back(h);
    hex += mavtest::to_hex(encode(msgs[i], h)) + "\n";
  }
  const auto lines = json_lines(run_node("decode.js", hex));
  ASSERT_EQ(lines.size(), msgs.size() + 1);
  for (std::size_t i = 0; i < msgs.size(); ++i) {
    SCOPED_TRACE(std::string(message_info(msgs[i]).name) + " #" + std::to_string(i));
    const json& p = lines[i];
    EXPECT_EQ(p["magic"], 0xFD);
    EXPECT_EQ(p["msgid"], message_info(msgs[i]).id);
    EXPECT_EQ(p["name"], message_info(msgs[i]).name);
    EXPECT_EQ(p["seq"], headers[i].seq);
    EXPECT_EQ(p["sysid"], headers[i].sysid);
    EXPECT_EQ(p["compid"], headers[i].compid);
    expect_fields(p["fields"], msgs[i]);
  }
  // node-mavlink checked every checksum with its own CRC_EXTRA table
  EXPECT_EQ(lines.back()["summary"]["valid"], msgs.size());
  EXPECT_EQ(lines.back()["summary"]["invalid"], 0);
  EXPECT_EQ(lines.back()["summary"]["unknown"], 0);
}

TEST(NodeMavlinkPeer, RejectsOurFrameWithCorruptedChecksum) {
  SKIP_WITHOUT_NODE();
  auto frame = encode(MissionItemReached{5}, Header{1, 1, 1, 0, 0});
  frame.back() ^= 0xFF;
  const auto lines = json_lines(run_node("decode.js", mavtest::to_hex(frame)));
  ASSERT_EQ(lines.size(), 1U);  // only the summary
  EXPECT_EQ(lines[0]["summary"]["valid"], 0);
  EXPECT_EQ(lines[0]["summary"]["invalid"], 1);
}

TEST(NodeMavlinkPeer, WeDecodeItsFrames) {
  SKIP_WITHOUT_NODE();
  const json specs = json::parse(R"([
    {"message": "Heartbeat", "sysid": 1, "compid": 1, "seq": 0,
     "fields": {"type": 2, "autopilot": 3, "baseMode": 89, "customMode": 3, "systemStatus": 4, "mavlinkVersion": 3}},
    {"message": "MissionCount", "sysid": 255, "compid": 190, "seq": 1,
     "fields": {"targetSystem": 1, "targetComponent": 1, "count": 300, "missionType": 0}},
    {"message": "MissionRequestInt", "sysid": 1, "compid": 1, "seq": 2,
     "fields": {"targetSystem": 255, "targetComponent": 190, "seq": 299, "missionType": 0}},
    {"message": "MissionRequest", "sysid": 1, "compid": 1, "seq": 2,
     "fields": {"targetSystem": 255, "targetComponent": 190, "seq": 7, "missionType": 0}},
    {"message": "MissionItemInt", "sysid": 255, "compid": 190, "seq": 3,
     "fields": {"targetSystem": 1, "targetComponent": 1, "seq": 1, "frame": 3, "command": 16,
                "current": 0, "autocontinue": 1, "param1": 0, "param2": 0, "param3": 0, "param4": 0,
                "x": 473977420, "y": 85455940, "z": 20, "missionType": 0}},
    {"message": "MissionItemInt", "sysid": 255, "compid": 190, "seq": 4,
     "fields": {"targetSystem": 1, "targetComponent": 1, "seq": 2, "frame": 2, "command": 178,
                "current": 0, "autocontinue": 1, "param1": 1, "param2": 7.25, "param3": -1, "param4": 0,
                "x": 0, "y": 0, "z": 0, "missionType": 0}},
    {"message": "MissionAck", "sysid": 1, "compid": 1, "seq": 5,
     "fields": {"targetSystem": 255, "targetComponent": 190, "type": 0, "missionType": 0, "opaqueId": 123456}},
    {"message": "MissionClearAll", "sysid": 255, "compid": 190, "seq": 6,
     "fields": {"targetSystem": 1, "targetComponent": 1, "missionType": 0}},
    {"message": "MissionCurrent", "sysid": 1, "compid": 1, "seq": 7,
     "fields": {"seq": 17, "total": 42, "missionState": 3, "missionMode": 1}},
    {"message": "MissionItemReached", "sysid": 1, "compid": 1, "seq": 8, "fields": {"seq": 16}},
    {"message": "MissionItemReached", "sysid": 1, "compid": 1, "seq": 9, "fields": {"seq": 0}}
  ])");
  const std::string out = run_node("encode.js", specs.dump());
  // All frames in one stream with garbage between them: our parser must find every one.
  std::vector<std::uint8_t> stream{0x01, 0xFD, 0x02};
  std::istringstream ss(out);
  std::string line;
  std::size_t lines = 0;
  while (std::getline(ss, line)) {
    if (line.empty()) continue;
    ++lines;
    const auto bytes = mavtest::from_hex(line);
    stream.insert(stream.end(), bytes.begin(), bytes.end());
    stream.insert(stream.end(), {0xFE, 0x00});
  }
  ASSERT_EQ(lines, specs.size());
  Parser p;
  std::vector<Frame> frames;
  p.push(stream, frames, true);
  ASSERT_EQ(frames.size(), specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const json& s = specs[i];
    SCOPED_TRACE(s["message"].get<std::string>());
    EXPECT_EQ(frames[i].header.sysid, s["sysid"]);
    EXPECT_EQ(frames[i].header.compid, s["compid"]);
    EXPECT_EQ(frames[i].header.seq, s["seq"]);
    const auto msg = decode(frames[i]);
    ASSERT_TRUE(msg);
    EXPECT_EQ(frames[i].msgid, message_info(*msg).id);
    // Every field node-mavlink was given comes back; the others are zero (node's defaults).
    expect_fields(s["fields"], *msg);
  }
}

namespace {

// Reads one line from a pipe (empty at EOF).
std::string read_line(FILE* f) {
  std::string line;
  int c;
  while ((c = std::fgetc(f)) != EOF && c != '\n') line += static_cast<char>(c);
  return line;
}

/// What vehicle.js reported after an upload to it as system 9: our result, its exit status, and the items
/// as node-mavlink decoded them.
struct NodeUpload {
  UploadResult result;
  int status = -1;
  json items;
};

NodeUpload upload_to_node(const std::vector<MissionItemInt>& items, const std::string& order,
                          const std::string& transport = "udp") {
  NodeUpload out;
  const std::string cmd = "node '" + (kNodeDir / "vehicle.js").string() + "' " + order + " 9 " + transport;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (pipe == nullptr) return out;
  const auto port = json::parse(read_line(pipe)).at("port").get<std::uint16_t>();
  auto gcs =
      open_link(parse_link_address(transport + ":127.0.0.1:" + std::to_string(port), "--to"), 255, 190);
  if (auto* tcp = dynamic_cast<TcpClientLink*>(gcs.get())) {
    EXPECT_EQ(tcp->connect(std::chrono::seconds(2)), "");
  }
  UploadOptions opt;
  opt.target_system = 9;
  out.result = upload_mission(*gcs, items, opt);
  const std::string report = read_line(pipe);
  out.status = ::pclose(pipe);
  if (out.result.ok) out.items = json::parse(report).at("items");
  return out;
}

}  // namespace

static void upload_to_node_in_both_orders(const std::string& transport) {
  std::vector<MissionItemInt> items;
  for (std::uint16_t i = 0; i < 12; ++i) {
    MissionItemInt m;
    m.frame = i == 0 ? 0 : 3;
    m.command = i == 1 ? 22 : 16;
    m.x = 406000000 + 1234 * i;
    m.y = 229000000 - 4321 * i;
    m.z = i == 0 ? 0.0F : 40.0F + 0.5F * i;
    m.param4 = static_cast<float>(i) * 0.25F;
    m.autocontinue = 1;
    items.push_back(m);
  }
  for (const std::string order : {"sequential", "reverse"}) {
    SCOPED_TRACE(order);
    const NodeUpload up = upload_to_node(items, order, transport);
    const UploadResult& res = up.result;
    ASSERT_TRUE(res.ok) << res.error;
    EXPECT_EQ(up.status, 0);
    EXPECT_EQ(res.unique_items, items.size());
    if (order == "reverse") {
      EXPECT_EQ(res.out_of_order, items.size() - 1);
    }
    const json& got = up.items;
    ASSERT_EQ(got.size(), items.size());
    for (std::size_t i = 0; i < items.size(); ++i) {
      MissionItemInt want = items[i];
      want.seq = static_cast<std::uint16_t>(i);
      want.target_system = 9;
      want.target_component = 1;
      expect_fields(got[i], want);
    }
  }
}

TEST(NodeMavlinkPeer, UploadToItsVehicleOverUdp) {
  SKIP_WITHOUT_NODE();
  upload_to_node_in_both_orders("udp");
}

// Issue 34: over TCP, node-mavlink's vehicle listening (as SITL on 5760) and writing every frame in two
// pieces; our client reads a byte stream.
TEST(NodeMavlinkPeer, UploadToItsVehicleOverTcp) {
  SKIP_WITHOUT_NODE();
  upload_to_node_in_both_orders("tcp");
}

// Issue 18: a camera plan's upload carries the gimbal and trigger items, as node-mavlink decodes them.
TEST(NodeMavlinkPeer, UploadCarriesCameraTriggersAndGimbal) {
  SKIP_WITHOUT_NODE();
  const uavcover::Plan plan = uavcover::fixture::two_uav_plan(true);
  const std::vector<MissionItemInt> items =
      to_mission_items(uavcover::waypoints::mission_items(plan, 0), std::nullopt);
  const NodeUpload up = upload_to_node(items, "sequential");
  EXPECT_EQ(up.status, 0);
  ASSERT_TRUE(up.result.ok) << up.result.error;
  const json& got = up.items;
  ASSERT_EQ(got.size(), items.size());
  int gimbal = 0, start = 0, stop = 0;
  // JSON has no NaN: node's JSON.stringify writes NaN params (yaw "keep heading", unset rates) as null
  auto same = [](const json& v, float want) {
    return v.is_null() ? std::isnan(want) : static_cast<float>(v.get<double>()) == want;
  };
  for (std::size_t i = 0; i < items.size(); ++i) {
    const MissionItemInt& want = items[i];
    EXPECT_EQ(got[i].at("seq").get<int>(), static_cast<int>(i));
    EXPECT_EQ(got[i].at("command").get<int>(), want.command);
    EXPECT_EQ(got[i].at("frame").get<int>(), want.frame);
    EXPECT_EQ(at(got[i], "x").get<std::int64_t>(), want.x);
    EXPECT_EQ(at(got[i], "y").get<std::int64_t>(), want.y);
    EXPECT_TRUE(same(got[i].at("z"), want.z)) << i;
    EXPECT_TRUE(same(got[i].at("param1"), want.param1)) << i;
    EXPECT_TRUE(same(got[i].at("param2"), want.param2)) << i;
    EXPECT_TRUE(same(got[i].at("param3"), want.param3)) << i;
    EXPECT_TRUE(same(got[i].at("param4"), want.param4)) << i;
    const int command = got[i].at("command").get<int>();
    if (command == 1000) {
      ++gimbal;
      EXPECT_FLOAT_EQ(got[i].at("param1").get<float>(), -90.0F);
    }
    if (command == 206) (got[i].at("param1").get<float>() > 0 ? start : stop) += 1;
  }
  EXPECT_EQ(gimbal, 1);
  EXPECT_EQ(start, 6);  // alpha's loop: 6 legs, each started and stopped
  EXPECT_EQ(stop, 6);
}

// Issue 31: the geofence and the rally points go up after the mission with their own mission types
// (MAV_MISSION_TYPE_FENCE, _RALLY), and node-mavlink's vehicle keeps the three apart.
TEST(NodeMavlinkPeer, UploadsFenceAndRallyWithTheirMissionTypes) {
  SKIP_WITHOUT_NODE();
  uavcover::Plan plan = uavcover::fixture::two_uav_plan(false);
  const uavcover::geodesy::LocalFrame frame(plan.origin);
  plan.rally = {frame.to_wgs84({-60, 20}), frame.to_wgs84({40, 20})};
  plan.uavs[0].transition_altitude_m = 60.0;
  const auto exported = uavcover::waypoints::mission_items(plan, 0);
  const auto fence =
      to_mission_items(uavcover::autopilot::fence_items(plan, 0, exported, 20.0), std::nullopt);
  const auto rally = to_mission_items(uavcover::autopilot::rally_items(plan, 0), std::nullopt);
  const auto mission = to_mission_items(exported, std::nullopt);
  ASSERT_EQ(rally.size(), 2U);

  const std::string cmd = "node '" + (kNodeDir / "vehicle.js").string() + "' all 9 udp";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  const auto port = json::parse(read_line(pipe)).at("port").get<std::uint16_t>();
  auto gcs = open_link(parse_link_address("udp:127.0.0.1:" + std::to_string(port), "--to"), 255, 190);
  UploadOptions opt;
  opt.target_system = 9;
  std::vector<UploadResult> results;
  for (const auto& [items, type] :
       {std::pair{&mission, kMissionTypeMission}, std::pair{&fence, kMissionTypeFence},
        std::pair{&rally, kMissionTypeRally}}) {
    opt.mission_type = type;
    results.push_back(upload_mission(*gcs, *items, opt));
  }
  std::vector<json> lines;
  for (int k = 0; k < 3; ++k) lines.push_back(json::parse(read_line(pipe)));
  EXPECT_EQ(::pclose(pipe), 0);
  for (const auto& r : results) EXPECT_TRUE(r.ok) << r.error;
  ASSERT_TRUE(lines[0].contains("items"));
  ASSERT_TRUE(lines[1].contains("fence"));
  ASSERT_TRUE(lines[2].contains("rally"));
  EXPECT_EQ(lines[0]["items"].size(), mission.size());
  // the fence: the inclusion polygon, then the no-fly zone (4 vertices) as an exclusion polygon
  const json& f = lines[1]["fence"];
  ASSERT_EQ(f.size(), fence.size());
  std::size_t inclusion = 0, exclusion = 0;
  for (const auto& it : f) {
    EXPECT_EQ(it.at("missionType").get<int>(), 1);
    const int c = it.at("command").get<int>();
    (c == 5001 ? inclusion : exclusion) += 1;
    EXPECT_TRUE(c == 5001 || c == 5002) << c;
  }
  EXPECT_EQ(exclusion, 4U);
  EXPECT_GE(inclusion, 3U);
  for (const auto& it : f)
    EXPECT_EQ(it.at("param1").get<double>(),
              static_cast<double>(it.at("command").get<int>() == 5001 ? inclusion : exclusion));
  const json& r = lines[2]["rally"];
  ASSERT_EQ(r.size(), 2U);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(r[k].at("command").get<int>(), 5100);
    EXPECT_EQ(r[k].at("missionType").get<int>(), 2);
    EXPECT_EQ(at(r[k], "x").get<std::int64_t>(), std::llround(plan.rally[k].lat * 1e7));
    EXPECT_EQ(at(r[k], "y").get<std::int64_t>(), std::llround(plan.rally[k].lon * 1e7));
    EXPECT_FLOAT_EQ(r[k].at("z").get<float>(), 60.0F);
  }
}
