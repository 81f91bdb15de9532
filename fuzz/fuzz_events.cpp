// libFuzzer target: the live job events' parsers of client input, the WebSocket message
// ({"subscribe": {"jobs": [ids]}}) and the Server-Sent Events ?jobs=12,13 parameter. They must refuse
// bad input with a field-named error, never crash, and never hand out more ids than allowed.
// The first byte picks the parser (low bit) and the subscription cap (the rest); the others are the text.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "server/events.hpp"
#include "server/http.hpp"

namespace {

void check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "invariant broken: %s\n", what);
    std::abort();
  }
}

bool positive(const std::vector<std::int64_t>& ids) {
  return std::all_of(ids.begin(), ids.end(), [](std::int64_t id) { return id > 0; });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using uavcover::server::ClientMessage;
  if (size == 0) return 0;
  const std::size_t max = data[0] >> 1;  // 0..127, around the server's default of 64
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  if ((data[0] & 1) == 0) {
    const ClientMessage m = uavcover::server::parse_client_message(text, max);
    switch (m.op) {
      case ClientMessage::Op::Subscribe:
        check(m.jobs.size() <= max && m.flights.size() <= max, "more subscribed ids than the cap");
        check(positive(m.jobs) && positive(m.flights), "a subscribed id is not positive");
        break;
      case ClientMessage::Op::Unsubscribe:
        check(m.jobs.size() + m.flights.size() <= text.size() / 2, "more ids than the message can hold");
        check(positive(m.jobs) && positive(m.flights), "an unsubscribed id is not positive");
        break;
      case ClientMessage::Op::Invalid:
        check(m.jobs.empty() && m.flights.empty(), "ids with an error");
        check(!m.error_message.empty(), "an error without a message");
        break;
    }
  } else {
    uavcover::server::Request req;
    req.method = "GET";
    req.path = "/api/v1/events";
    req.query["jobs"] = text;
    try {
      const auto ids = uavcover::server::parse_jobs_param(req, max);
      check(!ids.empty() && ids.size() <= max, "the id count is out of [1, max]");
      check(positive(ids), "an id is not positive");
      check(std::is_sorted(ids.begin(), ids.end()) && std::adjacent_find(ids.begin(), ids.end()) == ids.end(),
            "ids not sorted and unique");
    } catch (const uavcover::server::HttpError& e) {
      check(e.status == 400 && e.field == "jobs", "an error other than 400 \"jobs\"");
    }
  }
  return 0;
}
