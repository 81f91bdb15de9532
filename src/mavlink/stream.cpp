#include "mavlink/stream.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <boost/asio/connect.hpp>
#include <boost/system/system_error.hpp>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <thread>

namespace uavcover::mavlink {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;
using namespace std::chrono_literals;

namespace {

constexpr auto kRetryPeriod = 1s;       // reconnect / reopen at most this often
constexpr auto kWriteTimeout = 1000ms;  // a peer that reads nothing for this long: connection lost

tcp::endpoint to_asio(const Endpoint& e) {
  boost::system::error_code ec;
  const auto addr = asio::ip::make_address_v4(e.host == "localhost" ? "127.0.0.1" : e.host, ec);
  if (ec) throw std::runtime_error("not an IPv4 address: '" + e.host + "'");
  return {addr, e.port};
}

int poll_ms(std::chrono::milliseconds t) {
  return static_cast<int>(std::clamp<long long>(t.count(), 0, 60'000));
}

void sleep_for_at_most(std::chrono::milliseconds t, std::chrono::steady_clock::time_point until) {
  const auto left =
      std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now());
  const auto d = std::min(t, left);
  if (d.count() > 0) std::this_thread::sleep_for(d);
}

}  // namespace

// ---- StreamLink ----

bool StreamLink::send_raw(const std::vector<std::uint8_t>& bytes) {
  if (!has_peer()) return false;
  if (drop()) {
    ++stats_.dropped_tx;
    return true;
  }
  std::size_t done = 0;
  const auto deadline = clock::now() + kWriteTimeout;
  while (done < bytes.size()) {
    const int fd = stream_fd();
    if (fd < 0) return true;  // lost meanwhile: like a lost datagram
    // sockets: send() without SIGPIPE (a peer that went away must not kill the process)
    const ssize_t n = is_socket() ? ::send(fd, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL)
                                  : ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - clock::now());
      pollfd pfd{fd, POLLOUT, 0};
      if (left.count() <= 0 || ::poll(&pfd, 1, poll_ms(left)) <= 0) {
        lost("the peer reads nothing: write timed out");
        return true;
      }
      continue;
    }
    lost(std::string("write: ") + std::strerror(errno));
    return true;
  }
  ++stats_.sent;
  return true;
}

bool StreamLink::read_ready() {
  const int fd = stream_fd();
  if (fd < 0) return false;
  std::uint8_t buf[4096];
  const ssize_t n = ::read(fd, buf, sizeof buf);
  if (n > 0) {
    ++stats_.received;
    feed(buf, static_cast<std::size_t>(n), false, sockaddr_in{});
    return true;
  }
  if (n < 0 && (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK)) return false;
  lost(n == 0 ? "closed by the peer" : std::string("read: ") + std::strerror(errno));
  return false;
}

bool StreamLink::read_stream(std::chrono::milliseconds timeout) {
  const int fd = stream_fd();
  if (fd < 0) return false;
  pollfd pfd{fd, POLLIN, 0};
  const int r = ::poll(&pfd, 1, poll_ms(timeout));
  if (r <= 0) return false;
  return read_ready();
}

// ---- TcpClientLink ----

TcpClientLink::TcpClientLink(const Endpoint& remote, std::uint8_t sysid, std::uint8_t compid)
    : StreamLink(sysid, compid), remote_(remote), socket_(io_) {
  (void)to_asio(remote_);  // a bad address is said now, not at the first connect
}

TcpClientLink::~TcpClientLink() {
  boost::system::error_code ec;
  socket_.close(ec);
  io_.restart();
  io_.poll();  // completes a cancelled connect's handler
}

std::string TcpClientLink::describe() const {
  return "tcp:" + remote_.host + ":" + std::to_string(remote_.port);
}

int TcpClientLink::stream_fd() const {
  return state_ == State::Connected ? static_cast<int>(const_cast<tcp::socket&>(socket_).native_handle())
                                    : -1;
}

std::vector<int> TcpClientLink::poll_handles() const {
  if (state_ == State::Idle) return {};
  return {static_cast<int>(const_cast<tcp::socket&>(socket_).native_handle())};
}

void TcpClientLink::start_connect() {
  state_ = State::Connecting;
  next_try_ = clock::now() + kRetryPeriod;
  boost::system::error_code ec;
  socket_.close(ec);
  socket_.async_connect(to_asio(remote_), [this](const boost::system::error_code& e) {
    if (state_ != State::Connecting) return;
    if (e) {
      last_error_ = e.message();
      boost::system::error_code ignored;
      socket_.close(ignored);
      state_ = State::Idle;
      return;
    }
    boost::system::error_code opt;
    socket_.set_option(tcp::no_delay(true), opt);
    socket_.non_blocking(true, opt);
    state_ = State::Connected;
    last_error_.clear();
    ++stats_.connections;
  });
}

void TcpClientLink::progress(std::chrono::milliseconds timeout) {
  io_.restart();
  io_.run_for(timeout);
}

std::string TcpClientLink::connect(std::chrono::milliseconds timeout) {
  if (state_ == State::Connected) return "";
  if (state_ == State::Idle) start_connect();
  const auto deadline = clock::now() + timeout;
  while (state_ == State::Connecting && clock::now() < deadline)
    progress(std::chrono::duration_cast<std::chrono::milliseconds>(deadline - clock::now()));
  if (state_ == State::Connected) return "";
  if (state_ == State::Connecting) {  // give up this attempt
    boost::system::error_code ec;
    state_ = State::Idle;
    socket_.close(ec);
    io_.restart();
    io_.poll();
    last_error_ = "connection timed out";
  }
  return last_error_;
}

void TcpClientLink::lost(const std::string& why) {
  if (state_ == State::Connected) ++stats_.disconnects;
  last_error_ = why;
  boost::system::error_code ec;
  socket_.close(ec);
  state_ = State::Idle;
}

