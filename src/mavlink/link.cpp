#include "mavlink/link.hpp"

#include <arpa/inet.h>
#include <fmt/format.h>

#include <algorithm>
#include <charconv>

#include "mavlink/stream.hpp"
#include "mavlink/udp.hpp"
#include "uavcover/error.hpp"

namespace uavcover::mavlink {

namespace {

const char* kUsage =
    "expected udp:HOST:PORT, udpin:HOST:PORT, tcp:HOST:PORT, tcpin:HOST:PORT or serial:DEVICE:BAUD "
    "(e.g. tcp:127.0.0.1:5760, serial:/dev/ttyUSB0:57600)";

std::string scheme_name(Transport t) {
  switch (t) {
    case Transport::Udp:
      return "udp";
    case Transport::UdpListen:
      return "udpin";
    case Transport::Tcp:
      return "tcp";
    case Transport::TcpListen:
      return "tcpin";
    case Transport::Serial:
      return "serial";
  }
  return "udp";
}

}  // namespace

const std::vector<unsigned>& serial_baud_rates() {
  static const std::vector<unsigned> rates{1200,   2400,   4800,   9600,   19200,  38400,   57600,   115200,
                                           230400, 460800, 500000, 576000, 921600, 1000000, 1500000, 2000000};
  return rates;
}

std::string LinkAddress::text() const {
  if (transport == Transport::Serial) return fmt::format("serial:{}:{}", device, baud);
  return fmt::format("{}:{}:{}", scheme_name(transport), endpoint.host, endpoint.port);
}

Endpoint parse_host_port(const std::string& rest, const std::string& field, const std::string& usage,
                         bool allow_port_zero) {
  const auto colon = rest.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == rest.size()) throw InputError(field, usage);
  Endpoint e;
  e.host = rest.substr(0, colon);
  const std::string port = rest.substr(colon + 1);
  unsigned value = 0;
  const auto [ptr, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
  if (ec != std::errc{} || ptr != port.data() + port.size() || (value == 0 && !allow_port_zero) ||
      value > 65535)
    throw InputError(
        field, fmt::format("port must be an integer in {}..65535, got '{}'", allow_port_zero ? 0 : 1, port));
  e.port = static_cast<std::uint16_t>(value);
  in_addr tmp{};
  if (e.host != "localhost" && inet_pton(AF_INET, e.host.c_str(), &tmp) != 1)
    throw InputError(field, "host must be a dotted IPv4 address or 'localhost', got '" + e.host + "'");
  return e;
}

LinkAddress parse_link_address(const std::string& text, const std::string& field, bool allow_port_zero) {
  const std::string usage = std::string(kUsage) + ", got '" + text + "'";
  const auto colon = text.find(':');
  if (colon == std::string::npos) throw InputError(field, usage);
  const std::string scheme = text.substr(0, colon);
  const std::string rest = text.substr(colon + 1);
  LinkAddress a;
  if (scheme == "udp" || scheme == "udpout") {
    a.transport = Transport::Udp;
  } else if (scheme == "udpin") {
    a.transport = Transport::UdpListen;
  } else if (scheme == "tcp") {
    a.transport = Transport::Tcp;
  } else if (scheme == "tcpin") {
    a.transport = Transport::TcpListen;
  } else if (scheme == "serial") {
    a.transport = Transport::Serial;
    // serial:DEVICE:BAUD (MAVProxy's DEVICE,BAUD is accepted too)
    const auto sep = rest.find_last_of(":,");
    if (sep == std::string::npos || sep == 0 || sep + 1 == rest.size()) throw InputError(field, usage);
    a.device = rest.substr(0, sep);
    if (a.device.front() != '/')
      throw InputError(field,
                       "serial device must be an absolute path (e.g. /dev/ttyUSB0), got '" + a.device + "'");
    const std::string baud = rest.substr(sep + 1);
    unsigned value = 0;
    const auto [ptr, ec] = std::from_chars(baud.data(), baud.data() + baud.size(), value);
    const auto& rates = serial_baud_rates();
    if (ec != std::errc{} || ptr != baud.data() + baud.size() ||
        std::find(rates.begin(), rates.end(), value) == rates.end()) {
      std::string list;
      for (unsigned r : rates) list += (list.empty() ? "" : ", ") + std::to_string(r);
      throw InputError(field, "baud rate must be one of " + list + ", got '" + baud + "'");
    }
    a.baud = value;
    return a;
  } else {
    throw InputError(field, usage);
  }
  a.endpoint = parse_host_port(rest, field, usage, allow_port_zero && a.listens());
  return a;
}

void Link::set_loss(double p, std::uint64_t seed) {
  loss_ = p;
  rng_.seed(seed);
}

bool Link::drop() {
  if (loss_ <= 0.0) return false;
  return std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < loss_;
}

bool Link::send(const Message& m) {
  if (!has_peer()) return false;
  Header h;
  h.seq = seq_++;
  h.sysid = sysid_;
  h.compid = compid_;
  return send_raw(encode(m, h));
}

void Link::feed(const std::uint8_t* data, std::size_t n, bool end_of_input, const sockaddr_in& from) {
  std::vector<Frame> frames;
  parser_.push(std::span<const std::uint8_t>(data, n), frames, end_of_input);
  for (auto& f : frames) {
    pending_.push_back(std::move(f));
    pending_from_.push_back(from);
  }
}

std::optional<Received> Link::receive(std::chrono::milliseconds timeout) {
  using clock = std::chrono::steady_clock;
  const auto deadline = clock::now() + timeout;
  while (true) {
    while (!pending_.empty()) {
      Frame f = std::move(pending_.front());
      const sockaddr_in from = pending_from_.front();
      pending_.erase(pending_.begin());
      pending_from_.erase(pending_from_.begin());
      auto msg = decode(f);
      if (!msg) continue;
      return Received{f.header, std::move(*msg), from};
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - clock::now());
    if (left.count() < 0) return std::nullopt;
    if (!read_some(left) && clock::now() >= deadline && pending_.empty()) return std::nullopt;
  }
}

std::unique_ptr<Link> open_link(const LinkAddress& address, std::uint8_t sysid, std::uint8_t compid) {
  switch (address.transport) {
    case Transport::Udp: {
      auto link = std::make_unique<UdpLink>(Endpoint{"0.0.0.0", 0}, sysid, compid);
      link->set_peer(address.endpoint);
      return link;
    }
    case Transport::UdpListen: {
      auto link = std::make_unique<UdpLink>(address.endpoint, sysid, compid);
      link->learn_peer(true);
      return link;
    }
    case Transport::Tcp:
      return std::make_unique<TcpClientLink>(address.endpoint, sysid, compid);
    case Transport::TcpListen:
      return std::make_unique<TcpListenLink>(address.endpoint, sysid, compid);
    case Transport::Serial:
      return std::make_unique<SerialLink>(address.device, address.baud, sysid, compid);
  }
  throw std::runtime_error("unknown transport");
}

}  // namespace uavcover::mavlink
