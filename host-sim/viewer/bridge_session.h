// One page's WebSocket bridged to its own TCP connection to the node. Both
// directions are a chain of one read and one write at a time, so a slow
// page pushes back on the node's socket (the node then keeps only the
// newest data for it) instead of queueing here.
//
// To a secure node the bridge is the session's client: it runs the Noise
// handshake on the TCP side with the viewer's identity before it reads the
// page's first frame, then seals what the page sends and opens what the
// node sends, so the page sees the same plain frames as from a plain node.
#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "wire/frame.h"
#include "wire/noise/noise_transport.h"

namespace troupe::viewer {

struct ServerState;

class BridgeSession : public std::enable_shared_from_this<BridgeSession> {
 public:
  BridgeSession(boost::asio::ip::tcp::socket page, std::shared_ptr<ServerState> server);
  ~BridgeSession();

  /// Completes the WebSocket handshake of `upgrade`, then connects to the
  /// node and starts copying frames.
  void start(boost::beast::http::request<boost::beast::http::string_body> upgrade);

 private:
  void on_accept(boost::beast::error_code ec);
  void on_connect(boost::beast::error_code ec);
  /// Writes `node_out_` to the node, then goes on with `next`.
  void write_node(void (BridgeSession::*next)());
  /// Secure: opens the node's bytes in `node_raw_` into `node_in_` (the
  /// handshake first). False after failing the session.
  bool open_node_bytes(size_t bytes);
  void read_page();
  void on_page_frame(boost::beast::error_code ec, size_t bytes);
  void read_node();
  void on_node_bytes(boost::beast::error_code ec, size_t bytes);
  void write_page();
  /// Closes the WebSocket with `code` and `reason` (after any write in
  /// flight) and the node connection at once.
  void fail(boost::beast::websocket::close_code code, std::string reason);

  boost::beast::websocket::stream<boost::beast::tcp_stream> page_;
  boost::asio::ip::tcp::socket node_;
  std::shared_ptr<ServerState> server_;
  boost::beast::flat_buffer page_in_;
  wire::FrameReader node_in_;
  /// A secure node's session (nullptr: plain), the node's sealed bytes as
  /// read, and what goes to the node once sealed.
  std::unique_ptr<wire::noise::NoiseTransport> noise_;
  std::vector<uint8_t> node_raw_;
  std::vector<uint8_t> node_out_;
  std::deque<std::vector<uint8_t>> to_page_;
  bool writing_page_ = false;
  bool closing_ = false;
  boost::beast::websocket::close_reason close_;
};

}  // namespace troupe::viewer
