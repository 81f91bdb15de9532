// The flight (docs/flights.md): missions per UAV, operator commands, the supervisor (link health,
// alerts, automatic next sortie, reassignment offers), the observer's records, snapshot and restore.
// The per-vehicle link threads are in link.cpp.
#include "flight/flight.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <map>

#include "evaluation/cost.hpp"
#include "flight/runtime.hpp"
#include "sorties/sorties.hpp"
#include "uavcover/error.hpp"

namespace uavcover::flight {

using namespace detail;
using namespace std::chrono_literals;
using nlohmann::json;
namespace mav = uavcover::mavlink;

std::int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

namespace {

bool airborne_phase(const std::string& p) { return p == "flying" || p == "paused" || p == "returning"; }

std::string iso_time(std::int64_t ms) {
  if (ms <= 0) return "";
  const std::time_t s = static_cast<std::time_t>(ms / 1000);
  std::tm tm{};
  gmtime_r(&s, &tm);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", tm.tm_year + 1900, tm.tm_mon + 1,
                     tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec, static_cast<int>(ms % 1000));
}

}  // namespace

// ---- construction: each UAV's missions ----

Flight::Impl::Impl(std::int64_t id_, Plan plan_, FlightConfig config_, Observer& observer_)
    : id(id_), plan(std::move(plan_)), config(std::move(config_)), observer(observer_), frame(plan.origin) {
  if (config.vehicles.empty()) throw InputError("vehicles", "needs at least one vehicle");
  for (std::size_t i = 0; i < config.vehicles.size(); ++i) {
    const auto& b = config.vehicles[i];
    const auto it =
        std::find_if(plan.uavs.begin(), plan.uavs.end(), [&](const UavPlan& u) { return u.id == b.uav; });
    if (it == plan.uavs.end()) throw InputError(fmt::format("vehicles[{}].uav", i), "not a UAV of the plan");
    for (std::size_t j = 0; j < i; ++j)
      if (config.vehicles[j].uav == b.uav)
        throw InputError(fmt::format("vehicles[{}].uav", i), "bound twice");
    UavRt u;
    u.index = static_cast<std::size_t>(it - plan.uavs.begin());
    u.binding = b;
    u.waypoints.assign(sorties::coverage_waypoints(*it).size(), 'P');
    u.missions = own_missions(u.index, -1);
    uavs.push_back(std::move(u));
  }
}

MissionSpec Flight::Impl::make_mission(std::size_t uav, std::vector<waypoints::MissionItem> items) const {
  MissionSpec m;
  m.items = std::move(items);
  const std::size_t n = m.items.size();
  m.where.resize(n);
  m.rest_m.assign(n + 1, 0.0);
  m.rest_turns.assign(n + 1, 0);
  const LonLat home = plan.mission.uavs[uav].start_resolved;
  for (std::size_t j = 0; j < n; ++j) {
    const auto& it = m.items[j];
    if (it.command == waypoints::kNavReturnToLaunch)
      m.where[j] = frame.to_local(home);
    else if (it.lat != 0 || it.lon != 0)
      m.where[j] = frame.to_local(LonLat{it.lon, it.lat});
  }
  std::optional<Point> next;
  for (std::size_t j = n; j-- > 0;) {
    m.rest_m[j] = m.rest_m[j + 1] + (m.where[j] && next ? bg::distance(*m.where[j], *next) : 0.0);
    m.rest_turns[j] = m.rest_turns[j + 1] + (m.items[j].waypoint >= 0 ? 1 : 0);
    if (m.where[j]) next = m.where[j];
  }
  return m;
}

std::vector<MissionSpec> Flight::Impl::own_missions(std::size_t uav, int from_waypoint) const {
  std::vector<MissionSpec> out;
  const int n = static_cast<int>(sorties::coverage_waypoints(plan.uavs[uav]).size());
  if (n == 0) return out;
  std::vector<Sortie> ss;
  std::vector<std::vector<waypoints::MissionItem>> items;
  try {
    ss = sorties::resume_sorties(plan, uav, from_waypoint);
    items = sorties::resume_items(plan, uav, from_waypoint);
  } catch (const InputError&) {
    if (from_waypoint >= 0) throw;
    // a leg that does not fit one battery: the plan has no sorties; fly it as one mission
    ss = {Sortie{0, 0, n - 1, {}, 0, 0, 0}};
    items = {waypoints::mission_items(plan, uav)};
  }
  for (std::size_t k = 0; k < ss.size() && k < items.size(); ++k) {
    MissionSpec m = make_mission(uav, std::move(items[k]));
    m.kind = from_waypoint < 0 ? "sortie" : "resume";
    m.index = ss[k].index;
    m.first_waypoint = ss[k].first_waypoint;
    m.last_waypoint = ss[k].last_waypoint;
    m.from_waypoint = from_waypoint;
    m.k = static_cast<int>(k);
    out.push_back(std::move(m));
  }
  return out;
}

