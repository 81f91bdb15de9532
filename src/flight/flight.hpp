// Live execution of a plan (issue 12, docs/flights.md): a Flight binds a done plan to vehicles, one
// per UAV, each over its own MAVLink 2 link (UDP, TCP or serial; listen or connect). It uploads the UAVs'
// missions (battery sorties, resume, reassigned work), sends commands, reads telemetry, keeps every coverage
// waypoint's status (pending, current, reached, skipped), raises alerts and offers (or applies) the
// reassignment of a failed UAV's remaining coverage to the others.
//
// The module never touches a database or a disk: what must be kept (the downsampled flight log, the
// flight's state) goes to the Observer, which the server implements over the store.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "mavlink/link.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::flight {

/// One vehicle of a flight: which UAV of the plan it flies and how to reach it.
struct VehicleBinding {
  std::string uav;             ///< UavPlan::id
  mavlink::Endpoint endpoint;  ///< udp, tcp: HOST:PORT
  bool listen = false;         ///< true: bind HOST:PORT and learn the vehicle's address from its first
                               ///< datagram (UDP: a vehicle or mavlink-router that sends to us), or
                               ///< accept its TCP connection; false: send to HOST:PORT from an ephemeral
                               ///< local port (UDP), or connect to it (TCP, reconnecting after a loss)
  std::uint8_t sysid = 1;      ///< the vehicle's MAVLink system id
  std::uint8_t compid = 1;     ///< the autopilot's component id
  /// ArduPilot: mission item 0 is the home position (the upload adds it and shifts the seqs).
  bool home_item = false;
  /// Udp, Tcp or Serial ("udp:HOST:PORT", "tcp:HOST:PORT", "serial:DEVICE:BAUD"; "udpin:"/"tcpin:" are
  /// the Udp/Tcp forms with `listen`).
  mavlink::Transport transport = mavlink::Transport::Udp;
  std::string device{};  ///< serial: the device path (under /dev/)
  unsigned baud = 0;     ///< serial
};

/// The binding's link address (listen folded in: udpin/tcpin) and its text ("endpoint" in the JSON).
mavlink::LinkAddress link_address(const VehicleBinding& binding);
std::string endpoint_text(const VehicleBinding& binding);

struct FlightConfig {
  std::vector<VehicleBinding> vehicles;  ///< one per UAV of the plan that flies (idle UAVs may be left out)
  double link_timeout_s = 3.0;           ///< no message for this long: link lost (alert)
  double reassign_after_s = 10.0;        ///< link lost this long, or landed/aborted with coverage left: offer
  bool auto_reassign = false;            ///< apply offered reassignments without the operator
  bool auto_next_sortie = true;          ///< after a sortie lands (and the battery is swapped), fly the next
  double separation_m = 10.0;            ///< alert when two airborne UAVs are closer (3-D)
  double deviation_m = 15.0;             ///< alert when a UAV in coverage is further from its planned leg
  double low_battery_pct = 25.0;         ///< alert below this
  double log_period_s = 1.0;             ///< telemetry kept in the log at most this often per UAV
  double acceptance_radius_m = 2.0;      ///< Hong et al.: a waypoint is reached within this radius
  int command_retries = 3;               ///< COMMAND_LONG resends without COMMAND_ACK (1 s each)
  /// After each mission upload, the geofence and the rally points (issue 31) with their own mission
  /// types, where the vehicle's profile takes them (docs/fence-rally.md).
  bool fence_rally = true;
  /// Waypoint retries (Hong et al. 2021 §2.3; docs/flights.md, "Waypoint retries"): the current coverage
  /// waypoint not reached within max(waypoint_timeout_floor_s, waypoint_timeout_factor x the leg's flight
  /// time at the UAV's speed) is commanded again (MAV_CMD_DO_SET_MISSION_CURRENT); after this many retries
  /// without reaching it the UAV has failed (alert waypoint_failed, reassignment offered). 0: off.
  int waypoint_retries = 2;
  double waypoint_timeout_factor = 3.0;  ///< margin on the leg's flight time (wall clock)
  double waypoint_timeout_floor_s = 30.0;
  /// Where the helpers' reassigned work starts (docs/flights.md, "Reassignment"): "home" (their take-off
  /// points; flown after their current sortie lands) or "air" (a helper flying its own mission starts
  /// from its live position and is diverted to the work at once, its own rest resumed after it).
  std::string reassign_from = "home";
};

