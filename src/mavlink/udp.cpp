#include "mavlink/udp.hpp"

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <stdexcept>

#include "uavcover/error.hpp"

namespace uavcover::mavlink {

namespace {

sockaddr_in to_sockaddr(const Endpoint& e) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(e.port);
  const std::string host = e.host == "localhost" ? "127.0.0.1" : e.host;
  if (inet_pton(AF_INET, host.c_str(), &a.sin_addr) != 1)
    throw std::runtime_error("not an IPv4 address: '" + e.host + "'");
  return a;
}

std::string sys_error(const std::string& what) { return what + ": " + std::strerror(errno); }

}  // namespace

Endpoint parse_udp_endpoint(const std::string& text, const std::string& field) {
  const std::string usage = "expected udp:HOST:PORT (e.g. udp:127.0.0.1:14550), got '" + text + "'";
  if (text.rfind("udp:", 0) != 0) throw InputError(field, usage);
  return parse_host_port(text.substr(4), field, usage);
}

UdpLink::UdpLink(const Endpoint& local, std::uint8_t sysid, std::uint8_t compid) : Link(sysid, compid) {
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw std::runtime_error(sys_error("socket"));
  const sockaddr_in a = to_sockaddr(local);
  if (::bind(fd_, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
    const std::string msg = sys_error("bind " + local.host + ":" + std::to_string(local.port));
    ::close(fd_);
    throw std::runtime_error(msg);
  }
  sockaddr_in bound{};
  socklen_t n = sizeof bound;
  ::getsockname(fd_, reinterpret_cast<sockaddr*>(&bound), &n);
  local_port_ = ntohs(bound.sin_port);
}

UdpLink::~UdpLink() {
  if (fd_ >= 0) ::close(fd_);
}

void UdpLink::set_peer(const Endpoint& peer) { peer_ = to_sockaddr(peer); }

bool UdpLink::send_raw(const std::vector<std::uint8_t>& bytes) {
  if (!peer_) return false;
  if (drop()) {
    ++stats_.dropped_tx;
    return true;
  }
  const ssize_t n = ::sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&*peer_),
                             sizeof(sockaddr_in));
  if (n < 0) {
    // ECONNREFUSED & co. (nobody listening yet) behave like a lost datagram.
    if (errno == ECONNREFUSED || errno == EAGAIN || errno == EHOSTUNREACH || errno == ENETUNREACH)
      return true;
    throw std::runtime_error(sys_error("sendto"));
  }
  ++stats_.sent;
  return true;
}

std::string UdpLink::describe() const {
  if (!peer_) return "udpin:0.0.0.0:" + std::to_string(local_port_);
  char host[INET_ADDRSTRLEN] = {};
  inet_ntop(AF_INET, &peer_->sin_addr, host, sizeof host);
  return "udp:" + std::string(host) + ":" + std::to_string(ntohs(peer_->sin_port));
}

bool UdpLink::read_some(std::chrono::milliseconds timeout) {
  pollfd pfd{fd_, POLLIN, 0};
  const int r = ::poll(&pfd, 1, static_cast<int>(timeout.count()));
  if (r < 0) {
    if (errno == EINTR) return false;
    throw std::runtime_error(sys_error("poll"));
  }
  if (r == 0) return false;
  std::uint8_t buf[65536];
  sockaddr_in from{};
  socklen_t fromlen = sizeof from;
  const ssize_t n = ::recvfrom(fd_, buf, sizeof buf, 0, reinterpret_cast<sockaddr*>(&from), &fromlen);
  if (n < 0) {
    if (errno == EINTR || errno == EAGAIN || errno == ECONNREFUSED) return false;
    throw std::runtime_error(sys_error("recvfrom"));
  }
  if (drop()) {
    ++stats_.dropped_rx;
    return false;
  }
  ++stats_.received;
  if (learn_peer_) peer_ = from;
  feed(buf, static_cast<std::size_t>(n), true, from);
  return true;
}

}  // namespace uavcover::mavlink