// ---- records, alerts, phases ----

void Flight::Impl::record(const std::string& uav, const std::string& kind, json data) {
  dirty = true;
  if (pending.size() >= kPendingMax) {
    if (kind == "telemetry") return;  // the observer is behind: telemetry goes first
    const auto it = std::find_if(pending.begin(), pending.end(),
                                 [](const LogRecord& r) { return r.kind == "telemetry"; });
    if (it != pending.end())
      pending.erase(it);
    else
      pending.erase(pending.begin());
  }
  pending.push_back(LogRecord{now_ms(), uav, kind, std::move(data)});
}

void Flight::Impl::set_alert(const std::string& kind, const std::string& uav, const std::string& other,
                             bool active, const std::string& message) {
  auto it = std::find_if(alerts.begin(), alerts.end(), [&](const Alert& a) {
    return a.active && a.kind == kind && a.uav == uav && a.other == other;
  });
  if (active == (it != alerts.end())) return;
  if (active) {
    if (alerts.size() >= kAlertsMax) {
      const auto old = std::find_if(alerts.begin(), alerts.end(), [](const Alert& a) { return !a.active; });
      alerts.erase(old != alerts.end() ? old : alerts.begin());
    }
    alerts.push_back(Alert{kind, uav, other, message, now_ms(), true});
  } else {
    it->active = false;
  }
  json d{{"kind", kind}, {"active", active}, {"message", message}};
  if (!other.empty()) d["other"] = other;
  record(uav, "alert", std::move(d));
}

void Flight::Impl::set_phase(UavRt& u, const std::string& phase) {
  if (u.phase == phase) return;
  record(u.binding.uav, "state", {{"phase", phase}, {"from", u.phase}});
  u.phase = phase;
}

void Flight::Impl::queue_command(UavRt& u, const std::string& name, std::uint16_t command, float p1,
                                 float p2) {
  if (u.actions.size() >= kActionsMax)
    throw CommandRefused("too many commands queued for UAV " + u.binding.uav);
  Action a;
  a.kind = Action::Kind::Command;
  a.name = name;
  a.cmd.command = command;
  a.cmd.param1 = p1;
  a.cmd.param2 = p2;
  u.actions.push_back(std::move(a));
}

void Flight::Impl::queue_upload_and_start(UavRt& u) {
  if (u.current >= u.missions.size()) return;
  Action up;
  up.kind = Action::Kind::Upload;
  up.mission = u.current;
  up.name = "upload";
  u.actions.push_back(std::move(up));
  queue_command(u, "arm", mav::kCmdComponentArmDisarm, 1.0F);
  queue_command(u, "mission_start", mav::kCmdMissionStart);
  u.retry_after = Clock::now() + 2s;
}

void Flight::Impl::update_state() {
  std::string s;
  if (aborted) {
    s = "aborted";
  } else if (std::all_of(uavs.begin(), uavs.end(), [&](const UavRt& u) { return settled(u); })) {
    s = "done";
  } else if (started) {
    const bool any_flying = std::any_of(uavs.begin(), uavs.end(), [](const UavRt& u) {
      return u.phase == "flying" || u.phase == "returning";
    });
    const bool any_paused =
        std::any_of(uavs.begin(), uavs.end(), [](const UavRt& u) { return u.phase == "paused"; });
    s = !any_flying && any_paused ? "paused" : "flying";
  } else if (std::any_of(uavs.begin(), uavs.end(), [](const UavRt& u) { return u.phase == "uploading"; })) {
    s = "uploading";
  } else if (std::any_of(uavs.begin(), uavs.end(), [](const UavRt& u) { return u.phase == "ready"; })) {
    s = "ready";
  } else {
    s = "created";
  }
  if (s != state) {
    record("", "state", {{"state", s}, {"from", state}});
    state = s;
  }
}

// ---- supervision ----

