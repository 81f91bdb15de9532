// The Server-Sent Events session of /api/v1/events?jobs=...: the events of the jobs a client names.
#include <boost/asio/dispatch.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/websocket.hpp>

#include <array>
#include <deque>

#include "server/session_internal.hpp"
#include "uavcover/error.hpp"

namespace uavcover::server::detail {

namespace {

class SseSession : public Session, public std::enable_shared_from_this<SseSession> {
 public:
  SseSession(tcp::socket&& socket, Core& core)
      : stream_(std::move(socket)), core_(core), timer_(stream_.get_executor()) {}
  ~SseSession() override {
    core_.hub.close(sub_);
    core_.remove_session(reg_);
  }

  void start(unsigned version, std::vector<std::int64_t> ids, const std::string& request_id) {
    reg_ = core_.add_session(weak_from_this());
    if (reg_ == 0) return;
    ids_ = std::move(ids);
    chunked_ = version >= 11;
    stream_.expires_never();
    auto res = std::make_shared<http::response<http::empty_body>>(http::status::ok, version);
    res->set(http::field::server, "uavcover");
    res->set(http::field::content_type, "text/event-stream");
    res->set(http::field::cache_control, "no-cache");
    res->set("X-Accel-Buffering", "no");
    res->set("X-Request-Id", request_id);
    if (core_.cfg.cors_origin) {
      res->set(http::field::access_control_allow_origin, *core_.cfg.cors_origin);
      res->set(http::field::vary, "Origin");
    }
    if (chunked_)
      res->chunked(true);
    else
      res->keep_alive(false);
    auto sr = std::make_shared<http::response_serializer<http::empty_body>>(*res);
    writing_ = true;
    http::async_write_header(
        stream_, *sr,
        [self = shared_from_this(), res, sr](beast::error_code ec, std::size_t) { self->on_header(ec); });
  }

  void shutdown() override {
    net::post(stream_.get_executor(), [self = shared_from_this()] {
      self->stopping_ = true;
      if (!self->writing_) self->finish_stream();
    });
  }

 private:
  void on_header(beast::error_code ec) {
    writing_ = false;
    if (ec) return close_now();
    if (stopping_) return finish_stream();
    std::weak_ptr<SseSession> weak = weak_from_this();
    sub_ = core_.hub.open([weak](const std::string& message) {
      const auto self = weak.lock();
      if (!self) return false;
      net::post(self->stream_.get_executor(),
                [self, message] { self->enqueue("event: job\ndata: " + message + "\n\n"); });
      return true;
    });
    core_.hub.subscribe(sub_, ids_, ids_.size());
    arm_keepalive();
    watch_peer();
  }

  void arm_keepalive() {
    timer_.expires_after(core_.cfg.sse_keepalive);
    timer_.async_wait([self = shared_from_this()](beast::error_code ec) {
      if (ec || self->closed_) return;
      self->enqueue(": keepalive\n\n");
      self->arm_keepalive();
    });
  }

  // The client never sends anything: a read completes only when it goes away.
  void watch_peer() {
    stream_.async_read_some(net::buffer(scratch_),
                            [self = shared_from_this()](beast::error_code ec, std::size_t) {
                              if (ec) return self->close_now();
                              self->watch_peer();
                            });
  }

  void enqueue(std::string record) {
    if (closed_ || stopping_) return;
    if (queue_.size() >= kMaxPendingMessages ||
        (!queue_.empty() && queued_bytes_ + record.size() > core_.cfg.max_event_queue_bytes)) {
      spdlog::warn("events: closing an SSE client that does not read ({} records, {} bytes pending)",
                   queue_.size(), queued_bytes_);
      metrics().count_dropped_event_client();
      return close_now();
    }
    queued_bytes_ += record.size();
    queue_.push_back(std::move(record));
    if (!writing_) do_write();
  }

  void do_write() {
    writing_ = true;
    auto done = [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_write(ec); };
    if (chunked_)
      net::async_write(stream_, http::make_chunk(net::buffer(queue_.front())), std::move(done));
    else
      net::async_write(stream_, net::buffer(queue_.front()), std::move(done));
  }

  void on_write(beast::error_code ec) {
    writing_ = false;
    if (ec) return close_now();
    if (closed_) return;
    queued_bytes_ -= queue_.front().size();
    queue_.pop_front();
    if (stopping_) return finish_stream();
    if (!queue_.empty()) do_write();
  }

  // On server stop: the last chunk, then the connection closes.
  void finish_stream() {
    if (closed_) return;
    core_.hub.close(sub_);
    timer_.cancel();
    if (!chunked_) return close_now();
    queue_.clear();  // nothing is being written (the callers check)
    queued_bytes_ = 0;
    writing_ = true;
    net::async_write(stream_, http::make_chunk_last(),
                     [self = shared_from_this()](beast::error_code, std::size_t) { self->close_now(); });
  }

  void close_now() {
    if (closed_) return;
    closed_ = true;
    core_.hub.close(sub_);
    timer_.cancel();
    if (!writing_)
      queue_.clear();
    else if (!queue_.empty())
      queue_.erase(std::next(queue_.begin()), queue_.end());
    queued_bytes_ = queue_.empty() ? 0 : queue_.front().size();
    beast::error_code ec;
    stream_.socket().shutdown(tcp::socket::shutdown_both, ec);
    stream_.close();
  }

  beast::tcp_stream stream_;
  Core& core_;
  net::steady_timer timer_;
  std::vector<std::int64_t> ids_;
  std::deque<std::string> queue_;
  std::size_t queued_bytes_ = 0;
  std::array<char, 256> scratch_{};
  bool chunked_ = true;
  bool writing_ = false;
  bool stopping_ = false;
  bool closed_ = false;
  std::uint64_t sub_ = 0;
  std::uint64_t reg_ = 0;
};

}  // namespace

void start_sse(tcp::socket&& socket, Core& core, unsigned version, std::vector<std::int64_t> ids,
               const std::string& request_id) {
  std::make_shared<SseSession>(std::move(socket), core)->start(version, std::move(ids), request_id);
}

}  // namespace uavcover::server::detail
