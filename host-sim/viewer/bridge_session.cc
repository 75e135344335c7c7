#include "host-sim/viewer/bridge_session.h"

#include <boost/asio/connect.hpp>
#include <boost/asio/write.hpp>

#include "host-sim/viewer/server_state.h"
#include "runtime/log.h"

namespace troupe::viewer {
namespace {

// The node's sealed bytes read at once, bytes (a Noise message is at most
// 65,537 with its length; the session reassembles across reads).
constexpr size_t kSealedReadBytes = 16 * 1024;

}  // namespace

namespace beast = boost::beast;
namespace websocket = beast::websocket;
using boost::asio::ip::tcp;

BridgeSession::BridgeSession(tcp::socket page, std::shared_ptr<ServerState> server)
    : page_(std::move(page)),
      node_(page_.get_executor()),
      server_(std::move(server)),
      node_in_(server_->options.limits.max_frame_bytes) {
  ++server_->sessions;
  if (server_->secure) {
    noise_ = std::make_unique<wire::noise::NoiseTransport>(*server_->secure);
    node_raw_.resize(kSealedReadBytes);
  }
}

BridgeSession::~BridgeSession() {
  --server_->sessions;
}

void BridgeSession::start(beast::http::request<beast::http::string_body> upgrade) {
  beast::get_lowest_layer(page_).expires_never();
  page_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  // A message over the frame limit is refused by the WebSocket layer
  // before it is buffered (close code 1009).
  page_.read_message_max(server_->options.limits.max_frame_bytes);
  page_.binary(true);
  page_.async_accept(upgrade, beast::bind_front_handler(&BridgeSession::on_accept, shared_from_this()));
}

void BridgeSession::on_accept(beast::error_code ec) {
  if (ec) return;  // not a WebSocket after all; the socket just closes
  // Tries every address the node's name resolved to, in order, until one
  // connects (localhost: ::1 and 127.0.0.1 on a standard Debian).
  boost::asio::async_connect(node_, server_->node,
                             [self = shared_from_this()](beast::error_code connect_ec, const tcp::endpoint&) {
                               self->on_connect(connect_ec);
                             });
}

void BridgeSession::on_connect(beast::error_code ec) {
  if (ec) {
    const ViewOptions& o = server_->options;
    return fail(websocket::close_code::try_again_later,
                "cannot reach the node at " + o.node_host + ":" + std::to_string(o.node_port));
  }
  node_.set_option(tcp::no_delay(true));
  if (noise_) {
    // The page's frames wait (in its socket) until the session is up.
    node_out_.clear();
    noise_->begin(node_out_);
    return write_node(&BridgeSession::read_node);
  }
  read_page();
  read_node();
}

void BridgeSession::write_node(void (BridgeSession::*next)()) {
  boost::asio::async_write(node_, boost::asio::buffer(node_out_),
                           [self = shared_from_this(), next](beast::error_code write_ec, size_t) {
                             if (write_ec)
                               return self->fail(websocket::close_code::going_away, "node connection lost");
                             ((*self).*next)();
                           });
}

bool BridgeSession::open_node_bytes(size_t bytes) {
  const bool was_ready = noise_->ready();
  std::vector<uint8_t> reply;
  std::string error;
  if (!noise_->inbound(std::span<const uint8_t>(node_raw_.data(), bytes), node_in_, reply, error)) {
    fail(websocket::close_code::policy_error, "secure session failed: " + error);
    return false;
  }
  // IK's initiator has nothing to answer to message 2: the session is up.
  if (!was_ready && noise_->ready()) {
    log_info("viewer: secure session with the node (key %s)", noise_->peer_identity().c_str());
    read_page();
  }
  return true;
}

void BridgeSession::read_page() {
  page_.async_read(page_in_, beast::bind_front_handler(&BridgeSession::on_page_frame, shared_from_this()));
}

void BridgeSession::on_page_frame(beast::error_code ec, size_t bytes) {
  if (ec) {
    // The page left (or broke the WebSocket rules): drop its node connection.
    if (ec == websocket::error::message_too_big) {
      return fail(websocket::close_code::too_big, "frame over the limit");
    }
    closing_ = true;
    beast::error_code ignored;
    node_.close(ignored);
    return;
  }
  if (closing_) return;
  const std::span<const uint8_t> frame(static_cast<const uint8_t*>(page_in_.data().data()), bytes);
  // One message must be exactly one frame: its prefix, then that many bytes.
  if (!page_.got_binary()) return fail(websocket::close_code::bad_payload, "frames are binary messages");
  if (frame.size() < wire::kPrefixBytes ||
      wire::read_prefix(frame.data()) != frame.size() - wire::kPrefixBytes) {
    return fail(websocket::close_code::bad_payload, "a message must be one size-prefixed frame");
  }
  wire::VerifyError why = wire::VerifyError::None;
  if (wire::verify_frame(frame, server_->options.limits, &why) == nullptr) {
    return fail(websocket::close_code::bad_payload,
                "frame refused: " + std::string(wire::verify_error_text(why)));
  }
  if (noise_) {
    node_out_.clear();
    noise_->outbound(frame, node_out_);
    page_in_.clear();
    return write_node(&BridgeSession::read_page);
  }
  boost::asio::async_write(node_, boost::asio::buffer(frame.data(), frame.size()),
                           [self = shared_from_this()](beast::error_code write_ec, size_t) {
                             self->page_in_.clear();
                             if (write_ec)
                               return self->fail(websocket::close_code::going_away, "node connection lost");
                             self->read_page();
                           });
}

void BridgeSession::read_node() {
  if (noise_) {
    node_.async_read_some(boost::asio::buffer(node_raw_),
                          beast::bind_front_handler(&BridgeSession::on_node_bytes, shared_from_this()));
    return;
  }
  const std::span<uint8_t> space = node_in_.write_space();
  node_.async_read_some(boost::asio::buffer(space.data(), space.size()),
                        beast::bind_front_handler(&BridgeSession::on_node_bytes, shared_from_this()));
}

void BridgeSession::on_node_bytes(beast::error_code ec, size_t bytes) {
  if (ec || closing_) {
    if (closing_) return;
    // A secure node answers nothing to a handshake it refuses.
    if (noise_ && !noise_->ready()) {
      return fail(websocket::close_code::policy_error,
                  "the node refused the secure session: it does not accept our key, or does not hold the key "
                  "we know for it");
    }
    return fail(websocket::close_code::going_away, "the node closed the connection");
  }
  if (noise_) {
    if (!open_node_bytes(bytes)) return;
  } else {
    node_in_.commit(bytes);
  }
  for (std::span<const uint8_t> f = node_in_.next(); !f.empty(); f = node_in_.next()) {
    to_page_.emplace_back(f.begin(), f.end());
  }
  if (node_in_.too_large())
    return fail(websocket::close_code::too_big, "the node sent a frame over the limit");
  if (to_page_.empty()) return read_node();
  write_page();
}

void BridgeSession::write_page() {
  if (to_page_.empty()) {
    if (closing_) {
      page_.async_close(close_, [self = shared_from_this()](beast::error_code) {});
      return;
    }
    return read_node();  // everything read has been passed on: read more
  }
  writing_page_ = true;
  page_.async_write(boost::asio::buffer(to_page_.front()),
                    [self = shared_from_this()](beast::error_code ec, size_t) {
                      self->writing_page_ = false;
                      self->to_page_.pop_front();
                      if (ec) {
                        self->closing_ = true;
                        self->to_page_.clear();
                        beast::error_code ignored;
                        self->node_.close(ignored);
                        return;
                      }
                      if (self->closing_) self->to_page_.clear();
                      self->write_page();
                    });
}

void BridgeSession::fail(websocket::close_code code, std::string reason) {
  if (closing_) return;
  closing_ = true;
  log_warn("viewer: closing a page's connection: %s", reason.c_str());
  // A close frame's reason holds at most 123 bytes.
  if (reason.size() > 123) reason.resize(123);
  close_ = websocket::close_reason(code, reason);
  beast::error_code ignored;
  node_.close(ignored);
  if (writing_page_) return;  // the write's completion closes (its buffer is still in use)
  to_page_.clear();
  page_.async_close(close_, [self = shared_from_this()](beast::error_code) {});
}

}  // namespace troupe::viewer
