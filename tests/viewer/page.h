// A WebSocket client that speaks the wire protocol through the viewer's
// bridge, as the page does: the bridge tests' stand-in for the browser.
#pragma once

#include <gtest/gtest.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "wire/frame.h"

namespace troupe::viewer {

namespace page_detail {
namespace net = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using net::ip::tcp;

// Everything a test waits for is a socket event; this only bounds a broken run.
constexpr auto kDeadline = std::chrono::seconds(30);

// A WebSocket client that speaks the wire protocol, as the page does.
class Page {
 public:
  explicit Page(uint16_t port) : ws_(io_) {
    tcp::resolver resolver(io_);
    net::connect(ws_.next_layer(), resolver.resolve("127.0.0.1", std::to_string(port)));
    ws_.handshake("127.0.0.1", "/ws");
    ws_.binary(true);
  }

  void send(std::span<const uint8_t> frame) { ws_.write(net::buffer(frame.data(), frame.size())); }

  /// The next message; nullopt when the WebSocket closed (see close_code()).
  std::optional<std::vector<uint8_t>> read() {
    beast::flat_buffer buf;
    beast::error_code ec;
    bool done = false;
    ws_.async_read(buf, [&](beast::error_code e, size_t) {
      ec = e;
      done = true;
    });
    io_.restart();
    io_.run_for(kDeadline);
    if (!done) {
      ws_.next_layer().cancel();
      io_.restart();
      io_.run();
      ADD_FAILURE() << "no message within the deadline";
      return std::nullopt;
    }
    if (ec) return std::nullopt;
    const auto* p = static_cast<const uint8_t*>(buf.data().data());
    return std::vector<uint8_t>(p, p + buf.size());
  }

  /// Reads until the reply with `seq` (Ack, Nack or DeviceList); data and the
  /// node's Hello are skipped. Returns the frame (empty on close).
  std::vector<uint8_t> reply(uint32_t seq) {
    while (auto f = read()) {
      const wire::Message* m = wire::verify_frame(*f, {});
      if (m == nullptr) {
        ADD_FAILURE() << "the bridge passed a frame that does not verify";
        return {};
      }
      const wire::Kind k = m->header()->kind();
      if ((k == wire::Kind::Ack || k == wire::Kind::Nack || k == wire::Kind::DeviceList) &&
          m->header()->seq() == seq) {
        return *f;
      }
    }
    return {};
  }

  /// Reads until a Data frame with this body type.
  std::vector<uint8_t> data(wire::Body type) {
    while (auto f = read()) {
      const wire::Message* m = wire::verify_frame(*f, {});
      if (m && m->header()->kind() == wire::Kind::Data && m->body_type() == type) return *f;
    }
    return {};
  }

  /// Reads (the node's Hello may come first) until the server closes the
  /// WebSocket; false when a deadline passed instead.
  bool closed() {
    for (int i = 0; i < 1000; ++i) {
      if (!read()) return ws_.reason().code != websocket::close_code::none;
    }
    return false;
  }

  websocket::close_reason close_reason() const { return ws_.reason(); }

 private:
  net::io_context io_;
  websocket::stream<tcp::socket> ws_;
};

inline std::string reason(const Page& p) {
  const auto& r = p.close_reason().reason;
  return std::string(r.data(), r.size());
}

}  // namespace page_detail

using page_detail::Page;
using page_detail::reason;

}  // namespace troupe::viewer
