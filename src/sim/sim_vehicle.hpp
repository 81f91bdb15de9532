// A simulated MAVLink 2 multirotor (one UDP endpoint, one system id) and a fleet of them driven by one
// event loop, for rehearsal, demos and tests (`uavcover simulate`, docs/simulate.md).
//
// Each vehicle answers HEARTBEAT, receives missions through the mission protocol (mavlink::Vehicle,
// shared with the upload tests), obeys COMMAND_LONG arm/disarm, mission start, pause/continue, set the
// current item (MAV_CMD_DO_SET_MISSION_CURRENT), RTL and land (COMMAND_ACK), flies its mission items with a P
// controller on position under speed and acceleration limits (Hong et al. 2021, eq. 1-2), drains a linear
// battery, and reports telemetry.
//
// Two clocks: flight, battery and telemetry run in simulated time (fixed steps, `speedup` times faster
// than wall time); the mission protocol's timeouts stay in wall time (they are about the network).
#pragma once

#include <atomic>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <stop_token>
#include <string>
#include <utility>
#include <vector>

#include "autopilot/fence.hpp"
#include "geodesy/local_frame.hpp"
#include "mavlink/messages.hpp"
#include "mavlink/mission_protocol.hpp"
#include "mavlink/udp.hpp"
#include "uavcover/geometry.hpp"
#include "uavcover/terrain.hpp"

namespace uavcover::sim {

enum class Autopilot { Px4, Generic };
/// Link: silent and deaf, flies on. Land: a forced landing where it is. Stuck: it stops making progress
/// towards its mission items (holds where it is, as in a wind beyond its power or a bad position
/// estimate) but keeps its link, answers commands and still flies RTL and land.
enum class FailureKind { Link, Land, Stuck };

/// Failure injection: when the vehicle has flown `fraction` of its mission's planned path length.
struct Failure {
  double fraction = 0.5;
  FailureKind kind = FailureKind::Link;
};

struct VehicleConfig {
  std::uint8_t sysid = 1;
  mavlink::Endpoint listen{"127.0.0.1", 0};  ///< port 0: any free port
  bool tcp = false;  ///< listen for TCP clients (the newest one is the ground station) instead of UDP
  /// Tests: the mission protocol's ArduPilot-like storage and refusal of an item (mavlink::VehicleOptions).
  bool store_as_received = false;
  std::optional<std::uint16_t> refuse_item;
  /// Where the vehicle stands at start. Unset: at the home (or take-off) position of the first mission
  /// uploaded before it flies.
  std::optional<LonLat> home;
  double home_amsl_m = 0.0;  ///< ground altitude above mean sea level (GLOBAL_POSITION_INT.alt)
  /// The ground (issue 31): heights in the terrain frame (MAV_FRAME_GLOBAL_TERRAIN_ALT, 10 and 11) are
  /// above it, followed under the vehicle along each leg as ArduPilot's terrain following does. Null: no
  /// terrain data, and MISSION_START of a mission with such items is refused ("PreArm: Waiting for
  /// terrain data"), as ArduPilot without terrain data refuses it.
  std::shared_ptr<const HeightGrid> ground;
  /// A plan's DEM (or none) as the ground: `ground`, and `home_amsl_m` the ground's height at `home`
  /// when both are known (AMSL heights over the ground under home).
  void set_ground(std::shared_ptr<const HeightGrid> dem) {
    ground = std::move(dem);
    if (ground && home) home_amsl_m = ground->at(*home);
  }
  double v_max = 5.0;                ///< m/s horizontal, until the mission's DO_CHANGE_SPEED
  double a_max = 2.0;                ///< m/s^2
  double v_up = 3.0, v_down = 1.5;   ///< vertical speed limits, m/s
  double kp = 1.0;                   ///< 1/s, position gain
  double acceptance_radius_m = 2.0;  ///< a waypoint counts reached within this (3D) distance
  double endurance_min = 20.0;       ///< a full battery lasts this long armed
  double low_battery_pct = 20.0;     ///< STATUSTEXT warning at this charge
  double wind_mps = 0.0;             ///< constant wind speed
  double wind_from_deg = 270.0;      ///< where it blows from (meteorological, 270 = from the west)
  std::optional<Failure> failure;
  double loss = 0.0;  ///< drop this fraction of sent and received datagrams
  std::uint64_t seed = 1;
  double telemetry_hz = 5.0;  ///< GLOBAL_POSITION_INT and MISSION_CURRENT rate (sim time)
  Autopilot autopilot = Autopilot::Px4;
};

/// What the vehicle is doing.
enum class Mode { Standby, Hold, Mission, Rtl, Land };

/// MISSION_STATE values.
enum MissionState : std::uint8_t {
  kMissionStateUnknown = 0,
  kMissionStateNoMission = 1,
  kMissionStateNotStarted = 2,
  kMissionStateActive = 3,
  kMissionStatePaused = 4,
  kMissionStateComplete = 5,
};

struct Vec3 {
  double x = 0, y = 0, z = 0;  ///< east, north, up (m) from home
};

/// A snapshot of a vehicle (for tests and the fleet's summary).
struct VehicleState {
  double t = 0;  ///< simulated seconds since start
  Vec3 p, v;
  bool armed = false;
  bool airborne = false;
  bool link_lost = false;
  bool failed = false;     ///< a failure was injected (link or forced landing)
  double failed_at_s = 0;  ///< when
  Mode mode = Mode::Standby;
  double battery = 1.0;  ///< remaining fraction 0..1
  std::optional<std::uint16_t> current_seq;
  std::vector<std::uint16_t> reached;      ///< every MISSION_ITEM_REACHED sent, in order
  std::vector<std::uint16_t> set_current;  ///< every MAV_CMD_DO_SET_MISSION_CURRENT accepted (its seq)
  double flown_m = 0;                      ///< odometer during missions
  double planned_m = 0;                    ///< planned path length of the mission from where it started
  bool mission_complete = false;
  bool fence_breach = false;  ///< left its fence (issue 31): switched to RTL
  /// With VehicleConfig::ground: the lowest height above the ground on the way to terrain-frame items (m).
  double agl_min_m = std::numeric_limits<double>::infinity();
};

class SimVehicle {
 public:
  explicit SimVehicle(const VehicleConfig& config);
  SimVehicle(const SimVehicle&) = delete;
  SimVehicle& operator=(const SimVehicle&) = delete;

