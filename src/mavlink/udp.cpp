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
  const std::string rest = text.substr(4);
  const auto colon = rest.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == rest.size()) throw InputError(field, usage);
  Endpoint e;
  e.host = rest.substr(0, colon);
  const std::string port = rest.substr(colon + 1);
  unsigned value = 0;
  const auto [ptr, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
  if (ec != std::errc{} || ptr != port.data() + port.size() || value == 0 || value > 65535)
    throw InputError(field, "port must be an integer in 1..65535, got '" + port + "'");
  e.port = static_cast<std::uint16_t>(value);
  in_addr tmp{};
  if (e.host != "localhost" && inet_pton(AF_INET, e.host.c_str(), &tmp) != 1)
    throw InputError(field, "host must be a dotted IPv4 address or 'localhost', got '" + e.host + "'");
  return e;
}

UdpLink::UdpLink(const Endpoint& local, std::uint8_t sysid, std::uint8_t compid)
    : sysid_(sysid), compid_(compid) {
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

void UdpLink::set_loss(double p, std::uint64_t seed) {
  loss_ = p;
  rng_.seed(seed);
}

bool UdpLink::drop() {
  if (loss_ <= 0.0) return false;
  return std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < loss_;
}

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

bool UdpLink::send(const Message& m) {
  if (!peer_) return false;
  Header h;
  h.seq = seq_++;
  h.sysid = sysid_;
  h.compid = compid_;
  return send_raw(encode(m, h));
}

std::optional<Received> UdpLink::receive(std::chrono::milliseconds timeout) {
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
    pollfd pfd{fd_, POLLIN, 0};
    const int r = ::poll(&pfd, 1, static_cast<int>(left.count()));
    if (r < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(sys_error("poll"));
    }
    if (r == 0) {
      if (clock::now() >= deadline) return std::nullopt;
      continue;
    }
    std::uint8_t buf[65536];
    sockaddr_in from{};
    socklen_t fromlen = sizeof from;
    const ssize_t n = ::recvfrom(fd_, buf, sizeof buf, 0, reinterpret_cast<sockaddr*>(&from), &fromlen);
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN || errno == ECONNREFUSED) continue;
      throw std::runtime_error(sys_error("recvfrom"));
    }
    if (drop()) {
      ++stats_.dropped_rx;
      continue;
    }
    ++stats_.received;
    if (learn_peer_) peer_ = from;
    std::vector<Frame> frames;
    parser_.push(std::span<const std::uint8_t>(buf, static_cast<std::size_t>(n)), frames, true);
    for (auto& f : frames) {
      pending_.push_back(std::move(f));
      pending_from_.push_back(from);
    }
  }
}

}  // namespace uavcover::mavlink
