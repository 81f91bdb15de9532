// A MAVLink endpoint over a UDP socket (POSIX): sends encoded messages, receives and parses
// datagrams, with optional seeded packet-loss injection for tests.
#pragma once

#include <netinet/in.h>

#include <chrono>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "mavlink/frame.hpp"
#include "mavlink/messages.hpp"

namespace uavcover::mavlink {

/// An IPv4 UDP address.
struct Endpoint {
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;
  friend bool operator==(const Endpoint&, const Endpoint&) = default;
};

/// Parses "udp:HOST:PORT" (HOST: dotted IPv4 or "localhost"; PORT 1..65535).
/// Throws uavcover::InputError naming `field` when the text is not such an address.
Endpoint parse_udp_endpoint(const std::string& text, const std::string& field = "--to");

/// A received, decoded message with where it came from.
struct Received {
  Header header;
  Message message;
  sockaddr_in from{};
};

class UdpLink {
 public:
  struct Stats {
    std::size_t sent = 0, received = 0;          ///< datagrams actually sent / accepted
    std::size_t dropped_tx = 0, dropped_rx = 0;  ///< dropped by loss injection
  };

  /// Binds to `local` (port 0: any free port). Throws std::runtime_error on socket errors.
  explicit UdpLink(const Endpoint& local, std::uint8_t sysid, std::uint8_t compid);
  ~UdpLink();
  UdpLink(const UdpLink&) = delete;
  UdpLink& operator=(const UdpLink&) = delete;

  [[nodiscard]] std::uint16_t local_port() const { return local_port_; }
  /// The socket, for poll() over many links (the simulated fleet); reading stays with receive().
  [[nodiscard]] int native_handle() const { return fd_; }
  /// A decoded message is already waiting (receive() returns it without touching the socket).
  [[nodiscard]] bool has_pending() const { return !pending_.empty(); }
  [[nodiscard]] std::uint8_t sysid() const { return sysid_; }
  [[nodiscard]] std::uint8_t compid() const { return compid_; }

  /// Where send() goes. Unset until set_peer() or (with learn_peer) the first datagram received.
  void set_peer(const Endpoint& peer);
  void set_peer(const sockaddr_in& peer) { peer_ = peer; }
  [[nodiscard]] bool has_peer() const { return peer_.has_value(); }
  void learn_peer(bool on) { learn_peer_ = on; }

  /// Drops each datagram sent and each received with probability `p` (seeded, reproducible).
  void set_loss(double p, std::uint64_t seed);

  /// Encodes with the next packet sequence number and sends to the peer. False if no peer.
  bool send(const Message& m);
  /// Sends raw bytes (tests: garbage, foreign encoders' frames).
  bool send_raw(const std::vector<std::uint8_t>& bytes);

  /// Waits up to `timeout` for the next decoded message (non-mission messages included).
  std::optional<Received> receive(std::chrono::milliseconds timeout);

  [[nodiscard]] const Stats& stats() const { return stats_; }
  [[nodiscard]] const Parser::Stats& parser_stats() const { return parser_.stats(); }

 private:
  bool drop();

  int fd_ = -1;
  std::uint16_t local_port_ = 0;
  std::uint8_t sysid_, compid_;
  std::uint8_t seq_ = 0;
  std::optional<sockaddr_in> peer_;
  bool learn_peer_ = false;
  double loss_ = 0.0;
  std::mt19937_64 rng_;
  Parser parser_;
  std::vector<Frame> pending_;
  std::vector<sockaddr_in> pending_from_;
  Stats stats_;
};

}  // namespace uavcover::mavlink