  [[nodiscard]] std::uint8_t sysid() const { return cfg_.sysid; }
  [[nodiscard]] std::uint16_t port() const { return link_->local_port(); }
  /// The descriptors to poll for input (a TCP listener: its socket, and its client's once connected).
  [[nodiscard]] std::vector<int> poll_handles() const { return link_->poll_handles(); }
  [[nodiscard]] const VehicleState& state() const { return st_; }
  [[nodiscard]] const mavlink::Link& link() const { return *link_; }
  /// The stored mission (after a refused upload: the items received before the refused one, as ArduPilot).
  [[nodiscard]] const std::vector<mavlink::MissionItemInt>& stored_mission() const {
    return protocol_.mission();
  }
  [[nodiscard]] const std::vector<mavlink::MissionItemInt>& mission() const { return protocol_.mission(); }
  /// The fence and rally points uploaded (issue 31; empty: none).
  [[nodiscard]] const autopilot::Fence& fence() const { return fence_; }
  /// The fence items as stored by the mission protocol (set before it acknowledges an upload or a clear,
  /// so a ground station that heard the ack sees them; fence() follows once the vehicle has read them).
  [[nodiscard]] const std::vector<mavlink::MissionItemInt>& stored_fence() const { return protocol_.fence(); }
  [[nodiscard]] const std::vector<mavlink::MissionItemInt>& rally() const { return protocol_.rally(); }
  /// Tests without a link: the fence as an upload would set it.
  void set_fence(const autopilot::Fence& fence) { fence_ = fence; }
  [[nodiscard]] LonLat position_wgs84() const;
  /// Where telemetry goes until a ground station speaks (then: whoever sent last). UDP only: a TCP
  /// vehicle talks to its client.
  void set_peer(const mavlink::Endpoint& gcs);

  /// Reads and handles every datagram waiting on the socket (non-blocking), then the protocol's
  /// wall-time timeouts. A vehicle whose link failed reads and discards.
  void service_link();
  /// The mission protocol's wall-time timeouts only (service_link() does them too).
  void service_timeouts();
  /// Advances simulated time by `dt` seconds: flight, battery, failures, telemetry.
  void step(double dt);

