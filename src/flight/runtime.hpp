// The flight runtime's internal state (docs/flights.md, "Runtime"): shared by flight.cpp (records,
// phases, the public class), missions.cpp (each UAV's missions, reassigned work), supervisor.cpp,
// commands.cpp, snapshot.cpp (snapshot and restore) and link.cpp (one thread per vehicle: the MAVLink
// link, telemetry, waypoint statuses). Everything under Impl::mutex.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <stop_token>
#include <string>
#include <thread>
#include <vector>

#include "flight/flight.hpp"
#include "flight/reassign.hpp"
#include "geodesy/local_frame.hpp"
#include "mavlink/messages.hpp"
#include "mavlink/udp.hpp"
#include "uavcover/vehicle.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::flight::detail {

using Clock = std::chrono::steady_clock;

inline constexpr std::size_t kTrailMax = 600;      ///< trail points per UAV in the snapshot
inline constexpr std::size_t kTrackMax = 20000;    ///< flown track points per UAV (decimated beyond)
inline constexpr std::size_t kAlertsMax = 256;     ///< alerts kept (the oldest inactive go first)
inline constexpr std::size_t kPendingMax = 20000;  ///< log records waiting for the observer
inline constexpr std::size_t kActionsMax = 64;     ///< queued link actions per UAV
inline constexpr std::size_t kReassignMax = 64;    ///< reassignments per flight
/// An offer from the air is re-planned when applied after a helper has flown this far from its depot.
inline constexpr double kStaleDepotM = 20.0;
inline constexpr int kUploadAttempts = 3;                         ///< whole mission uploads before giving up
inline constexpr std::chrono::milliseconds kCommandPeriod{1000};  ///< COMMAND_LONG resend period
inline constexpr std::uint8_t kGcsSysid = 255, kGcsCompid = 190;  ///< ours (MAV_COMP_ID_MISSIONPLANNER)

/// One mission of a UAV's queue: a battery sortie of its plan, a resumed rest, or reassigned work.
struct MissionSpec {
  std::string kind = "sortie";                 ///< "sortie", "resume", "reassigned"
  int index = 0;                               ///< the sortie's number (for reassigned work: within the work)
  int first_waypoint = 0, last_waypoint = -1;  ///< coverage waypoints (own: global; reassigned: the work's)
  int from_waypoint = -1;  ///< own kinds: the last reached waypoint the list was built from (-1: the plan)
  int k = 0;               ///< position in that list (reassigned: in the work's missions)
  int reassignment = 0;    ///< reassigned: its id
  std::string state = "pending";  ///< pending, uploading, ready, flying, done, interrupted, skipped
  std::string waypoints;          ///< reassigned: statuses of first..last
  std::vector<waypoints::MissionItem> items;
  // ETA: per item, the air distance (the path length in calm air; issue 32: each leg at its ground speed in
  // the mission's wind) and coverage waypoints from that item to the end
  std::vector<double> rest_m;
  std::vector<int> rest_turns;
  /// seconds climbing or descending beyond the horizontal flight from that item to the end (the whole
  /// flight, docs/wind.md): the leg arriving at an item counts with it
  std::vector<double> rest_vertical_s;
  std::vector<std::optional<Point>> where;  ///< each item's position (local metres), if it has one
};

struct Action {
  enum class Kind { Upload, Command } kind = Kind::Command;
  std::size_t mission = 0;  ///< Upload: index into the UAV's missions
  mavlink::CommandLong cmd;
  std::string name;  ///< command name for the log ("arm", "mission_start", ...)
};

struct Alert {
  std::string kind, uav, other, message;
  std::int64_t since_ms = 0;
  bool active = true;
};

