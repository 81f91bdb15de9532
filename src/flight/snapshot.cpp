// A flight's snapshot (the JSON of GET /flights/{id} and of the store) and its restore after a
// server restart (docs/flights.md).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "evaluation/cost.hpp"
#include "flight/runtime.hpp"
#include "json/iso_time.hpp"
#include "sorties/sorties.hpp"
#include "uavcover/error.hpp"

namespace uavcover::flight {

using namespace detail;
using namespace std::chrono_literals;
using nlohmann::json;

namespace {

/// A time of the snapshot, or "" when there is none (0).
std::string time_or_empty(std::int64_t ms) { return ms <= 0 ? "" : iso_time(ms); }

}  // namespace

// ---- restore ----

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
        Helper x{static_cast<std::size_t>(h - plan.uavs.begin()),
                 std::clamp(jh.at("battery").get<double>(), 0.01, 1.0)};
        if (const auto d = jh.find("depot"); d != jh.end() && d->is_array())
          x.depot = LonLat{d->at(0).get<double>(), d->at(1).get<double>()};
        r.helpers.push_back(x);
      }
      r.from = jr.value("from", "home") == "air" ? "air" : "home";
      if (r.state == "replanning") r.state = "offered";  // the re-plan was lost with the server
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
      if (const auto rt = ju.find("retries"); rt != ju.end() && rt->is_object())
        u.retries_total = std::max(0, rt->value("total", 0));
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
    double left_m = 0, vertical_s = 0;
    int turns = 0;
    for (std::size_t k = u.current; k < u.missions.size(); ++k) {
      const MissionSpec& m = u.missions[k];
      if (m.state == "skipped" || m.state == "done") continue;
      std::size_t from = 0;
      if (k == u.current && airborne_phase(u.phase) && u.current_item) {
        from = std::min<std::size_t>(static_cast<std::size_t>(*u.current_item), m.items.size());
        if (from < m.items.size() && m.where[from] && u.have_position)
          left_m += evaluation::air_distance_m(frame.to_local(LonLat{u.lon, u.lat}), *m.where[from],
                                               spec.speed_mps, plan.mission.wind);
      }
      left_m += m.rest_m[from];
      turns += m.rest_turns[from];
      vertical_s += m.rest_vertical_s[from];
    }
    // eq. 15 of what is left, and its climbs and descents (the whole flight, docs/wind.md)
    const double eta_s =
        (left_m > 0 || turns > 0 ? 60.0 * evaluation::flight_duration_min(left_m, turns, spec) : 0.0) +
        vertical_s;
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
        // where it begins: the take-off item (its helper's home, or its live position from the air)
        if (!m.items.empty()) jm["start"] = {m.items.front().lon, m.items.front().lat};
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
          {"last_heard", u.last_heard_ms ? json(time_or_empty(u.last_heard_ms)) : json()},
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
        {"retries",
         {{"waypoint", u.timed && u.retries > 0 ? json(u.timed_waypoint) : json()},
          {"count", u.retries},
          {"total", u.retries_total}}},
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
                  {"since", time_or_empty(a.since_ms)},
                  {"active", a.active}});
  json jr = json::array();
  for (const auto& r : reassignments) {
    json to = json::array();
    json helpers = json::array();
    for (const auto& h : r.helpers)
      helpers.push_back({{"uav", plan.uavs[h.index].id},
                         {"battery", h.battery_fraction},
                         {"depot", h.depot ? json{h.depot->lon, h.depot->lat} : json()}});
    json x{{"id", r.id},
           {"failed_uav", r.failed_uav},
           {"state", r.state},
           {"from", r.from},
           {"at", time_or_empty(r.at_ms)},
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

}  // namespace uavcover::flight