void Flight::Impl::supervise_locked(Clock::time_point now) {
  const auto secs = [](double s) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
  };
  for (auto& u : uavs) {
    // link health (an upload reads the link itself: not judged meanwhile)
    if (u.phase != "uploading" && u.link_state != "lost" &&
        now - u.last_heard > secs(config.link_timeout_s)) {
      u.link_state = "lost";
      u.lost_since = now;
      set_alert("link_lost", u.binding.uav, "", true,
                fmt::format("no message for {} s", config.link_timeout_s));
    }
    const bool low = u.battery_pct && *u.battery_pct < config.low_battery_pct;
    if (low != u.low_battery) {
      u.low_battery = low;
      set_alert("low_battery", u.binding.uav, "", low,
                fmt::format("battery {:.0f}%", u.battery_pct.value_or(0)));
    }
    // a UAV lost for reassign_after_s with work left has failed
    if (u.link_state == "lost" && u.lost_since && now - *u.lost_since >= secs(config.reassign_after_s) &&
        u.phase != "failed" && has_work_left(u) && started) {
      if (u.current < u.missions.size() && u.missions[u.current].state == "flying")
        u.missions[u.current].state = "interrupted";
      u.actions.clear();
      u.command_active = false;
      set_phase(u, "failed");
    }
    // the automatic next sortie (and a start that failed on a lossy link, tried again)
    if (config.auto_next_sortie && started && !aborted && u.link_state == "ok" && u.actions.empty() &&
        !u.command_active && now >= u.retry_after && !u.interrupted && u.current < u.missions.size()) {
      const auto& st = u.missions[u.current].state;
      if ((u.phase == "landed" || u.phase == "done" || u.phase == "idle") && st == "pending") {
        queue_upload_and_start(u);
      } else if (u.phase == "ready" && st == "ready") {
        queue_command(u, "arm", mav::kCmdComponentArmDisarm, 1.0F);
        queue_command(u, "mission_start", mav::kCmdMissionStart);
        u.retry_after = now + 2s;
      }
    }
  }
  // separation between airborne UAVs
  for (std::size_t a = 0; a < uavs.size(); ++a)
    for (std::size_t b = a + 1; b < uavs.size(); ++b) {
      const UavRt &ua = uavs[a], &ub = uavs[b];
      bool close = false;
      double d = 0;
      if (ua.have_position && ub.have_position && ua.alt_m > 1.0 && ub.alt_m > 1.0 && ua.link_state == "ok" &&
          ub.link_state == "ok") {
        const double h =
            bg::distance(frame.to_local(LonLat{ua.lon, ua.lat}), frame.to_local(LonLat{ub.lon, ub.lat}));
        d = std::hypot(h, ua.alt_m - ub.alt_m);
        close = d < config.separation_m;
      }
      set_alert("separation", ua.binding.uav, ub.binding.uav, close, fmt::format("{:.1f} m apart", d));
    }
  update_state();
}

void Flight::Impl::supervisor_loop(const std::stop_token& stop) {
  while (!stop.stop_requested()) {
    std::vector<std::size_t> offers;  // failed UAVs to re-plan
    std::vector<std::vector<Helper>> helpers;
    std::vector<int> reached;
    {
      std::lock_guard lock(mutex);
      const auto now = Clock::now();
      supervise_locked(now);
      const auto after =
          std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(config.reassign_after_s));
      for (std::size_t i = 0; i < uavs.size(); ++i) {
        UavRt& u = uavs[i];
        const bool failed = u.phase == "failed";
        const bool landed_early = u.phase == "landed" && u.interrupted && u.interrupted_since &&
                                  now - *u.interrupted_since >= after;
        if (u.offered || aborted || !(failed || landed_early) || reassignments.size() >= kReassignMax)
          continue;
        u.offered = true;
        std::vector<Helper> hs;
        for (const auto& h : uavs)
          if (&h != &u && h.link_state == "ok" && h.phase != "failed")
            hs.push_back(Helper{h.index, airborne_phase(h.phase)
                                             ? std::clamp(h.battery_pct.value_or(100.0) / 100.0, 0.01, 1.0)
                                             : 1.0});
        offers.push_back(i);
        helpers.push_back(std::move(hs));
        reached.push_back(last_reached(u));
      }
    }
    for (std::size_t k = 0; k < offers.size(); ++k) {
      const std::size_t i = offers[k];
      ReassignmentRt r;
      r.failed = uavs[i].index;  // immutable after construction
      r.failed_uav = uavs[i].binding.uav;
      r.last_reached = reached[k];
      r.helpers = helpers[k];
      r.at_ms = now_ms();
      std::string error;
      if (r.helpers.empty()) {
        error = "no UAV left to help";
      } else {
        try {
          r.result =
              std::make_shared<const Reassignment>(reassign(plan, r.failed, r.last_reached, r.helpers));
          if (r.result->work.empty()) error = "nothing left to cover";
        } catch (const std::exception& e) {
          error = e.what();
        }
      }
      std::lock_guard lock(mutex);
      if (!error.empty()) {
        record(r.failed_uav, "reassignment", {{"state", "impossible"}, {"reason", error}});
        continue;
      }
      r.id = static_cast<int>(reassignments.size()) + 1;
      reassignments.push_back(r);
      const json j = snapshot_locked()["reassignments"].back();
      record(r.failed_uav, "reassignment", j);
      if (config.auto_reassign) apply_reassignment(reassignments.back());
    }
    flush();
    std::this_thread::sleep_for(50ms);
  }
  add_thread_cpu();
}