struct UavRt {
  std::size_t index = 0;  ///< into plan.uavs
  VehicleBinding binding;
  std::string phase = "idle";
  // link
  std::string link_state = "unknown";  ///< unknown, ok, lost
  Clock::time_point last_heard{};
  std::int64_t last_heard_ms = 0;
  std::size_t rx = 0, tx = 0;
  std::optional<Clock::time_point> lost_since;
  // telemetry
  bool have_position = false;
  double lon = 0, lat = 0, alt_m = 0, speed_mps = 0, heading_deg = 0;
  bool armed = false;
  std::string mode = "unknown";
  std::optional<double> battery_pct;
  std::string band = "ground";
  Clock::time_point next_log{};
  bool deviating = false, low_battery = false;  ///< alerts raised
  // missions
  std::vector<MissionSpec> missions;
  std::size_t current = 0;     ///< the mission flown or next to fly (== missions.size(): none left)
  std::string waypoints;       ///< own coverage waypoints: P, C, R, S
  bool airborne_seen = false;  ///< during the current mission
  bool interrupted = false;    ///< landed (or lost) with the current mission's coverage left
  std::optional<Clock::time_point> interrupted_since;
  bool offered = false;             ///< a reassignment was offered for this failure
  std::optional<int> current_item;  ///< mission item index (seq minus home) the vehicle flies
  Clock::time_point retry_after{};  ///< automatic next sortie / start: not before
  // waypoint retries (docs/flights.md, "Waypoint retries"): the coverage item under its deadline
  std::optional<std::pair<std::size_t, int>> timed;  ///< (mission, item) being timed
  std::optional<Clock::time_point> deadline;         ///< not reached by then: retried (unset: paused)
  int timed_waypoint = -1;                           ///< its coverage waypoint (MissionItem::waypoint)
  int retries = 0;                                   ///< re-commands of the timed item so far
  int retries_total = 0;                             ///< over the flight
  // tracks
  std::deque<std::array<double, 3>> trail;
  std::vector<std::array<double, 3>> track;
  std::size_t track_stride = 1, track_skip = 0;
  // link actions (executed by the UAV's thread in order)
  std::deque<Action> actions;
  bool command_active = false;
  Action active;
  int tries_left = 0;
  Clock::time_point resend_at{};
  std::optional<std::uint8_t> ack_result;  ///< COMMAND_ACK received for the active command
};

struct ReassignmentRt {
  int id = 0;
  std::string failed_uav;
  std::size_t failed = 0;
  std::string state = "offered";  ///< offered, applied, declined
  std::int64_t at_ms = 0;
  int last_reached = -1;
  std::vector<Helper> helpers;
  std::shared_ptr<const Reassignment> result;
  std::string from = "home";  ///< where the helpers' work starts (FlightConfig::reassign_from)
  std::string replan_from;    ///< state "replanning": the choice the operator asked for
};

}  // namespace uavcover::flight::detail

namespace uavcover::flight {

struct Flight::Impl {
  Impl(std::int64_t id, Plan plan, FlightConfig config, Observer& observer);

  const std::int64_t id;
  const Plan plan;
  const FlightConfig config;
  Observer& observer;
  const geodesy::LocalFrame frame;

  mutable std::mutex mutex;
  std::vector<detail::UavRt> uavs;
  std::vector<detail::Alert> alerts;
  std::vector<detail::ReassignmentRt> reassignments;
  bool started = false;  ///< a start was commanded once
  bool aborted = false;
  std::string state = "created";
  std::vector<LogRecord> pending;
  bool dirty = true;

  std::mutex flush_mutex;  ///< keeps the observer's records in order
  std::vector<std::unique_ptr<mavlink::Link>> links;
  std::vector<std::jthread> threads;
  bool running = false;

