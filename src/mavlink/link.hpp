// A MAVLink link, whatever carries it: UDP datagrams (udp.hpp), a TCP connection we open or accept, or a
// serial port (stream.hpp). The mission protocol, the simulated vehicles and the flight supervisor talk
// to a Link and do not care which.
//
// Addresses (docs/upload.md "Endpoints"):
//   udp:HOST:PORT      send to HOST:PORT (the vehicle answers to our port); `udpout:` is the same
//   udpin:HOST:PORT    bind HOST:PORT and answer whoever sends to it
//   tcp:HOST:PORT      connect to HOST:PORT (SITL, MAVProxy --out tcpin:..., a companion computer)
//   tcpin:HOST:PORT    listen on HOST:PORT and talk to the last client that connected
//   serial:DEVICE:BAUD a serial port (telemetry radio, USB autopilot), 8N1, no flow control
// HOST is a dotted IPv4 address or "localhost"; PORT 1..65535 (0 is accepted where a listener may take
// any free port); BAUD one of the standard rates.
#pragma once

#include <netinet/in.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "mavlink/frame.hpp"
#include "mavlink/messages.hpp"

namespace uavcover::mavlink {

/// An IPv4 address and port.
struct Endpoint {
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;
  friend bool operator==(const Endpoint&, const Endpoint&) = default;
};

/// A received, decoded message with where it came from (UDP: the datagram's source; otherwise zero).
struct Received {
  Header header;
  Message message;
  sockaddr_in from{};
};

enum class Transport { Udp, UdpListen, Tcp, TcpListen, Serial };

/// Where a link goes, parsed from the text forms above.
struct LinkAddress {
  Transport transport = Transport::Udp;
  Endpoint endpoint;   ///< udp, udpin, tcp, tcpin
  std::string device;  ///< serial
  unsigned baud = 0;   ///< serial
  [[nodiscard]] bool listens() const {
    return transport == Transport::UdpListen || transport == Transport::TcpListen;
  }
  /// The canonical text ("udp:127.0.0.1:14550", "tcpin:0.0.0.0:5760", "serial:/dev/ttyUSB0:57600").
  [[nodiscard]] std::string text() const;
  friend bool operator==(const LinkAddress&, const LinkAddress&) = default;
};

/// The baud rates a serial link accepts.
const std::vector<unsigned>& serial_baud_rates();

/// Parses an address in one of the forms above. `allow_port_zero`: a listener may take any free port.
/// Throws uavcover::InputError naming `field` ("--to: expected ...") when the text is not such an address.
LinkAddress parse_link_address(const std::string& text, const std::string& field,
                               bool allow_port_zero = false);

/// Parses "HOST:PORT" (the part after the scheme); InputError naming `field`, with `usage` on bad shape.
Endpoint parse_host_port(const std::string& rest, const std::string& field, const std::string& usage,
                         bool allow_port_zero = false);

class Link {
 public:
  struct Stats {
    std::size_t sent = 0, received = 0;          ///< frames (UDP: datagrams) sent / chunks accepted
    std::size_t dropped_tx = 0, dropped_rx = 0;  ///< dropped by loss injection
    std::size_t connections = 0;                 ///< stream links: connections made or accepted
    std::size_t disconnects = 0;                 ///< stream links: connections lost
  };

  Link(std::uint8_t sysid, std::uint8_t compid) : sysid_(sysid), compid_(compid) {}
  virtual ~Link() = default;
  Link(const Link&) = delete;
  Link& operator=(const Link&) = delete;

  [[nodiscard]] std::uint8_t sysid() const { return sysid_; }
  [[nodiscard]] std::uint8_t compid() const { return compid_; }

  /// send() has somewhere to go (UDP: a peer is known; TCP: connected; serial: open).
  [[nodiscard]] virtual bool has_peer() const = 0;
  /// UDP: answer whoever sent last. Streams always answer their one peer: a no-op.
  virtual void learn_peer(bool /*on*/) {}
  /// The descriptors to poll() for input (the simulated fleet polls many links at once); reading stays
  /// with receive(). A listener without a client polls its listening socket (receive() accepts).
  [[nodiscard]] virtual std::vector<int> poll_handles() const = 0;
  /// A decoded message is already waiting (receive() returns it without touching the socket).
  [[nodiscard]] bool has_pending() const { return !pending_.empty(); }
  /// The local port (UDP, TCP listener; 0 for others).
  [[nodiscard]] virtual std::uint16_t local_port() const { return 0; }
  /// The address, for messages ("tcp:127.0.0.1:5760").
  [[nodiscard]] virtual std::string describe() const = 0;

  /// Drops each frame sent and each chunk received with probability `p` (seeded, reproducible).
  /// Streams drop whole frames on send only (a byte stream cannot lose part of itself and resync
  /// honestly; the receive side is left intact).
  void set_loss(double p, std::uint64_t seed);

  /// Encodes with the next packet sequence number and sends. False if there is no peer.
  bool send(const Message& m);
  /// Sends raw bytes (tests: garbage, foreign encoders' frames). False if there is no peer.
  virtual bool send_raw(const std::vector<std::uint8_t>& bytes) = 0;

  /// Waits up to `timeout` for the next decoded message (non-mission messages included).
  std::optional<Received> receive(std::chrono::milliseconds timeout);

  [[nodiscard]] const Stats& stats() const { return stats_; }
  [[nodiscard]] const Parser::Stats& parser_stats() const { return parser_.stats(); }

 protected:
  /// Reads what is available within `timeout` and feeds it to feed(); false when nothing came.
  virtual bool read_some(std::chrono::milliseconds timeout) = 0;
  /// Parses `n` bytes (UDP: one datagram, `end_of_input`) and queues the frames with their source.
  void feed(const std::uint8_t* data, std::size_t n, bool end_of_input, const sockaddr_in& from);
  bool drop();
  Stats stats_;

 private:
  std::uint8_t sysid_, compid_;
  std::uint8_t seq_ = 0;
  double loss_ = 0.0;
  std::mt19937_64 rng_;
  Parser parser_;
  std::vector<Frame> pending_;
  std::vector<sockaddr_in> pending_from_;
};

/// Opens a link to `address` as (sysid, compid). UDP binds at once (udp: an ephemeral port on 0.0.0.0);
/// tcpin listens at once; tcp connects lazily (on first use, again after a loss, at most every second:
/// see TcpClientLink::connect() for a connect that reports why); serial opens at once. Throws
/// std::runtime_error when a socket or device cannot be opened.
std::unique_ptr<Link> open_link(const LinkAddress& address, std::uint8_t sysid, std::uint8_t compid);

}  // namespace uavcover::mavlink
