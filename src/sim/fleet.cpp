// A simulated fleet (docs/simulate.md): its vehicles stepped on one clock, and the --fail option.
#include <poll.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include "autopilot/rules.hpp"
#include "mavlink/stream.hpp"
#include "mavlink/udp.hpp"
#include "sim/sim_internal.hpp"
#include "uavcover/error.hpp"

namespace uavcover::sim {

namespace mav = uavcover::mavlink;
namespace wp = uavcover::waypoints;
using namespace detail;

Fleet::Fleet(const std::vector<VehicleConfig>& configs, const FleetOptions& options) : opt_(options) {
  vehicles_.reserve(configs.size());
  for (const auto& c : configs) vehicles_.push_back(std::make_unique<SimVehicle>(c));
}

void Fleet::run(const std::stop_token& stop, std::optional<double> max_sim_s) {
  using clock = std::chrono::steady_clock;
  const double dt = opt_.physics_dt;
  std::vector<pollfd> fds;
  std::vector<std::size_t> owner;  // fds[k] belongs to vehicles_[owner[k]]
  auto t0 = clock::now();
  long long tick = 0;
  while (!stop.stop_requested()) {
    if (max_sim_s && sim_time_.load() >= *max_sim_s - 1e-9) return;
    const auto due = t0 + std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(
                              static_cast<double>(tick + 1) * dt / opt_.speedup));
    // handle the network until the next step is due
    while (true) {
      const auto left = due - clock::now();
      const auto wait = std::min<clock::duration>(std::max<clock::duration>(left, clock::duration::zero()),
                                                  std::chrono::milliseconds(20));
      timespec ts{};
      ts.tv_sec = static_cast<time_t>(std::chrono::duration_cast<std::chrono::seconds>(wait).count());
      ts.tv_nsec = static_cast<long>(std::chrono::duration_cast<std::chrono::nanoseconds>(wait).count() %
                                     1'000'000'000);
      // rebuilt each time: a TCP vehicle's descriptors change as clients come and go
      fds.clear();
      owner.clear();
      for (std::size_t i = 0; i < vehicles_.size(); ++i)
        for (int fd : vehicles_[i]->poll_handles()) {
          fds.push_back(pollfd{fd, POLLIN, 0});
          owner.push_back(i);
        }
      const int n = ::ppoll(fds.data(), fds.size(), &ts, nullptr);
      if (n > 0) {
        std::size_t last = vehicles_.size();
        for (std::size_t k = 0; k < fds.size(); ++k)
          if ((fds[k].revents & (POLLIN | POLLHUP | POLLERR)) && owner[k] != last) {
            last = owner[k];
            vehicles_[owner[k]]->service_link();
          }
      }
      if (stop.stop_requested()) return;
      if (clock::now() >= due) break;
    }
    for (auto& v : vehicles_) {
      v->service_timeouts();  // the mission protocol's re-requests (wall time)
      v->step(dt);
    }
    ++tick;
    sim_time_.store(sim_time_.load() + dt);
    // Fallen far behind (an overloaded machine): let simulated time slip instead of rushing.
    if (clock::now() - due > std::chrono::seconds(1)) {
      t0 = clock::now() - std::chrono::duration_cast<clock::duration>(
                              std::chrono::duration<double>(static_cast<double>(tick) * dt / opt_.speedup));
    }
  }
}

std::pair<std::uint8_t, Failure> parse_failure(const std::string& text, const std::string& field) {
  const std::string usage = "expected ID@FRACTION[:link|:land|:stuck] (e.g. 2@0.4:land), got '" + text + "'";
  const auto at = text.find('@');
  if (at == std::string::npos || at == 0) throw InputError(field, usage);
  unsigned id = 0;
  const char* b = text.data();
  const auto [p1, e1] = std::from_chars(b, b + at, id);
  if (e1 != std::errc{} || p1 != b + at || id < 1 || id > 255)
    throw InputError(field, "vehicle id must be a system id in 1..255, got '" + text.substr(0, at) + "'");
  std::string rest = text.substr(at + 1);
  Failure f;
  if (const auto colon = rest.find(':'); colon != std::string::npos) {
    const std::string kind = rest.substr(colon + 1);
    if (kind == "link")
      f.kind = FailureKind::Link;
    else if (kind == "land")
      f.kind = FailureKind::Land;
    else if (kind == "stuck")
      f.kind = FailureKind::Stuck;
    else
      throw InputError(field, "failure kind must be 'link', 'land' or 'stuck', got '" + kind + "'");
    rest = rest.substr(0, colon);
  }
  double frac = 0;
  const auto [p2, e2] = std::from_chars(rest.data(), rest.data() + rest.size(), frac);
  if (e2 != std::errc{} || p2 != rest.data() + rest.size() || !(frac > 0.0 && frac < 1.0))
    throw InputError(field, "fraction must be a number in (0, 1), got '" + rest + "'");
  f.fraction = frac;
  return {static_cast<std::uint8_t>(id), f};
}

}  // namespace uavcover::sim