  // ---- under mutex ----
  void record(const std::string& uav, const std::string& kind, nlohmann::json data);
  void set_alert(const std::string& kind, const std::string& uav, const std::string& other, bool active,
                 const std::string& message);
  void set_phase(detail::UavRt& u, const std::string& phase);
  void set_waypoint(detail::UavRt& u, detail::MissionSpec& m, int waypoint, char status);
  void on_current(detail::UavRt& u, int item, std::uint8_t mission_state);
  void on_reached(detail::UavRt& u, int item);
  void on_heartbeat(detail::UavRt& u, const mavlink::Heartbeat& hb);
  void on_position(detail::UavRt& u, const mavlink::GlobalPositionInt& g);
  void check_landed(detail::UavRt& u);
  void finish_command(detail::UavRt& u, bool ok, const std::string& outcome);
  [[nodiscard]] bool command_effect_seen(const detail::UavRt& u) const;
  [[nodiscard]] bool has_work_left(const detail::UavRt& u) const;
  [[nodiscard]] bool settled(const detail::UavRt& u) const;
  [[nodiscard]] int last_reached(const detail::UavRt& u) const;
  /// The status (P, C, R, S) of coverage waypoint `waypoint` of mission `m` (own missions: global
  /// index; reassigned: the work's), or 0 when out of range.
  [[nodiscard]] char waypoint_status(const detail::UavRt& u, const detail::MissionSpec& m,
                                     int waypoint) const;
  /// Whether every coverage waypoint of mission `m` is reached or skipped.
  [[nodiscard]] bool coverage_done(const detail::UavRt& u, const detail::MissionSpec& m) const;
  /// Waypoint retries: times the current coverage item, re-commands it, fails the UAV (supervisor).
  void check_waypoint(detail::UavRt& u, detail::Clock::time_point now);
  /// The deadline of mission item `item` from where the UAV is now (seconds).
  [[nodiscard]] double waypoint_timeout_s(const detail::UavRt& u, const detail::MissionSpec& m,
                                          int item) const;
  /// Marks the UAV failed (its mission interrupted, its queue cleared): a reassignment is offered.
  void fail_uav(detail::UavRt& u);
  /// The helpers of a reassignment for failed UAV `failed`, starting from `from` ("home", "air").
  [[nodiscard]] std::vector<Helper> helpers_for(const detail::UavRt& failed, const std::string& from) const;
  /// Whether helper `h` flies one of its own missions now (it can be diverted from the air).
  [[nodiscard]] bool divertable(const detail::UavRt& h) const;
  /// Replaces the UAV's missions after the current one by `first`, then the rest of its own coverage
  /// from its last reached waypoint, then the reassigned work still pending; the current is the next.
  void requeue(detail::UavRt& u, std::vector<detail::MissionSpec> first);
  void queue_upload_and_start(detail::UavRt& u);
  void queue_command(detail::UavRt& u, const std::string& name, std::uint16_t command, float p1 = 0,
                     float p2 = 0);
  void update_state();
  void supervise_locked(detail::Clock::time_point now);
  detail::MissionSpec make_mission(std::size_t uav, std::vector<waypoints::MissionItem> items) const;
  [[nodiscard]] std::vector<detail::MissionSpec> own_missions(std::size_t uav, int from_waypoint) const;
  /// The vehicle profile UAV `uav` flies (issue 31): the mission's (the UAV's own, else the mission's)
  /// when it names a MAVLink one, else ArduPilot for a binding with a home item, else PX4.
  [[nodiscard]] const VehicleProfile& profile_of(std::size_t uav) const;
  /// Whether UAV `uav`'s binding sends the home position as item 0.
  [[nodiscard]] bool home_item_of(std::size_t uav) const;
  void apply_reassignment(detail::ReassignmentRt& r);
  /// Why an offer from the air would start a helper where it no longer is (issue 33: an offer applied
  /// late): a helper that has flown more than kStaleDepotM from its depot, or can no longer be diverted.
  /// Empty when every depot still holds (or the offer has none).
  [[nodiscard]] std::string stale_depot(const detail::ReassignmentRt& r) const;
  /// apply_reassignment() for the supervisor: a refusal goes to the log instead of the thread.
  void apply_safely(detail::ReassignmentRt& r);
  [[nodiscard]] detail::MissionSpec reassigned_mission(const detail::ReassignmentRt& r,
                                                       const ReassignedWork& w, std::size_t k) const;
  [[nodiscard]] nlohmann::json snapshot_locked() const;
  void restore(const nlohmann::json& s);

  // ---- threads ----
  void vehicle_loop(std::size_t i, const std::stop_token& stop);
  void vehicle_step(std::size_t i, mavlink::Link& link, detail::Clock::time_point& next_heartbeat,
                    std::vector<mavlink::Received>& batch, const std::stop_token& stop);
  void supervisor_loop(const std::stop_token& stop);
  void flush();
  std::int64_t last_changed_ms = 0;
  std::atomic<std::int64_t> cpu_ns{0};  ///< CPU time of the flight's threads that ended (docs: runtime)
  void add_thread_cpu();
};

std::int64_t now_ms();

namespace detail {

/// Whether a phase is one in the air (flying, paused or returning).
inline bool airborne_phase(const std::string& p) {
  return p == "flying" || p == "paused" || p == "returning";
}

}  // namespace detail

}  // namespace uavcover::flight
