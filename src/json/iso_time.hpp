// Times in the JSON documents (the API, a flight's snapshot): "2026-11-26T01:02:03.456Z" from Unix
// milliseconds, UTC. The one home of the format (issue 27: the server and the flight each had one).
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace uavcover {

/// "2026-11-26T01:02:03.456Z" from Unix milliseconds.
inline std::string iso_time(std::int64_t unix_ms) {
  using namespace std::chrono;
  const sys_time<milliseconds> t{milliseconds(unix_ms)};
  const auto day = floor<days>(t);
  const year_month_day ymd{day};
  const hh_mm_ss<milliseconds> hms{t - day};
  char buf[40];
  std::snprintf(buf, sizeof buf, "%04d-%02u-%02uT%02lld:%02lld:%02lld.%03lldZ", static_cast<int>(ymd.year()),
                static_cast<unsigned>(ymd.month()), static_cast<unsigned>(ymd.day()),
                static_cast<long long>(hms.hours().count()), static_cast<long long>(hms.minutes().count()),
                static_cast<long long>(hms.seconds().count()),
                static_cast<long long>(hms.subseconds().count()));
  return buf;
}

}  // namespace uavcover
