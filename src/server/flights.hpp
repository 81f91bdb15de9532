// The server's side of flights (docs/flights.md): FlightManager owns the live flight::Flight objects
// (and the simulated fleets it starts for them), implements flight::Observer by writing the flight log
// and the flight's snapshot to the store from its own writer thread (batched, never on the HTTP threads),
// and re-attaches the flights that were not done or aborted when the server starts.
#pragma once

#include <array>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "flight/flight.hpp"
#include "server/terrain_source.hpp"
#include "store/store.hpp"
#include "uavcover/plan.hpp"

namespace uavcover::server {

struct FlightLimits {
  std::size_t max_live = 16;      ///< flights followed at once (409 beyond)
  std::size_t max_vehicles = 64;  ///< vehicles per flight (422 beyond)
  bool allow_remote = false;      ///< endpoints other than loopback (only when the server has a token)
  std::chrono::milliseconds flush_period{200};      ///< the writer's period
  std::chrono::milliseconds snapshot_period{1000};  ///< a changed snapshot is stored at most this often
  DemDir dem_dir = {};                              ///< `serve --dem-dir` (issue 31): a terrain plan's ground
};

/// Each UAV's flown track in WGS84 with altitudes (flight::Flight::tracks()).
using Tracks = std::vector<std::pair<std::string, std::vector<std::array<double, 3>>>>;

/// The plan of a done plan job, from its plan.json and paths.geojson artifacts.
/// A done plan job's plan, with its ground heights when its mission follows terrain (issue 31).
Plan load_job_plan(store::Store& store, const store::Job& job, const DemDir& dem_dir = {});

/// The Flight object of docs/flights.md: the snapshot with the stored flight's id, plan, mission, times,
/// config and state.
nlohmann::json flight_json(const store::StoredFlight& row, const nlohmann::json& snapshot);

class FlightManager final : public flight::Observer {
 public:
  explicit FlightManager(store::Store& store, FlightLimits limits = {});
  ~FlightManager() override;
  FlightManager(const FlightManager&) = delete;
  FlightManager& operator=(const FlightManager&) = delete;

  /// Re-attaches the stored flights that are not done or aborted (from their snapshots; a simulated one
  /// ends aborted: its fleet ended with the server that ran it) and starts the writer.
  void start();
  /// Stops following every flight (the vehicles keep flying what they have), stops the simulated
  /// fleets and writes what is pending. Idempotent.
  void stop();

  /// POST /plans/{id}/flights: validates the FlightRequest (InputError naming the field), starts the
  /// simulated fleet when asked, stores the flight, opens its links. HttpError 409 when max_live flights
  /// are followed already.
  nlohmann::json create(const store::Job& plan_job, const nlohmann::json& body);
  /// The Flight JSON: live from memory when this server follows it, else as stored. Empty when unknown.
  std::optional<nlohmann::json> get(store::Id id);
  /// Several flights' JSON (the events); unknown ids are left out.
  std::vector<nlohmann::json> get_many(const std::vector<store::Id>& ids);
  /// Queues a command (flight::parse_command; CommandRefused -> HttpError 409). NotFound.
  nlohmann::json command(store::Id id, const nlohmann::json& body);
  /// DELETE: a followed flight stops being followed and ends aborted; one that is done or aborted already
  /// is deleted with its log. Returns the flight as it was last. NotFound.
  nlohmann::json remove(store::Id id);
  /// Each UAV's flown track: live, or rebuilt from the log's telemetry. NotFound.
  Tracks tracks(store::Id id);
  /// Flown coverage (flight::flown_coverage over tracks()): {"flown_poc", "planned_poc", "flown_pooc",
  /// "bounds": [[s, w], [n, e]], "updated"} and the overlay PNG. Computed at most every few seconds per
  /// flight (cached). NotFound.
  struct Coverage {
    nlohmann::json summary;
    std::string png;
  };
  std::shared_ptr<const Coverage> coverage(store::Id id);
  /// Writes every pending record and changed snapshot now (stop, tests).
  void flush();
  [[nodiscard]] std::size_t live_count() const;

  // flight::Observer (called from the flights' threads)
  void on_records(std::int64_t flight_id, const std::vector<flight::LogRecord>& records) override;
  void on_changed(std::int64_t flight_id) override;

 private:
  struct Live;
  std::shared_ptr<Live> find(store::Id id) const;
  void attach(const store::StoredFlight& row, const std::optional<nlohmann::json>& restored);
  void writer_loop();
  void write_pending();
  void retire(const std::shared_ptr<Live>& live, const std::string& state, const std::string& reason);

  store::Store& store_;
  FlightLimits limits_;
  mutable std::mutex mutex_;  ///< live_
  std::mutex create_mutex_;   ///< create(): the max_live check and the new flight's insert as one step
  std::map<store::Id, std::shared_ptr<Live>> live_;
  std::mutex queue_mutex_;  ///< pending_, changed_, stopping_
  std::condition_variable wake_;
  std::map<store::Id, std::vector<store::FlightLogRecord>> pending_;
  std::set<store::Id> changed_;
  bool stopping_ = false;
  std::mutex write_mutex_;  ///< one write_pending() at a time
  std::mutex coverage_mutex_;
  std::map<store::Id, std::pair<std::chrono::steady_clock::time_point, std::shared_ptr<const Coverage>>>
      coverage_cache_;
  std::thread writer_;
};

}  // namespace uavcover::server
