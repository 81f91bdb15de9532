// The MAVLink mission upload protocol over any Link (UDP, TCP, serial), both ends:
//  - upload_mission(): the GCS side. MISSION_COUNT -> vehicle MISSION_REQUEST_INT(i) -> MISSION_ITEM_INT(i)
//    -> ... -> MISSION_ACK. Requests are served in whatever order and as often as they come. An upload
//    that fails after the vehicle answered (an item refused, a timeout midway) is followed by
//    MISSION_CLEAR_ALL, so no partial mission stays behind; the result says whether the clear was acked.
//  - Vehicle: receives a mission (requests items in order, re-requests on timeout or out-of-sequence
//    items, acks), answers MISSION_CLEAR_ALL, and "flies" a stored mission by broadcasting
//    MISSION_CURRENT / MISSION_ITEM_REACHED, for tests and the simulated fleet.
// Timeouts and retries follow the MAVLink mission protocol guide: 1500 ms default timeout, 250 ms for
// mission items, at most 5 retries.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <stop_token>
#include <string>
#include <vector>

#include "mavlink/link.hpp"
#include "mavlink/messages.hpp"
#include "mavlink/udp.hpp"
#include "uavcover/geometry.hpp"
#include "waypoints/waypoints.hpp"

namespace uavcover::mavlink {

inline constexpr std::chrono::milliseconds kDefaultTimeout{1500};
inline constexpr std::chrono::milliseconds kItemTimeout{250};
inline constexpr int kMaxRetries = 5;

/// MISSION_ITEM_INT for one exported item: lat/lon * 1e7 (rounded) in global frames, as-is otherwise.
MissionItemInt to_mission_item_int(const waypoints::MissionItem& item, std::uint16_t seq);

/// The items to upload. With `home` (ArduPilot: seq 0 is the home position) a MAV_CMD_NAV_WAYPOINT at
/// the home position (frame MAV_FRAME_GLOBAL, altitude 0) is item 0 and the mission follows from seq 1.
std::vector<MissionItemInt> to_mission_items(const std::vector<waypoints::MissionItem>& items,
                                             const std::optional<LonLat>& home);

struct UploadOptions {
  std::chrono::milliseconds timeout = kDefaultTimeout;  ///< wait for the vehicle's next message
  int retries = kMaxRetries;                            ///< resends after a timeout before giving up
  std::uint8_t target_system = 1;
  std::uint8_t target_component = 1;
  std::uint8_t mission_type = kMissionTypeMission;
  /// A stop ends the upload within about 100 ms (ok false, error "stopped"), e.g. a flight deleted
  /// while its vehicle is silent; without it the retries take up to (retries + 1) * timeout.
  std::stop_token stop;
};

struct UploadResult {
  bool ok = false;
  std::optional<std::uint8_t> ack;  ///< MISSION_ACK.type received, if any
  std::string error;                ///< why it failed (empty when ok)
  std::size_t count = 0;            ///< items in the mission
  std::size_t unique_items = 0;     ///< distinct items the vehicle requested
  std::size_t items_sent = 0;       ///< MISSION_ITEM_INT sent, repeats included
  std::size_t count_sent = 0;       ///< MISSION_COUNT sent, resends included
  std::size_t timeouts = 0;
  std::size_t out_of_order = 0;  ///< requests for anything but the next new item
  double elapsed_s = 0.0;
  /// After a failure: MISSION_CLEAR_ALL was sent (the vehicle had answered, so it may hold part of the
  /// upload: ArduPilot stores items as they arrive, issue 34).
  bool clear_sent = false;
  /// ... and the vehicle acknowledged it (MISSION_ACK accepted): it holds no mission.
  bool cleared = false;
  /// After a failure: the vehicle may hold a partial mission (the clear was not acknowledged).
  [[nodiscard]] bool partial_possible() const { return !ok && clear_sent && !cleared; }
};

/// Called after each item sent: (distinct items requested so far, total).
using UploadProgressFn = std::function<void(std::size_t done, std::size_t total)>;

/// Uploads `items` (their seq fields are overwritten with their index) to the vehicle at the link's
/// peer. Bounded: gives up after `retries` consecutive timeouts, and after at most
/// (retries + 1) * timeout * (count + 2) in total. On a failure after the vehicle answered, sends
/// MISSION_CLEAR_ALL (clear_mission()) and appends its outcome to `error`: "the vehicle's mission was
/// cleared", or "WARNING: the vehicle may hold a partial mission" when the clear was not acknowledged.
UploadResult upload_mission(Link& link, std::vector<MissionItemInt> items, const UploadOptions& options,
                            const UploadProgressFn& progress = {});

/// Watches a flying vehicle: collects MISSION_ITEM_REACHED seqs (in arrival order) until `last_seq` is
/// reached or nothing arrives for `idle_timeout`.
struct ProgressLog {
  std::vector<std::uint16_t> reached;
  std::vector<std::uint16_t> current;  ///< MISSION_CURRENT seqs as they changed
};
/// Sends MISSION_CLEAR_ALL and waits for the vehicle's accepting MISSION_ACK, resending after each
/// `timeout` up to `retries` times. True when acknowledged.
bool clear_mission(Link& link, const UploadOptions& options);

ProgressLog monitor_progress(Link& link, std::uint8_t target_system, std::uint16_t last_seq,
                             std::chrono::milliseconds idle_timeout);

struct VehicleOptions {
  std::chrono::milliseconds item_timeout = kItemTimeout;
  int retries = kMaxRetries;
  std::size_t max_items = 700;  ///< answers MAV_MISSION_NO_SPACE above this
  std::chrono::milliseconds heartbeat_period{1000};
  /// ArduPilot-like storage: each item is written as it arrives (issue 34: a refusal at item 3 left a
  /// 3-item mission) and MISSION_COUNT truncates the stored mission to the count (assumed, not checked
  /// in ArduPilot's source), so a transfer refused or abandoned midway leaves a truncated or mixed
  /// mission. Off: the stored mission changes only when an upload completes, except after an item
  /// `check_item` or `refuse_item` refuses: then it is the items received before the refused one.
  bool store_as_received = false;
  /// Tests: refuse the item with this seq with MISSION_ACK `refuse_result` (the transfer ends).
  std::optional<std::uint16_t> refuse_item;
  std::uint8_t refuse_result = 8;  // MAV_MISSION_INVALID_PARAM3
  /// The autopilot's verdict on each item as it arrives (MAV_MISSION_RESULT; empty = accept every item).
  /// An item it refuses ends the transfer with that MISSION_ACK, and the stored mission becomes the items
  /// received before it, as ArduPilot keeps them (it stores each item as it comes; issue 34 saw a 3-item
  /// mission left after a refusal at item 3). The simulator uses autopilot::ardupilot_item_result.
  std::function<std::uint8_t(const MissionItemInt&)> check_item;
  /// Fence and rally points (MAV_MISSION_TYPE_FENCE, _RALLY; issue 31): stored apart from the mission,
  /// each replaced only when its upload completes. Off: both types are answered MAV_MISSION_UNSUPPORTED.
  bool fence_rally = true;
  std::size_t max_fence_items = 256;  ///< MAV_MISSION_NO_SPACE above this
  std::size_t max_rally_items = 100;
  /// The autopilot's verdict on a whole fence once every item has arrived (MAV_MISSION_RESULT; empty =
  /// accept): a refused fence leaves the stored one unchanged. The simulator uses autopilot::read_fence.
  std::function<std::uint8_t(const std::vector<MissionItemInt>&)> check_fence;
};

class Vehicle {
 public:
  struct Stats {
    std::size_t uploads_accepted = 0;
    std::size_t requests_sent = 0;
    std::size_t rerequests = 0;       ///< after a timeout or an out-of-sequence item
    std::size_t out_of_sequence = 0;  ///< items ahead of the expected one: dropped, expected re-requested
    std::size_t duplicates = 0;       ///< items already received: dropped (the expected one is requested)
    std::size_t cancelled = 0;        ///< transfers abandoned after the retries
    std::size_t acks_resent = 0;      ///< final item seen again after the ACK: ACK repeated
    std::size_t refused = 0;          ///< transfers ended by refusing an item (check_item, refuse_item)
    std::size_t clears = 0;           ///< MISSION_CLEAR_ALL handled
    std::size_t fence_uploads = 0;    ///< fence uploads accepted (issue 31)
    std::size_t rally_uploads = 0;    ///< rally uploads accepted
  };