void Flight::Impl::add_thread_cpu() {
  timespec ts{};
  if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) == 0) cpu_ns += ts.tv_sec * 1'000'000'000LL + ts.tv_nsec;
}

void Flight::Impl::flush() {
  std::lock_guard order(flush_mutex);
  std::vector<LogRecord> out;
  bool changed = false;
  {
    std::lock_guard lock(mutex);
    out.swap(pending);
    const std::int64_t t = now_ms();
    if (dirty && t - last_changed_ms >= 100) {
      dirty = false;
      changed = true;
      last_changed_ms = t;
    }
  }
  try {  // the observer's failure (a store that cannot write) must not stop the flight
    if (!out.empty()) observer.on_records(id, out);
    if (changed) observer.on_changed(id);
  } catch (const std::exception&) {
  }
}

// ---- reassignment ----

MissionSpec Flight::Impl::reassigned_mission(const ReassignmentRt& r, const ReassignedWork& w,
                                             std::size_t k) const {
  MissionSpec m = make_mission(w.index, w.missions.at(k));
  m.kind = "reassigned";
  m.reassignment = r.id;
  m.k = static_cast<int>(k);
  m.index = static_cast<int>(k);
  // without sorties (a leg longer than a battery) the work is one mission
  m.first_waypoint = k < w.sorties.size() ? w.sorties[k].first_waypoint : 0;
  m.last_waypoint = k < w.sorties.size() ? w.sorties[k].last_waypoint : w.waypoints - 1;
  m.waypoints.assign(static_cast<std::size_t>(std::max(0, m.last_waypoint - m.first_waypoint + 1)), 'P');
  return m;
}

void Flight::Impl::apply_reassignment(ReassignmentRt& r) {
  if (!r.result) throw CommandRefused("reassignment " + std::to_string(r.id) + " has no result");
  for (const auto& w : r.result->work) {
    auto it = std::find_if(uavs.begin(), uavs.end(), [&](const UavRt& h) { return h.index == w.index; });
    if (it == uavs.end()) continue;
    for (std::size_t k = 0; k < w.missions.size(); ++k) it->missions.push_back(reassigned_mission(r, w, k));
    if (it->phase == "done") set_phase(*it, "landed");
  }
  auto failed = std::find_if(uavs.begin(), uavs.end(), [&](const UavRt& h) { return h.index == r.failed; });
  if (failed != uavs.end()) {
    for (std::size_t k = failed->current; k < failed->missions.size(); ++k) {
      MissionSpec& m = failed->missions[k];
      if (m.state == "done") continue;
      for (int g = m.first_waypoint; m.kind == "reassigned" && g <= m.last_waypoint; ++g)
        set_waypoint(*failed, m, g, 'S');
      m.state = "skipped";
    }
    MissionSpec own;  // the UAV's own waypoints
    own.kind = "sortie";
    for (std::size_t g = 0; g < failed->waypoints.size(); ++g)
      if (failed->waypoints[g] == 'P' || failed->waypoints[g] == 'C')
        set_waypoint(*failed, own, static_cast<int>(g), 'S');
    failed->current = failed->missions.size();
    failed->interrupted = false;
    failed->actions.clear();
    if (failed->phase == "landed") set_phase(*failed, "done");
  }
  r.state = "applied";
  record(r.failed_uav, "reassignment", {{"id", r.id}, {"state", "applied"}});
}

// ---- operator commands ----

