#include "mavlink/mission_protocol.hpp"

#include <cmath>
#include <thread>

namespace uavcover::mavlink {

namespace {

using clock = std::chrono::steady_clock;

bool is_global_frame(std::uint8_t frame) {
  switch (frame) {
    case 0:
    case 3:
    case 5:
    case 6:
    case 10:
    case 11:
      return true;
    default:
      return false;
  }
}

std::int32_t scaled(double degrees) { return static_cast<std::int32_t>(std::llround(degrees * 1e7)); }

std::chrono::milliseconds until(clock::time_point t) {
  const auto d = std::chrono::duration_cast<std::chrono::milliseconds>(t - clock::now());
  return d.count() < 0 ? std::chrono::milliseconds(0) : d;
}

// A message addressed to `sysid` (0 = broadcast)?
bool for_me(std::uint8_t target_system, std::uint8_t sysid) {
  return target_system == 0 || target_system == sysid;
}

}  // namespace

MissionItemInt to_mission_item_int(const waypoints::MissionItem& item, std::uint16_t seq) {
  MissionItemInt m;
  m.seq = seq;
  m.frame = item.frame;
  m.command = item.command;
  m.current = 0;
  m.autocontinue = item.autocontinue ? 1 : 0;
  m.param1 = item.param1;
  m.param2 = item.param2;
  m.param3 = item.param3;
  m.param4 = item.param4;
  if (is_global_frame(item.frame)) {
    m.x = scaled(item.lat);
    m.y = scaled(item.lon);
  } else {
    m.x = static_cast<std::int32_t>(std::llround(item.lat));
    m.y = static_cast<std::int32_t>(std::llround(item.lon));
  }
  m.z = item.alt;
  return m;
}

std::vector<MissionItemInt> to_mission_items(const std::vector<waypoints::MissionItem>& items,
                                             const std::optional<LonLat>& home) {
  std::vector<MissionItemInt> out;
  out.reserve(items.size() + 1);
  if (home) {
    MissionItemInt h;
    h.frame = 0;  // MAV_FRAME_GLOBAL
    h.command = waypoints::kNavWaypoint;
    h.x = scaled(home->lat);
    h.y = scaled(home->lon);
    h.z = 0.0F;
    out.push_back(h);
  }
  for (const auto& it : items) out.push_back(to_mission_item_int(it, static_cast<std::uint16_t>(out.size())));
  return out;
}

UploadResult upload_mission(Link& link, std::vector<MissionItemInt> items, const UploadOptions& options,
                            const UploadProgressFn& progress) {
  UploadResult res;
  const auto t0 = clock::now();
  bool heard = false;  // the vehicle answered this transfer: it may hold part of it
  auto finish = [&](bool ok, std::string error) {
    res.ok = ok;
    res.error = std::move(error);
    if (!ok && heard) {
      res.clear_sent = true;
      res.cleared = clear_mission(link, options);
      res.error += res.cleared ? "; the vehicle's mission was cleared (MISSION_CLEAR_ALL acknowledged)"
                               : "; WARNING: MISSION_CLEAR_ALL was not acknowledged: the vehicle may hold a "
                                 "partial mission";
    }
    res.elapsed_s = std::chrono::duration<double>(clock::now() - t0).count();
    return res;
  };
  if (items.size() > 65535)
    return finish(false, "too many mission items (" + std::to_string(items.size()) + ")");
  if (!link.has_peer()) return finish(false, "no vehicle address");
  const auto count = static_cast<std::uint16_t>(items.size());
  res.count = count;
  for (std::size_t i = 0; i < items.size(); ++i) {
    items[i].seq = static_cast<std::uint16_t>(i);
    items[i].target_system = options.target_system;
    items[i].target_component = options.target_component;
    items[i].mission_type = options.mission_type;
  }
  const int retries = std::max(0, options.retries);
  const auto hard_deadline = t0 + options.timeout * (retries + 1) * (static_cast<long>(count) + 2);

  Heartbeat hb;
  hb.type = 6;       // MAV_TYPE_GCS
  hb.autopilot = 8;  // MAV_AUTOPILOT_INVALID
  hb.system_status = 4;
  link.send(hb);

  MissionCount mc;
  mc.target_system = options.target_system;
  mc.target_component = options.target_component;
  mc.count = count;
  mc.mission_type = options.mission_type;
  link.send(mc);
  ++res.count_sent;

  std::vector<bool> served(count, false);
  std::optional<std::uint16_t> last_served;
  std::uint16_t next_new = 0;  // lowest item never requested
  int consecutive_timeouts = 0;
  auto timeout_at = clock::now() + options.timeout;

  while (true) {
    if (clock::now() >= hard_deadline) return finish(false, "gave up: the upload took too long");
    if (options.stop.stop_requested()) return finish(false, "stopped");
    // waits in short slices when it can be stopped
    const auto wake = std::min(timeout_at, hard_deadline);
    auto r = link.receive(until(
        options.stop.stop_possible() ? std::min(wake, clock::now() + std::chrono::milliseconds(100)) : wake));
    if (!r) {
      if (clock::now() < timeout_at) continue;
      ++res.timeouts;
      if (++consecutive_timeouts > retries)
        return finish(false, "no answer from the vehicle after " + std::to_string(retries) + " retries (" +
                                 (last_served ? "waiting for the next request or the ack"
                                              : "waiting for the first request") +
                                 ")");
      if (!last_served) {
        link.send(mc);  // the count or the first request was lost
        ++res.count_sent;
      } else {
        link.send(items[*last_served]);  // the item, the next request or the ack was lost
        ++res.items_sent;
      }
      timeout_at = clock::now() + options.timeout;
      continue;
    }
    if (options.target_system != 0 && r->header.sysid != options.target_system) continue;
    // MISSION_REQUEST_INT, or the deprecated MISSION_REQUEST answered the same way (with MISSION_ITEM_INT)
    std::optional<MissionRequestInt> request;
    if (const auto* ri = std::get_if<MissionRequestInt>(&r->message)) request = *ri;
    if (const auto* rf = std::get_if<MissionRequest>(&r->message))
      request = MissionRequestInt{rf->target_system, rf->target_component, rf->seq, rf->mission_type};
    if (request) {
      const MissionRequestInt* req = &*request;
      if (!for_me(req->target_system, link.sysid()) || req->mission_type != options.mission_type) continue;
      heard = true;
      if (req->seq >= count)
        return finish(false, "the vehicle requested item " + std::to_string(req->seq) + " of a " +
                                 std::to_string(count) + "-item mission");
      if (req->seq != next_new) ++res.out_of_order;
      link.send(items[req->seq]);
      ++res.items_sent;
      if (!served[req->seq]) {
        served[req->seq] = true;
        ++res.unique_items;
        while (next_new < count && served[next_new]) ++next_new;
        if (progress) progress(res.unique_items, count);
      }
      last_served = req->seq;
      consecutive_timeouts = 0;
      timeout_at = clock::now() + options.timeout;
    } else if (const auto* ack = std::get_if<MissionAck>(&r->message)) {
      if (!for_me(ack->target_system, link.sysid()) || ack->mission_type != options.mission_type) continue;
      // An acceptance before anything was requested belongs to an earlier transfer (a repeated ack).
      if (ack->type == kMissionAccepted && count > 0 && !last_served) continue;
      heard = true;
      res.ack = ack->type;
      if (ack->type != kMissionAccepted)
        return finish(false,
                      "the vehicle refused the mission: " + std::string(mission_result_name(ack->type)));
      if (res.unique_items != count)
        return finish(false, "the vehicle accepted after requesting only " +
                                 std::to_string(res.unique_items) + " of " + std::to_string(count) +
                                 " items");
      return finish(true, "");
    }
  }
}

bool clear_mission(Link& link, const UploadOptions& options) {
  MissionClearAll clear;
  clear.target_system = options.target_system;
  clear.target_component = options.target_component;
  clear.mission_type = options.mission_type;
  const int retries = std::max(0, options.retries);
  for (int attempt = 0; attempt <= retries; ++attempt) {
    link.send(clear);
    const auto timeout_at = clock::now() + options.timeout;
    while (clock::now() < timeout_at) {
      auto r = link.receive(until(timeout_at));
      if (!r) break;
      if (options.target_system != 0 && r->header.sysid != options.target_system) continue;
      const auto* ack = std::get_if<MissionAck>(&r->message);
      // only an acceptance answers the clear (a repeated refusal of the upload does not)
      if (ack && for_me(ack->target_system, link.sysid()) && ack->mission_type == options.mission_type &&
          ack->type == kMissionAccepted)
        return true;
    }
  }
  return false;
}

ProgressLog monitor_progress(Link& link, std::uint8_t target_system, std::uint16_t last_seq,
                             std::chrono::milliseconds idle_timeout) {
  ProgressLog log;
  while (true) {
    auto r = link.receive(idle_timeout);
    if (!r) return log;
    if (target_system != 0 && r->header.sysid != target_system) continue;
    if (const auto* cur = std::get_if<MissionCurrent>(&r->message)) {
      if (log.current.empty() || log.current.back() != cur->seq) log.current.push_back(cur->seq);
    } else if (const auto* reached = std::get_if<MissionItemReached>(&r->message)) {
      log.reached.push_back(reached->seq);
      if (reached->seq == last_seq) return log;
    }
  }
}

Vehicle::Vehicle(Link& link, VehicleOptions options) : link_(link), opt_(options) { link_.learn_peer(true); }

void Vehicle::request(std::uint16_t seq) {
  MissionRequestInt req;
  req.target_system = gcs_system_;
  req.target_component = gcs_component_;
  req.seq = seq;
  req.mission_type = type_;
  link_.send(req);
  ++stats_.requests_sent;
  deadline_ = clock::now() + opt_.item_timeout;
}

void Vehicle::ack(std::uint8_t type, std::uint8_t target_system, std::uint8_t target_component) {
  MissionAck a;
  a.target_system = target_system;
  a.target_component = target_component;
  a.type = type;
  a.mission_type = type_;
  link_.send(a);
}

void Vehicle::end_transfer() {
  receiving_ = false;
  incoming_.clear();
  // what was stored so far is the mission now
  if (type_ == kMissionTypeMission && opt_.store_as_received) ++mission_version_;
}

void Vehicle::on_timeout() {
  if (!receiving_ || clock::now() < deadline_) return;
  if (retries_left_-- > 0) {
    ++stats_.rerequests;
    request(expected_);
    return;
  }
  end_transfer();  // give up (without store_as_received the stored mission is unchanged)
  ++stats_.cancelled;
  ack(kMissionOperationCancelled, gcs_system_, gcs_component_);
}

bool Vehicle::handle(const Received& r) {
  if (const auto* mc = std::get_if<MissionCount>(&r.message)) {
    if (!for_me(mc->target_system, link_.sysid())) return true;
    gcs_system_ = r.header.sysid;
    gcs_component_ = r.header.compid;
    if (receiving_ && mc->mission_type != type_) {  // one transfer at a time: the other one is dropped
      end_transfer();
      ++stats_.cancelled;
    }
    type_ = mc->mission_type;
    const bool fence_or_rally = type_ == kMissionTypeFence || type_ == kMissionTypeRally;
    if (type_ != kMissionTypeMission && !(fence_or_rally && opt_.fence_rally)) {
      ack(kMissionUnsupported, gcs_system_, gcs_component_);
      return true;
    }
    const std::size_t capacity = type_ == kMissionTypeFence   ? opt_.max_fence_items
                                 : type_ == kMissionTypeRally ? opt_.max_rally_items
                                                              : opt_.max_items;
    if (mc->count > capacity) {
      ack(kMissionNoSpace, gcs_system_, gcs_component_);
      return true;
    }
    if (mc->count == 0) {  // an empty upload clears the mission (or the fence, the rally points)
      receiving_ = false;
      last_completed_count_ = 0;
      if (type_ == kMissionTypeMission) {
        mission_.clear();
        ++stats_.uploads_accepted;
        ++mission_version_;
      } else if (type_ == kMissionTypeFence) {
        fence_.clear();
        ++fence_version_;
        ++stats_.fence_uploads;
      } else {
        rally_.clear();
        ++stats_.rally_uploads;
      }
      ack(kMissionAccepted, gcs_system_, gcs_component_);
      return true;
    }
    receiving_ = true;  // a new count (also a resent one) (re)starts the transfer
    count_ = mc->count;
    if (type_ == kMissionTypeMission && opt_.store_as_received && mission_.size() > count_)
      mission_.resize(count_);  // ArduPilot truncates
    expected_ = 0;
    incoming_.clear();
    retries_left_ = opt_.retries;
    last_completed_count_.reset();
    request(0);
  } else if (const auto* item = std::get_if<MissionItemInt>(&r.message)) {
    if (!for_me(item->target_system, link_.sysid())) return true;
    if (receiving_ && item->mission_type != type_) return true;  // not the transfer in progress
    if (!receiving_) {
      // The GCS repeats the final item when our ACK was lost: repeat the ACK.
      if (last_completed_count_ && *last_completed_count_ > 0 && item->seq + 1 == *last_completed_count_) {
        ++stats_.acks_resent;
        ack(kMissionAccepted, r.header.sysid, r.header.compid);
      }
      return true;
    }
    if (item->seq < expected_) {  // a late duplicate (we re-requested too early): drop it
      ++stats_.duplicates;
      return true;
    }
    if (item->seq != expected_) {  // out of sequence: drop it and ask again for the expected one
      ++stats_.out_of_sequence;
      ++stats_.rerequests;
      request(expected_);
      return true;
    }
    std::uint8_t verdict = kMissionAccepted;
    if (type_ == kMissionTypeFence) {  // fence and rally: their own commands only (MAV_CMD_NAV_FENCE_*
      // 5001-5004, MAV_CMD_NAV_RALLY_POINT 5100)
      if (item->command < 5001 || item->command > 5004) verdict = kMissionUnsupported;
    } else if (type_ == kMissionTypeRally) {
      if (item->command != 5100) verdict = kMissionUnsupported;
    } else if (opt_.refuse_item && item->seq == *opt_.refuse_item) {
      verdict = opt_.refuse_result;
    } else if (opt_.check_item) {
      verdict = opt_.check_item(*item);
    }
    if (verdict != kMissionAccepted && type_ != kMissionTypeMission) {  // the stored one stays
      ++stats_.refused;
      receiving_ = false;
      incoming_.clear();
      ack(verdict, gcs_system_, gcs_component_);
      return true;
    }
    if (verdict != kMissionAccepted) {
      ++stats_.refused;
      if (opt_.store_as_received) {
        end_transfer();  // what was stored as it came stays
      } else {           // the items before the refused one stay stored (ArduPilot)
        mission_ = std::move(incoming_);
        incoming_.clear();
        receiving_ = false;
        ++mission_version_;
      }
      ack(verdict, gcs_system_, gcs_component_);
      return true;
    }
    incoming_.push_back(*item);
    if (type_ == kMissionTypeMission && opt_.store_as_received) {  // ArduPilot writes each as it arrives
      if (item->seq < mission_.size())
        mission_[item->seq] = *item;
      else
        mission_.push_back(*item);
    }
    ++expected_;
    retries_left_ = opt_.retries;
    if (expected_ == count_) {
      receiving_ = false;
      if (type_ == kMissionTypeFence && opt_.check_fence) {
        if (const std::uint8_t v = opt_.check_fence(incoming_); v != kMissionAccepted) {
          ++stats_.refused;
          incoming_.clear();
          ack(v, gcs_system_, gcs_component_);
          return true;
        }
      }
      last_completed_count_ = count_;
      if (type_ == kMissionTypeFence) {
        fence_ = std::move(incoming_);
        ++fence_version_;
        ++stats_.fence_uploads;
      } else if (type_ == kMissionTypeRally) {
        rally_ = std::move(incoming_);
        ++stats_.rally_uploads;
      } else {
        mission_ = std::move(incoming_);
        ++stats_.uploads_accepted;
        ++mission_version_;
      }
      incoming_.clear();
      ack(kMissionAccepted, gcs_system_, gcs_component_);
    } else {
      request(expected_);
    }
  } else if (const auto* clear = std::get_if<MissionClearAll>(&r.message)) {
    if (!for_me(clear->target_system, link_.sysid())) return true;
    // MAV_MISSION_TYPE_ALL (255) clears all three
    const std::uint8_t t = clear->mission_type;
    if (t != kMissionTypeMission && t != 255 &&
        !((t == kMissionTypeFence || t == kMissionTypeRally) && opt_.fence_rally)) {
      type_ = t;
      ack(kMissionUnsupported, r.header.sysid, r.header.compid);
      return true;
    }
    if (t == kMissionTypeMission || t == 255) {
      mission_.clear();
      ++mission_version_;
    }
    if (t == kMissionTypeFence || t == 255) {
      fence_.clear();
      ++fence_version_;
    }
    if (t == kMissionTypeRally || t == 255) rally_.clear();
    receiving_ = false;
    ++stats_.clears;
    type_ = t;
    ack(kMissionAccepted, r.header.sysid, r.header.compid);
  } else {
    return false;
  }
  return true;
}

void Vehicle::run(std::chrono::milliseconds limit, const std::atomic<bool>* stop, bool until_accepted) {
  const auto end = clock::now() + limit;
  const std::size_t accepted_before = stats_.uploads_accepted;
  while (clock::now() < end) {
    if (stop && stop->load()) return;
    if (until_accepted && stats_.uploads_accepted > accepted_before) return;
    const auto now = clock::now();
    if (now >= next_heartbeat_ && link_.has_peer()) {
      Heartbeat hb;
      hb.type = 2;       // MAV_TYPE_QUADROTOR
      hb.autopilot = 3;  // MAV_AUTOPILOT_ARDUPILOTMEGA
      hb.system_status = 3;
      link_.send(hb);
      next_heartbeat_ = now + opt_.heartbeat_period;
    }
    auto wait = std::min(until(end), std::chrono::milliseconds(50));
    if (receiving_) wait = std::min(wait, until(deadline_));
    if (auto r = link_.receive(wait)) handle(*r);
    on_timeout();
  }
}

void Vehicle::fly(std::uint16_t first_seq, std::chrono::milliseconds per_item) {
  const auto total = static_cast<std::uint16_t>(mission_.size());
  for (std::uint16_t seq = first_seq; seq < total; ++seq) {
    MissionCurrent cur;
    cur.seq = seq;
    cur.total = total;
    cur.mission_state = 3;  // MISSION_STATE_ACTIVE
    link_.send(cur);
    std::this_thread::sleep_for(per_item);
    link_.send(MissionItemReached{seq});
  }
  MissionCurrent done;
  done.seq = total == 0 ? 0 : static_cast<std::uint16_t>(total - 1);
  done.total = total;
  done.mission_state = 5;  // MISSION_STATE_COMPLETE
  link_.send(done);
}

}  // namespace uavcover::mavlink