  /// The link's sysid/compid are the vehicle's; replies go to whoever sent last.
  Vehicle(Link& link, VehicleOptions options = {});

  /// Handles messages and timeouts for at most `limit`, or until `stop` becomes true, or (when
  /// `until_accepted`) until an upload completes.
  void run(std::chrono::milliseconds limit, const std::atomic<bool>* stop = nullptr,
           bool until_accepted = false);

  /// Flies the stored mission from `first_seq`: for each item, MISSION_CURRENT(seq) then, after
  /// `per_item`, MISSION_ITEM_REACHED(seq); finally MISSION_CURRENT with mission_state COMPLETE.
  void fly(std::uint16_t first_seq, std::chrono::milliseconds per_item);

  /// For an owner that runs its own event loop (the simulated fleet polls many links at once):
  /// handles one received message; true when it was a mission-protocol message (MISSION_COUNT,
  /// MISSION_ITEM_INT, MISSION_CLEAR_ALL), false for anything else (left to the caller).
  bool handle(const Received& r);
  /// Re-requests the expected item (or cancels the transfer) when its timeout has passed; call it
  /// regularly, at least every item_timeout, while a transfer is in progress.
  void on_timeout();
  /// A transfer is in progress (the stored mission is still the previous one).
  [[nodiscard]] bool receiving() const { return receiving_; }

