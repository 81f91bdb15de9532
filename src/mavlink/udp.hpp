// A MAVLink link over a UDP socket (POSIX): sends encoded messages, receives and parses datagrams, with
// optional seeded packet-loss injection for tests.
#pragma once

#include <netinet/in.h>

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "mavlink/link.hpp"

namespace uavcover::mavlink {

/// Parses "udp:HOST:PORT" (HOST: dotted IPv4 or "localhost"; PORT 1..65535).
/// Throws uavcover::InputError naming `field` when the text is not such an address.
Endpoint parse_udp_endpoint(const std::string& text, const std::string& field = "--to");

class UdpLink final : public Link {
 public:
  /// Binds to `local` (port 0: any free port). Throws std::runtime_error on socket errors.
  explicit UdpLink(const Endpoint& local, std::uint8_t sysid, std::uint8_t compid);
  ~UdpLink() override;

  [[nodiscard]] std::uint16_t local_port() const override { return local_port_; }
  /// The socket, for poll() over many links (the simulated fleet); reading stays with receive().
  [[nodiscard]] int native_handle() const { return fd_; }
  [[nodiscard]] std::vector<int> poll_handles() const override { return {fd_}; }
  [[nodiscard]] std::string describe() const override;

  /// Where send() goes. Unset until set_peer() or (with learn_peer) the first datagram received.
  void set_peer(const Endpoint& peer);
  void set_peer(const sockaddr_in& peer) { peer_ = peer; }
  [[nodiscard]] bool has_peer() const override { return peer_.has_value(); }
  void learn_peer(bool on) override { learn_peer_ = on; }

  bool send_raw(const std::vector<std::uint8_t>& bytes) override;

 protected:
  bool read_some(std::chrono::milliseconds timeout) override;

 private:
  int fd_ = -1;
  std::uint16_t local_port_ = 0;
  std::optional<sockaddr_in> peer_;
  bool learn_peer_ = false;
};

}  // namespace uavcover::mavlink