void Flight::Impl::restore(const json& s) {
  auto phase_ok = [](const std::string& p) {
    static const std::vector<std::string> k{"idle",      "uploading", "ready",  "flying", "paused",
                                            "returning", "landed",    "failed", "done"};
    return std::find(k.begin(), k.end(), p) != k.end();
  };
  try {
    started = s.value("started", false);
    aborted = s.value("state", "") == "aborted";
    state = s.value("state", "created");
    for (const auto& jr : s.value("reassignments", json::array())) {
      if (reassignments.size() >= kReassignMax) break;
      ReassignmentRt r;
      r.id = jr.at("id").get<int>();
      if (r.id != static_cast<int>(reassignments.size()) + 1)
        throw InputError("restored.reassignments", "ids must count from 1");
      r.failed_uav = jr.at("failed_uav").get<std::string>();
      const auto it = std::find_if(plan.uavs.begin(), plan.uavs.end(),
                                   [&](const UavPlan& u) { return u.id == r.failed_uav; });
      if (it == plan.uavs.end()) throw InputError("restored.reassignments", "unknown UAV " + r.failed_uav);
      r.failed = static_cast<std::size_t>(it - plan.uavs.begin());
      r.state = jr.at("state").get<std::string>();
      r.last_reached = jr.at("last_reached").get<int>();
      for (const auto& jh : jr.value("helpers", json::array())) {
        const auto h = std::find_if(plan.uavs.begin(), plan.uavs.end(), [&](const UavPlan& u) {
          return u.id == jh.at("uav").get<std::string>();
        });
        if (h == plan.uavs.end()) throw InputError("restored.reassignments.helpers", "unknown UAV");
        r.helpers.push_back(Helper{static_cast<std::size_t>(h - plan.uavs.begin()),
                                   std::clamp(jh.at("battery").get<double>(), 0.01, 1.0)});
      }
      if (r.state !=
          "declined")  // deterministic: the same plan, UAV, waypoint and helpers give the same work
        r.result = std::make_shared<const Reassignment>(reassign(plan, r.failed, r.last_reached, r.helpers));
      reassignments.push_back(std::move(r));
    }
    for (const auto& ju : s.value("uavs", json::array())) {
      const std::string id_ = ju.at("uav").get<std::string>();
      auto it = std::find_if(uavs.begin(), uavs.end(), [&](const UavRt& u) { return u.binding.uav == id_; });
      if (it == uavs.end()) continue;
      UavRt& u = *it;
      const std::string wp = ju.at("waypoints").get<std::string>();
      if (wp.size() != u.waypoints.size() || wp.find_first_not_of("PCRS") != std::string::npos)
        throw InputError("restored.uavs.waypoints", "does not match the plan");
      u.waypoints = wp;
      const std::string phase = ju.at("phase").get<std::string>();
      if (!phase_ok(phase)) throw InputError("restored.uavs.phase", "unknown phase " + phase);
      u.phase = phase == "uploading" ? "idle" : phase;
      u.interrupted = ju.value("interrupted", false);
      if (u.interrupted) u.interrupted_since = Clock::now();
      u.offered = ju.value("offered", false);
      u.battery_pct = ju.contains("battery_pct") && ju["battery_pct"].is_number()
                          ? std::optional<double>(ju["battery_pct"].get<double>())
                          : std::nullopt;
      for (const auto& p : ju.value("trail", json::array()))
        if (p.is_array() && p.size() == 3 && u.trail.size() < kTrailMax)
          u.trail.push_back({p[0].get<double>(), p[1].get<double>(), p[2].get<double>()});
      std::vector<MissionSpec> ms;
      std::map<int, std::vector<MissionSpec>> own_cache;
      for (const auto& jm : ju.at("missions")) {
        const std::string kind = jm.at("kind").get<std::string>();
        const int k = jm.at("k").get<int>();
        MissionSpec m;
        if (kind == "reassigned") {
          const int rid = jm.at("reassignment").get<int>();
          if (rid < 1 || rid > static_cast<int>(reassignments.size()) ||
              !reassignments[static_cast<std::size_t>(rid - 1)].result)
            throw InputError("restored.uavs.missions", "unknown reassignment");
          const auto& work = reassignments[static_cast<std::size_t>(rid - 1)].result->work;
          const auto w = std::find_if(work.begin(), work.end(),
                                      [&](const ReassignedWork& x) { return x.index == u.index; });
          if (w == work.end() || k < 0 || k >= static_cast<int>(w->missions.size()))
            throw InputError("restored.uavs.missions", "not in the reassignment");
          m = reassigned_mission(reassignments[static_cast<std::size_t>(rid - 1)], *w,
                                 static_cast<std::size_t>(k));
          const std::string wp = jm.at("waypoints").get<std::string>();
          if (wp.size() != m.waypoints.size() || wp.find_first_not_of("PCRS") != std::string::npos)
            throw InputError("restored.uavs.missions.waypoints", "does not match the reassignment");
          m.waypoints = wp;
        } else {
          const int from = jm.at("from_waypoint").get<int>();
          if (!own_cache.contains(from)) own_cache[from] = own_missions(u.index, from);
          const auto& list = own_cache[from];
          if (k < 0 || k >= static_cast<int>(list.size()))
            throw InputError("restored.uavs.missions.k", "out of range");
          m = list[static_cast<std::size_t>(k)];
        }
        m.state = jm.at("state").get<std::string>();
        if (m.state == "uploading") m.state = "pending";
        ms.push_back(std::move(m));
      }
      u.missions = std::move(ms);
      u.current = std::min(u.missions.size(), ju.at("current_mission").get<std::size_t>());
      if (u.phase == "ready" && u.current < u.missions.size() && u.missions[u.current].state == "ready" &&
          !started)
        u.phase = "ready";
      if (airborne_phase(u.phase)) u.airborne_seen = true;  // it was flying when the server stopped
    }
    for (const auto& ja : s.value("alerts", json::array())) {
      if (alerts.size() >= kAlertsMax) break;
      alerts.push_back(Alert{ja.at("kind").get<std::string>(), ja.at("uav").get<std::string>(),
                             ja.value("other", json()).is_string() ? ja["other"].get<std::string>() : "",
                             ja.value("message", ""), 0, false});  // re-raised by what the links say now
    }
  } catch (const json::exception& e) {
    throw InputError("restored", std::string("not a flight snapshot: ") + e.what());
  }
}