bool TcpClientLink::read_some(std::chrono::milliseconds timeout) {
  const auto deadline = clock::now() + timeout;
  if (state_ == State::Idle) {
    if (clock::now() < next_try_) {
      sleep_for_at_most(timeout, next_try_);
      return false;
    }
    start_connect();
  }
  if (state_ == State::Connecting) {
    progress(timeout);
    if (state_ != State::Connected) {
      if (state_ == State::Idle) sleep_for_at_most(timeout, deadline);  // refused: wait out the timeout
      return false;
    }
  }
  return read_stream(std::chrono::duration_cast<std::chrono::milliseconds>(deadline - clock::now()));
}

// ---- TcpListenLink ----

TcpListenLink::TcpListenLink(const Endpoint& local, std::uint8_t sysid, std::uint8_t compid)
    : StreamLink(sysid, compid), local_(local), acceptor_(io_), client_(io_) {
  try {
    const auto ep = to_asio(local);
    acceptor_.open(ep.protocol());
    acceptor_.set_option(tcp::acceptor::reuse_address(true));
    acceptor_.bind(ep);
    acceptor_.listen();
    acceptor_.non_blocking(true);
    local_port_ = acceptor_.local_endpoint().port();
  } catch (const boost::system::system_error& e) {
    throw std::runtime_error("listen on " + local.host + ":" + std::to_string(local.port) + ": " +
                             e.code().message());
  }
}

TcpListenLink::~TcpListenLink() {
  boost::system::error_code ec;
  client_.close(ec);
  acceptor_.close(ec);
}

std::string TcpListenLink::describe() const {
  return "tcpin:" + local_.host + ":" + std::to_string(local_port_);
}

int TcpListenLink::stream_fd() const {
  return client_.is_open() ? static_cast<int>(const_cast<tcp::socket&>(client_).native_handle()) : -1;
}

std::vector<int> TcpListenLink::poll_handles() const {
  std::vector<int> out{static_cast<int>(const_cast<tcp::acceptor&>(acceptor_).native_handle())};
  if (client_.is_open()) out.push_back(stream_fd());
  return out;
}

void TcpListenLink::lost(const std::string& why) {
  if (client_.is_open()) ++stats_.disconnects;
  last_error_ = why;
  boost::system::error_code ec;
  client_.close(ec);
}

void TcpListenLink::accept_pending() {
  boost::system::error_code ec;
  tcp::socket next(io_);
  acceptor_.accept(next, ec);
  if (ec) return;  // would_block, or the client went away already
  if (client_.is_open()) lost("replaced by a new connection");
  client_ = std::move(next);
  client_.set_option(tcp::no_delay(true), ec);
  client_.non_blocking(true, ec);
  ++stats_.connections;
}

bool TcpListenLink::read_some(std::chrono::milliseconds timeout) {
  pollfd fds[2] = {{static_cast<int>(acceptor_.native_handle()), POLLIN, 0}, {stream_fd(), POLLIN, 0}};
  const nfds_t n = fds[1].fd >= 0 ? 2 : 1;
  const int r = ::poll(fds, n, poll_ms(timeout));
  if (r <= 0) return false;
  if (fds[0].revents & POLLIN) accept_pending();
  if (n == 2 && (fds[1].revents & (POLLIN | POLLHUP | POLLERR)) && stream_fd() == fds[1].fd)
    return read_ready();
  return false;
}

// ---- SerialLink ----

SerialLink::SerialLink(const std::string& device, unsigned baud, std::uint8_t sysid, std::uint8_t compid)
    : StreamLink(sysid, compid), device_(device), baud_(baud), port_(io_) {
  open();
  if (!port_.is_open()) throw std::runtime_error("cannot open " + device_ + ": " + last_error_);
}

SerialLink::~SerialLink() {
  boost::system::error_code ec;
  port_.close(ec);
}

std::string SerialLink::describe() const { return "serial:" + device_ + ":" + std::to_string(baud_); }

void SerialLink::open() {
  next_try_ = clock::now() + kRetryPeriod;
  try {
    port_.open(device_);
    port_.set_option(asio::serial_port_base::baud_rate(baud_));
    port_.set_option(asio::serial_port_base::character_size(8));
    port_.set_option(asio::serial_port_base::parity(asio::serial_port_base::parity::none));
    port_.set_option(asio::serial_port_base::stop_bits(asio::serial_port_base::stop_bits::one));
    port_.set_option(asio::serial_port_base::flow_control(asio::serial_port_base::flow_control::none));
    // reads and writes go through poll() with our timeouts, never a blocking call
    const int fd = port_.native_handle();
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
    ++stats_.connections;
    last_error_.clear();
  } catch (const boost::system::system_error& e) {
    last_error_ = e.code().message();
    boost::system::error_code ec;
    port_.close(ec);
  }
}

int SerialLink::stream_fd() const {
  return port_.is_open() ? static_cast<int>(const_cast<asio::serial_port&>(port_).native_handle()) : -1;
}

std::vector<int> SerialLink::poll_handles() const {
  if (!port_.is_open()) return {};
  return {stream_fd()};
}

void SerialLink::lost(const std::string& why) {
  if (port_.is_open()) ++stats_.disconnects;
  last_error_ = why;
  boost::system::error_code ec;
  port_.close(ec);
}

bool SerialLink::read_some(std::chrono::milliseconds timeout) {
  if (!port_.is_open()) {
    if (clock::now() < next_try_) {
      sleep_for_at_most(timeout, next_try_);
      return false;
    }
    open();
    if (!port_.is_open()) return false;
  }
  return read_stream(timeout);
}

}  // namespace uavcover::mavlink
