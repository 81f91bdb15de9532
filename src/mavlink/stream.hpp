// MAVLink links over byte streams (Boost.Asio): a TCP connection we open (tcp:HOST:PORT), a TCP listener
// that talks to the last client that connected (tcpin:HOST:PORT), and a serial port
// (serial:DEVICE:BAUD). A stream carries frames split and joined arbitrarily: the frame parser keeps
// partial frames between reads and resynchronises on garbage (frame.hpp).
//
// Every wait is bounded by the caller's timeout: connecting, accepting and reading never block longer,
// so the mission protocol's timeouts and the flight supervisor's loop hold over any transport. A lost
// connection (EOF, reset, unplugged device) is closed; the client reconnects and the serial link reopens
// at most once a second, the listener waits for the next client.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/serial_port.hpp>
#include <chrono>
#include <optional>
#include <string>

#include "mavlink/link.hpp"

namespace uavcover::mavlink {

/// Shared by the stream links: reading a descriptor with poll(), writing all bytes with bounded waits.
class StreamLink : public Link {
 public:
  using Link::Link;
  bool send_raw(const std::vector<std::uint8_t>& bytes) override;
  /// Why the last connection attempt or connection failed ("" if none did).
  [[nodiscard]] const std::string& last_error() const { return last_error_; }

 protected:
  using clock = std::chrono::steady_clock;
  /// The connected descriptor, -1 when there is none.
  [[nodiscard]] virtual int stream_fd() const = 0;
  /// A socket (written with send(MSG_NOSIGNAL)), not a device.
  [[nodiscard]] virtual bool is_socket() const { return true; }
  /// Closes the connection after an error or EOF (`why` goes to last_error()).
  virtual void lost(const std::string& why) = 0;
  /// Reads once from stream_fd() (poll()ed readable); false on EOF/error (then lost() was called).
  bool read_ready();
  /// Waits for stream_fd() to be readable for at most `timeout`, then reads.
  bool read_stream(std::chrono::milliseconds timeout);
  std::string last_error_;
};

/// tcp:HOST:PORT. Connects lazily inside receive() (and again after a loss), at most once a second.
class TcpClientLink final : public StreamLink {
 public:
  TcpClientLink(const Endpoint& remote, std::uint8_t sysid, std::uint8_t compid);
  ~TcpClientLink() override;

  /// Connects now, waiting at most `timeout`; returns "" on success, else why not ("Connection refused").
  std::string connect(std::chrono::milliseconds timeout);
  [[nodiscard]] bool has_peer() const override { return state_ == State::Connected; }
  [[nodiscard]] std::vector<int> poll_handles() const override;
  [[nodiscard]] std::string describe() const override;

 protected:
  bool read_some(std::chrono::milliseconds timeout) override;
  [[nodiscard]] int stream_fd() const override;
  void lost(const std::string& why) override;

 private:
  enum class State { Idle, Connecting, Connected };
  void start_connect();
  void progress(std::chrono::milliseconds timeout);

  Endpoint remote_;
  boost::asio::io_context io_;
  boost::asio::ip::tcp::socket socket_;
  State state_ = State::Idle;
  clock::time_point next_try_{};
};

/// tcpin:HOST:PORT. Listens at construction (port 0: any free port); a new client replaces the current one
/// (a ground station that reconnects after a crash leaves a half-open connection behind).
class TcpListenLink final : public StreamLink {
 public:
  TcpListenLink(const Endpoint& local, std::uint8_t sysid, std::uint8_t compid);
  ~TcpListenLink() override;

  [[nodiscard]] bool has_peer() const override { return client_.is_open(); }
  [[nodiscard]] std::vector<int> poll_handles() const override;
  [[nodiscard]] std::uint16_t local_port() const override { return local_port_; }
  [[nodiscard]] std::string describe() const override;

 protected:
  bool read_some(std::chrono::milliseconds timeout) override;
  [[nodiscard]] int stream_fd() const override;
  void lost(const std::string& why) override;

 private:
  void accept_pending();

  Endpoint local_;
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  boost::asio::ip::tcp::socket client_;
  std::uint16_t local_port_ = 0;
};

/// serial:DEVICE:BAUD, 8 data bits, no parity, one stop bit, no flow control, raw. Opens at construction
/// (std::runtime_error naming the device if it cannot); reopens after the device went away.
class SerialLink final : public StreamLink {
 public:
  SerialLink(const std::string& device, unsigned baud, std::uint8_t sysid, std::uint8_t compid);
  ~SerialLink() override;

  [[nodiscard]] bool has_peer() const override { return port_.is_open(); }
  [[nodiscard]] std::vector<int> poll_handles() const override;
  [[nodiscard]] std::string describe() const override;

 protected:
  bool read_some(std::chrono::milliseconds timeout) override;
  [[nodiscard]] int stream_fd() const override;
  [[nodiscard]] bool is_socket() const override { return false; }
  void lost(const std::string& why) override;

 private:
  void open();

  std::string device_;
  unsigned baud_;
  boost::asio::io_context io_;
  boost::asio::serial_port port_;
  clock::time_point next_try_{};
};

}  // namespace uavcover::mavlink