/// Parses and validates the "vehicles"/settings part of POST /plans/{id}/flights against the plan
/// (docs/flights.md): every vehicle names a UAV of the plan once, endpoints parse, numbers are in range.
/// Throws InputError naming the field ("vehicles[1].endpoint: ...").
FlightConfig parse_config(const nlohmann::json& body, const Plan& plan);
nlohmann::json config_json(const FlightConfig& config);

/// One line of the flight log (docs/flights.md): kind "telemetry" (downsampled), "waypoint" (a status
/// change), "command", "ack", "statustext", "alert", "sortie", "reassignment", "state".
struct LogRecord {
  std::int64_t t_ms = 0;  ///< Unix milliseconds (wall clock of the server)
  std::string uav;        ///< "" for flight-wide records
  std::string kind;
  nlohmann::json data = nlohmann::json::object();
};

/// Where a flight's records and changes go. Called from the flight's supervisor thread (and from stop()),
/// never under the flight's lock: implementations may call snapshot() but must not block for long, nor
/// call stop() or destroy the flight (that joins the calling thread). An exception thrown here is
/// swallowed: the flight goes on.
class Observer {
 public:
  virtual ~Observer() = default;
  /// Records to keep, in order. The flight does not retry: the observer persists them (the store).
  virtual void on_records(std::int64_t flight_id, const std::vector<LogRecord>& records) = 0;
  /// The snapshot changed (coalesced: at most every 100 ms).
  virtual void on_changed(std::int64_t flight_id) = 0;
};

/// An operator command (POST /flights/{id}/commands): "upload", "start", "pause", "continue", "rtl",
/// "land", "abort", "resume", "next_sortie", "reassign" (apply an offered reassignment; with
/// `reassignment` its id, with `reassign_from` where the helpers start), "decline" (refuse it). `uav` empty:
/// every UAV of the flight.
struct Command {
  std::string command;
  std::string uav;
  std::optional<int> reassignment;
  /// "reassign" only: "home" or "air" (FlightConfig::reassign_from); another choice than the offer's
  /// re-plans it from the helpers' positions now, then applies it.
  std::optional<std::string> reassign_from{};
};
/// Parses the command body; InputError naming "command", "uav", "reassignment" or "reassign_from".
Command parse_command(const nlohmann::json& body);

/// The command is not possible in the flight's current state (HTTP 409 with this message).
struct CommandRefused : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Flight {
 public:
  /// `plan` must have the UAVs the config names. `restored`: a snapshot() saved before a server restart;
  /// the flight continues from it (statuses, sortie queue, reassignments) and re-opens its links.
  Flight(std::int64_t id, Plan plan, FlightConfig config, Observer& observer,
         const std::optional<nlohmann::json>& restored = std::nullopt);
  ~Flight();  ///< stops the threads and closes the sockets (vehicles keep flying what they have)
  Flight(const Flight&) = delete;
  Flight& operator=(const Flight&) = delete;

  /// Opens the links and starts following telemetry. InputError naming "vehicles[i].endpoint" when a
  /// socket cannot be bound.
  void start();
  /// Stops following (idempotent).
  void stop();

  /// Validates the command against the current state (CommandRefused, InputError for an unknown UAV)
  /// and queues it; returns at once. Its progress and outcome show in the snapshot and the log.
  void command(const Command& command);

  [[nodiscard]] std::int64_t id() const;
  /// "created", "uploading", "ready", "flying", "paused", "done", "aborted" (docs/flights.md).
  [[nodiscard]] std::string state() const;
  /// True once the flight ended (done or aborted): nothing more will change.
  [[nodiscard]] bool finished() const;
  /// The flight as docs/flights.md's Flight object (without "id", "plan_id" and times, which the server
  /// adds), with the fields a restore needs ("Snapshot fields for restore"). Thread-safe.
  [[nodiscard]] nlohmann::json snapshot() const;
  /// Each UAV's flown track so far in WGS84 with altitudes (metres above take-off), for flown coverage.
  [[nodiscard]] std::vector<std::pair<std::string, std::vector<std::array<double, 3>>>> tracks() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uavcover::flight
