// The operator's commands on a flight (docs/flights.md, "Commands").
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "evaluation/cost.hpp"
#include "flight/runtime.hpp"
#include "sorties/sorties.hpp"
#include "uavcover/error.hpp"

namespace uavcover::flight {

using namespace detail;
using namespace std::chrono_literals;
using nlohmann::json;
namespace mav = uavcover::mavlink;

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
    json d{{"command", k}, {"reassignment", r->id}};
    if (c.reassign_from) d["reassign_from"] = *c.reassign_from;
    f.record("", "command", std::move(d));
    // an offer from the air applied late would send a helper back to where it was: re-planned too
    const std::string stale =
        k == "reassign" && c.reassign_from.value_or(r->from) == r->from ? f.stale_depot(*r) : std::string();
    if (k == "reassign" && ((c.reassign_from && *c.reassign_from != r->from) || !stale.empty())) {
      // the other choice, or the same from where the helpers are now: the supervisor re-plans it, then
      // applies it
      r->state = "replanning";
      r->replan_from = c.reassign_from.value_or(r->from);
      json rec{{"id", r->id}, {"state", "replanning"}, {"from", r->replan_from}};
      if (!stale.empty()) rec["reason"] = "stale depot: " + stale;
      f.record(r->failed_uav, "reassignment", std::move(rec));
    } else if (k == "reassign") {
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
      // a UAV failed on a waypoint (waypoint_failed) may still be flying: it can be brought back
      ok = (airborne_phase(u.phase) || (u.phase == "failed" && u.armed)) && u.link_state != "lost";
      if (ok) f.queue_command(u, k, k == "rtl" ? mav::kCmdNavReturnToLaunch : mav::kCmdNavLand);
    } else if (k == "resume") {
      ok = u.phase == "landed" && u.interrupted && idle_link(u) && u.link_state == "ok";
      if (ok) {
        f.requeue(u, {});  // the missions flown and the one interrupted, then the resumed rest
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

}  // namespace uavcover::flight