// ---- snapshot ----

json Flight::Impl::snapshot_locked() const {
  json ju = json::array();
  for (const auto& u : uavs) {
    const Uav& spec = plan.mission.uavs[u.index];
    // ETA: what is left of the current mission from the vehicle's item, and the missions after it
    double left_m = 0;
    int turns = 0;
    for (std::size_t k = u.current; k < u.missions.size(); ++k) {
      const MissionSpec& m = u.missions[k];
      if (m.state == "skipped" || m.state == "done") continue;
      std::size_t from = 0;
      if (k == u.current && airborne_phase(u.phase) && u.current_item) {
        from = std::min<std::size_t>(static_cast<std::size_t>(*u.current_item), m.items.size());
        if (from < m.items.size() && m.where[from] && u.have_position)
          left_m += bg::distance(frame.to_local(LonLat{u.lon, u.lat}), *m.where[from]);
      }
      left_m += m.rest_m[from];
      turns += m.rest_turns[from];
    }
    const double eta_s =
        left_m > 0 || turns > 0 ? 60.0 * evaluation::flight_duration_min(left_m, turns, spec) : 0.0;
    const auto reached = std::count(u.waypoints.begin(), u.waypoints.end(), 'R');
    json missions = json::array();
    for (const auto& m : u.missions) {
      json jm{{"kind", m.kind},
              {"index", m.index},
              {"first_waypoint", m.first_waypoint},
              {"last_waypoint", m.last_waypoint},
              {"state", m.state},
              {"k", m.k}};
      if (m.kind == "reassigned") {
        jm["reassignment"] = m.reassignment;
        jm["waypoints"] = m.waypoints;
        json path = json::array();
        for (const auto& it : m.items)
          if (it.waypoint >= 0) path.push_back({it.lon, it.lat});
        jm["path"] = std::move(path);
      } else {
        jm["from_waypoint"] = m.from_waypoint;
      }
      missions.push_back(std::move(jm));
    }
    json trail = json::array();
    for (const auto& p : u.trail) trail.push_back({p[0], p[1], p[2]});
    int sortie = 0, sorties_n = 0;
    for (std::size_t k = 0; k < u.missions.size(); ++k)
      if (u.missions[k].kind != "reassigned") {
        ++sorties_n;
        if (k < u.current) ++sortie;
      }
    json j{
        {"uav", u.binding.uav},
        {"endpoint", endpoint_text(u.binding)},
        {"sysid", u.binding.sysid},
        {"phase", u.phase},
        {"link",
         {{"state", u.link_state},
          {"last_heard", u.last_heard_ms ? json(iso_time(u.last_heard_ms)) : json()},
          {"rx", u.rx},
          {"tx", u.tx}}},
        {"armed", u.armed},
        {"mode", u.mode},
        {"band", u.band},
        {"progress",
         u.waypoints.empty() ? 1.0 : static_cast<double>(reached) / static_cast<double>(u.waypoints.size())},
        {"eta_s", std::lround(eta_s)},
        {"sortie", std::min(sortie, std::max(0, sorties_n - 1))},
        {"sorties", sorties_n},
        {"current_mission", u.current},
        {"interrupted", u.interrupted},
        {"offered", u.offered},
        {"waypoints", u.waypoints},
        {"missions", std::move(missions)},
        {"trail", std::move(trail)}};
    j["battery_pct"] = u.battery_pct ? json(*u.battery_pct) : json();
    j["position"] = u.have_position ? json{{"lon", u.lon},
                                           {"lat", u.lat},
                                           {"alt_m", u.alt_m},
                                           {"speed_mps", u.speed_mps},
                                           {"heading_deg", u.heading_deg}}
                                    : json();
    ju.push_back(std::move(j));
  }
  json ja = json::array();
  for (const auto& a : alerts)
    ja.push_back({{"kind", a.kind},
                  {"uav", a.uav},
                  {"other", a.other.empty() ? json() : json(a.other)},
                  {"message", a.message},
                  {"since", iso_time(a.since_ms)},
                  {"active", a.active}});
  json jr = json::array();
  for (const auto& r : reassignments) {
    json to = json::array();
    json helpers = json::array();
    for (const auto& h : r.helpers)
      helpers.push_back({{"uav", plan.uavs[h.index].id}, {"battery", h.battery_fraction}});
    json x{{"id", r.id},
           {"failed_uav", r.failed_uav},
           {"state", r.state},
           {"at", iso_time(r.at_ms)},
           {"last_reached", r.last_reached},
           {"helpers", std::move(helpers)}};
    if (r.result) {
      for (const auto& w : r.result->work)
        to.push_back({{"uav", w.uav},
                      {"waypoints", w.waypoints},
                      {"length_m", w.coverage_length_m},
                      {"sorties", w.sorties.size()}});
      x["remaining_waypoints"] = r.result->remaining_waypoints.size();
      x["area_m2"] = r.result->area_m2;
      x["warnings"] = r.result->warnings;
    }
    x["to"] = std::move(to);
    jr.push_back(std::move(x));
  }
  return {{"state", state},
          {"started", started},
          {"config", config_json(config)},
          {"uavs", std::move(ju)},
          {"alerts", std::move(ja)},
          {"reassignments", std::move(jr)},
          {"runtime", {{"cpu_s", static_cast<double>(cpu_ns.load()) * 1e-9}}}};
}