  [[nodiscard]] const std::vector<MissionItemInt>& mission() const { return mission_; }
  /// The stored fence and rally items (issue 31).
  [[nodiscard]] const std::vector<MissionItemInt>& fence() const { return fence_; }
  [[nodiscard]] const std::vector<MissionItemInt>& rally() const { return rally_; }
  /// Counts every change of the stored fence.
  [[nodiscard]] std::size_t fence_version() const { return fence_version_; }
  [[nodiscard]] const Stats& stats() const { return stats_; }
  /// Counts every change of the stored mission (accepted uploads and clears).
  [[nodiscard]] std::size_t mission_version() const { return mission_version_; }

 private:
  using clock = std::chrono::steady_clock;
  void request(std::uint16_t seq);
  void end_transfer();  ///< a transfer refused or abandoned midway
  void ack(std::uint8_t type, std::uint8_t target_system, std::uint8_t target_component);

  Link& link_;
  VehicleOptions opt_;
  std::vector<MissionItemInt> mission_;
  std::vector<MissionItemInt> fence_, rally_;
  std::size_t fence_version_ = 0;
  // transfer in progress
  std::uint8_t type_ = kMissionTypeMission;  ///< its MAV_MISSION_TYPE
  bool receiving_ = false;
  std::uint16_t count_ = 0;
  std::uint16_t expected_ = 0;
  std::vector<MissionItemInt> incoming_;
  int retries_left_ = 0;
  clock::time_point deadline_{};
  std::uint8_t gcs_system_ = 0, gcs_component_ = 0;
  // last completed upload (to repeat a lost ACK)
  std::optional<std::uint16_t> last_completed_count_;
  clock::time_point next_heartbeat_{};
  Stats stats_;
  std::size_t mission_version_ = 0;
};

}  // namespace uavcover::mavlink
