// The WebSocket session of /api/v1/events: job and flight events to a subscribing client.
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

class WsSession : public Session, public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(tcp::socket&& socket, Core& core) : ws_(std::move(socket)), core_(core) {}
  ~WsSession() override {
    core_.hub.close(sub_);
    core_.remove_session(reg_);
  }

  void start(http::request<http::string_body> req, const std::string& request_id) {
    reg_ = core_.add_session(weak_from_this());
    if (reg_ == 0) return;  // closing: the socket goes with this object
    req_ = std::move(req);
    beast::get_lowest_layer(ws_).expires_never();
    websocket::stream_base::timeout t{};
    t.handshake_timeout =
        std::max<std::chrono::steady_clock::duration>(core_.cfg.header_timeout, std::chrono::seconds(1));
    t.idle_timeout = std::chrono::seconds(60);
    t.keep_alive_pings = true;
    ws_.set_option(t);
    ws_.read_message_max(kWsMessageMax);
    const auto cors = core_.cfg.cors_origin;
    ws_.set_option(websocket::stream_base::decorator([request_id, cors](websocket::response_type& res) {
      res.set(http::field::server, "uavcover");
      res.set("X-Request-Id", request_id);
      if (cors) res.set("Access-Control-Allow-Origin", *cors);
    }));
    ws_.async_accept(req_, beast::bind_front_handler(&WsSession::on_accept, shared_from_this()));
  }

  void shutdown() override {
    net::post(ws_.get_executor(), [self = shared_from_this()] { self->close_now(); });
  }

 private:
  void on_accept(beast::error_code ec) {
    if (ec) return;
    std::weak_ptr<WsSession> weak = weak_from_this();
    sub_ = core_.hub.open([weak](const std::string& message) {
      const auto self = weak.lock();
      if (!self) return false;
      net::post(self->ws_.get_executor(), [self, message] { self->enqueue(message); });
      return true;
    });
    do_read();
  }

  void do_read() {
    ws_.async_read(buffer_, beast::bind_front_handler(&WsSession::on_read, shared_from_this()));
  }

  void on_read(beast::error_code ec, std::size_t) {
    if (ec) return close_now();
    const std::string text = beast::buffers_to_string(buffer_.data());
    buffer_.consume(buffer_.size());
    handle(text);
    if (!closed_) do_read();
  }

  void handle(const std::string& text) {
    const std::size_t max = static_cast<std::size_t>(std::max(0, core_.cfg.max_subscriptions));
    const ClientMessage msg = parse_client_message(text, max);
    switch (msg.op) {
      case ClientMessage::Op::Invalid:
        return enqueue(error_message(msg.error_field, msg.error_message));
      case ClientMessage::Op::Unsubscribe:
        core_.hub.unsubscribe(sub_, msg.jobs);
        return core_.hub.unsubscribe_flights(sub_, msg.flights);
      case ClientMessage::Op::Subscribe:
        if (!core_.hub.subscribe(sub_, msg.jobs, max))
          enqueue(error_message("subscribe.jobs",
                                fmt::format("at most {} job subscriptions per connection", max)));
        if (!core_.hub.subscribe_flights(sub_, msg.flights, max))
          enqueue(error_message("subscribe.flights",
                                fmt::format("at most {} flight subscriptions per connection", max)));
        return;
    }
  }

  void enqueue(const std::string& message) {
    if (closed_) return;
    // a message larger than the cap still goes out alone; behind others it must fit
    if (queue_.size() >= kMaxPendingMessages ||
        (!queue_.empty() && queued_bytes_ + message.size() > core_.cfg.max_event_queue_bytes)) {
      spdlog::warn("events: closing a WebSocket client that does not read ({} messages, {} bytes pending)",
                   queue_.size(), queued_bytes_);
      metrics().count_dropped_event_client();
      return close_now(websocket::close_code::try_again_later);
    }
    queued_bytes_ += message.size();
    queue_.push_back(message);
    if (!writing_) do_write();
  }

  void do_write() {
    writing_ = true;
    ws_.text(true);
    ws_.async_write(net::buffer(queue_.front()),
                    beast::bind_front_handler(&WsSession::on_write, shared_from_this()));
  }

  void on_write(beast::error_code ec, std::size_t) {
    writing_ = false;
    if (ec) return close_now();
    if (closed_) return;
    queued_bytes_ -= queue_.front().size();
    queue_.pop_front();
    if (!queue_.empty()) do_write();
  }

  void close_now(websocket::close_code code = websocket::close_code::going_away) {
    if (closed_) return;
    closed_ = true;
    core_.hub.close(sub_);
    // the message being written stays until its write completes
    if (!writing_)
      queue_.clear();
    else if (!queue_.empty())
      queue_.erase(std::next(queue_.begin()), queue_.end());
    queued_bytes_ = queue_.empty() ? 0 : queue_.front().size();
    if (!writing_ && ws_.is_open()) {
      // a close frame when nothing is being written; the socket goes when the close completes
      ws_.async_close(code, [self = shared_from_this()](beast::error_code) {
        beast::error_code ignored;
        beast::get_lowest_layer(self->ws_).socket().close(ignored);
      });
      return;
    }
    beast::get_lowest_layer(ws_).close();
  }

  websocket::stream<beast::tcp_stream> ws_;
  Core& core_;
  http::request<http::string_body> req_;
  beast::flat_buffer buffer_;
  std::deque<std::string> queue_;
  std::size_t queued_bytes_ = 0;  ///< the bytes in queue_ (the event queue cap)
  bool writing_ = false;
  bool closed_ = false;
  std::uint64_t sub_ = 0;
  std::uint64_t reg_ = 0;
};

}  // namespace

void start_websocket(tcp::socket&& socket, Core& core, http::request<http::string_body> req,
                     const std::string& request_id) {
  std::make_shared<WsSession>(std::move(socket), core)->start(std::move(req), request_id);
}

}  // namespace uavcover::server::detail