// ---- the public class ----

Flight::Flight(std::int64_t id, Plan plan, FlightConfig config, Observer& observer,
               const std::optional<json>& restored)
    : impl_(std::make_unique<Impl>(id, std::move(plan), std::move(config), observer)) {
  if (restored) impl_->restore(*restored);
}

Flight::~Flight() { stop(); }

void Flight::start() {
  std::lock_guard lock(impl_->mutex);
  Impl& f = *impl_;
  if (f.running) return;
  f.links.clear();
  for (std::size_t i = 0; i < f.uavs.size(); ++i) {
    const auto& b = f.uavs[i].binding;
    try {
      f.links.push_back(mav::open_link(link_address(b), kGcsSysid, kGcsCompid));
    } catch (const std::exception& e) {
      f.links.clear();
      throw InputError(fmt::format("vehicles[{}].endpoint", i), e.what());
    }
  }
  const auto now = Clock::now();
  for (auto& u : f.uavs) u.last_heard = now;  // judged lost only after link_timeout_s of silence
  f.running = true;
  for (std::size_t i = 0; i < f.uavs.size(); ++i)
    f.threads.emplace_back([&f, i](const std::stop_token& st) { f.vehicle_loop(i, st); });
  f.threads.emplace_back([&f](const std::stop_token& st) { f.supervisor_loop(st); });
}

void Flight::stop() {
  std::vector<std::jthread> threads;
  {
    std::lock_guard lock(impl_->mutex);
    if (!impl_->running) return;
    impl_->running = false;
    threads.swap(impl_->threads);
  }
  for (auto& t : threads) t.request_stop();
  threads.clear();  // joins
  impl_->links.clear();
  impl_->flush();
}