  // Commands, as COMMAND_LONG does them (also for tests without a link). MAV_RESULT.
  std::uint8_t arm(bool on, bool force = false);
  std::uint8_t start_mission(int first = 0, int last = -1);
  std::uint8_t pause(bool pause);
  std::uint8_t return_to_launch();
  std::uint8_t land_here();
  /// MAV_CMD_DO_SET_MISSION_CURRENT: in a mission, fly to item `seq` now (from where the vehicle is);
  /// otherwise only reported current (MISSION_CURRENT). FAILED when out of range (or no mission).
  std::uint8_t set_current(int seq);
  /// Replaces the stored mission as an upload would (for tests without a link).
  void set_mission(const std::vector<mavlink::MissionItemInt>& items);

 private:
  struct Target {
    Vec3 p;
    bool land = false;  ///< descend to the ground (then the item is done on touchdown)
    /// A terrain-frame item's height above the ground: the goal's height follows the ground under the
    /// vehicle (p.z is the height at the target itself, for the arrival check).
    std::optional<double> agl;
  };
  void handle(const mavlink::Received& r);
  void on_command(const mavlink::CommandLong& c, const mavlink::Received& r);
  void load_mission();
  [[nodiscard]] bool is_home_item(std::size_t seq) const;
  [[nodiscard]] std::vector<Target> item_targets(const mavlink::MissionItemInt& item, const Vec3& from) const;
  [[nodiscard]] Vec3 to_local(std::int32_t lat_e7, std::int32_t lon_e7) const;
  [[nodiscard]] double item_alt(const mavlink::MissionItemInt& item) const;
  /// The ground's height above home under local point (x, y) (0 without VehicleConfig::ground).
  [[nodiscard]] double ground_above_home(double x, double y) const;
  void begin_item(std::size_t seq);
  void item_done();
  void complete_mission();
  void fly(double dt);
  void touchdown();
  void drain(double dt);
  void check_failure();
  void telemetry(double dt);
  void send(const mavlink::Message& m);
  void status(std::uint8_t severity, const std::string& text);
  void send_current();
  [[nodiscard]] mavlink::Heartbeat heartbeat() const;

  VehicleConfig cfg_;
  std::unique_ptr<mavlink::Link> link_;
  mavlink::Vehicle protocol_;
  std::optional<geodesy::LocalFrame> frame_;
  bool home_fixed_ = false;
  std::size_t mission_version_ = 0;
  std::vector<mavlink::MissionItemInt> mission_;
  std::size_t first_item_ = 0, last_item_ = 0;  ///< mission range being flown
  std::size_t item_ = 0;                        ///< current item
  std::vector<Target> targets_;                 ///< of the current item (or of RTL/land), in order
  std::size_t target_ = 0;
  double v_max_;
  Vec3 wind_;
  Vec3 hold_;
  Vec3 stuck_at_;  ///< FailureKind::Stuck: where it stopped making progress
  bool paused_ = false;
  std::uint16_t heading_cdeg_ = 0;
  VehicleState st_;
  bool low_battery_sent_ = false;
  double next_fast_ = 0, next_slow_ = 0;
  std::optional<std::uint16_t> last_sent_current_;
  autopilot::Fence fence_;
  std::size_t fence_version_ = 0;
  bool fence_breached_ = false;
  std::uint8_t last_sent_state_ = 0;
};

struct FleetOptions {
  double speedup = 1.0;      ///< simulated seconds per wall second
  double physics_dt = 0.05;  ///< simulated seconds per step
};

/// N vehicles and the loop that runs them: waits on every socket until the next step is due in
/// wall time, handles what arrived, then steps every vehicle by physics_dt of simulated time.
class Fleet {
 public:
  Fleet(const std::vector<VehicleConfig>& configs, const FleetOptions& options);
  [[nodiscard]] std::vector<std::unique_ptr<SimVehicle>>& vehicles() { return vehicles_; }
  /// Simulated seconds run so far (may be read from another thread while run() runs).
  [[nodiscard]] double sim_time() const { return sim_time_.load(); }
  /// Runs until `stop` is requested (or, when given, `max_sim_s` of simulated time has passed).
  void run(const std::stop_token& stop, std::optional<double> max_sim_s = std::nullopt);

 private:
  FleetOptions opt_;
  std::vector<std::unique_ptr<SimVehicle>> vehicles_;
  std::atomic<double> sim_time_{0.0};
};

/// Parses "ID@FRACTION[:link|:land|:stuck]" (ID = system id 1..255, FRACTION in (0, 1)); throws InputError
/// naming `field`.
std::pair<std::uint8_t, Failure> parse_failure(const std::string& text, const std::string& field = "--fail");

}  // namespace uavcover::sim