void Flight::command(const Command& c) {
  Impl& f = *impl_;
  std::lock_guard lock(f.mutex);
  if (f.state == "done" || f.aborted) throw CommandRefused("the flight is " + f.state);
  std::vector<UavRt*> targets;
  for (auto& u : f.uavs)
    if (c.uav.empty() || u.binding.uav == c.uav) targets.push_back(&u);
  if (!c.uav.empty() && targets.empty()) throw InputError("uav", "the flight has no UAV \"" + c.uav + "\"");
  auto idle_link = [](const UavRt& u) { return u.actions.empty() && !u.command_active; };
  int n = 0;
  const std::string& k = c.command;
  if (k == "reassign" || k == "decline") {
    ReassignmentRt* r = nullptr;
    for (auto& x : f.reassignments)
      if ((c.reassignment ? x.id == *c.reassignment : x.state == "offered") && (!r || !c.reassignment))
        r = &x;
    if (!r)
      throw CommandRefused(c.reassignment ? fmt::format("no reassignment {}", *c.reassignment)
                                          : "no reassignment is offered");
    if (r->state != "offered") throw CommandRefused(fmt::format("reassignment {} is {}", r->id, r->state));
    f.record("", "command", {{"command", k}, {"reassignment", r->id}});
    if (k == "reassign") {
      f.apply_reassignment(*r);
    } else {
      r->state = "declined";
      f.record(r->failed_uav, "reassignment", {{"id", r->id}, {"state", "declined"}});
    }
    f.update_state();
    return;
  }
  if (k == "abort") {
    for (auto& u : f.uavs) {
      u.actions.clear();
      if (airborne_phase(u.phase) && u.link_state != "lost")
        f.queue_command(u, "rtl", mav::kCmdNavReturnToLaunch);
    }
    f.record("", "command", {{"command", k}});
    f.aborted = true;
    f.update_state();
    return;
  }
  for (UavRt* t : targets) {
    UavRt& u = *t;
    const bool has_next = u.current < u.missions.size();
    const std::string st = has_next ? u.missions[u.current].state : "";
    bool ok = false;
    if (k == "upload") {
      ok = (u.phase == "idle" || u.phase == "ready" || u.phase == "landed") && idle_link(u) &&
           !u.interrupted && (st == "pending" || st == "ready");
      if (ok) {
        u.missions[u.current].state = "pending";
        Action a;
        a.kind = Action::Kind::Upload;
        a.mission = u.current;
        a.name = "upload";
        u.actions.push_back(std::move(a));
      }
    } else if (k == "start") {
      ok = u.phase == "ready" && st == "ready" && idle_link(u);
      if (ok) {
        f.queue_command(u, "arm", mav::kCmdComponentArmDisarm, 1.0F);
        f.queue_command(u, "mission_start", mav::kCmdMissionStart);
        f.started = true;
      }
    } else if (k == "pause" || k == "continue") {
      ok = u.phase == (k == "pause" ? "flying" : "paused");
      if (ok) f.queue_command(u, k, mav::kCmdDoPauseContinue, k == "pause" ? 0.0F : 1.0F);
    } else if (k == "rtl" || k == "land") {
      ok = airborne_phase(u.phase) && u.link_state != "lost";
      if (ok) f.queue_command(u, k, k == "rtl" ? mav::kCmdNavReturnToLaunch : mav::kCmdNavLand);
    } else if (k == "resume") {
      ok = u.phase == "landed" && u.interrupted && idle_link(u) && u.link_state == "ok";
      if (ok) {
        if (u.missions.size() > 1000) throw CommandRefused("too many missions for UAV " + u.binding.uav);
        std::vector<MissionSpec> rest = f.own_missions(u.index, f.last_reached(u));
        // kept: the missions flown and the one interrupted; then the resumed rest (it replaces the own
        // missions not flown), then the reassigned work still queued
        std::vector<MissionSpec> next(u.missions.begin(),
                                      u.missions.begin() + static_cast<long>(u.current) + 1);
        for (auto& m : rest) next.push_back(std::move(m));
        for (std::size_t j = u.current + 1; j < u.missions.size(); ++j)
          if (u.missions[j].kind == "reassigned" && u.missions[j].state == "pending")
            next.push_back(u.missions[j]);
        u.missions = std::move(next);
        ++u.current;
        u.interrupted = false;
        u.offered = false;
        f.queue_upload_and_start(u);
        f.started = true;
      }
    } else if (k == "next_sortie") {
      ok = (u.phase == "landed" || u.phase == "done") && !u.interrupted && st == "pending" && idle_link(u);
      if (ok) f.queue_upload_and_start(u);
    }
    if (ok) {
      ++n;
      f.record(u.binding.uav, "command", {{"command", k}});
    }
  }
  if (n == 0)
    throw CommandRefused(
        fmt::format("{}: no UAV {}can do it now", k, c.uav.empty() ? "" : "\"" + c.uav + "\" "));
  f.update_state();
}

std::int64_t Flight::id() const { return impl_->id; }

std::string Flight::state() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->state;
}

bool Flight::finished() const {
  std::lock_guard lock(impl_->mutex);
  if (impl_->state == "done") return true;
  if (!impl_->aborted) return false;
  return std::all_of(impl_->uavs.begin(), impl_->uavs.end(),
                     [](const UavRt& u) { return u.actions.empty() && !u.command_active; });
}

json Flight::snapshot() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->snapshot_locked();
}

std::vector<std::pair<std::string, std::vector<std::array<double, 3>>>> Flight::tracks() const {
  std::lock_guard lock(impl_->mutex);
  std::vector<std::pair<std::string, std::vector<std::array<double, 3>>>> out;
  for (const auto& u : impl_->uavs) out.emplace_back(u.binding.uav, u.track);
  return out;
}

}  // namespace uavcover::flight
