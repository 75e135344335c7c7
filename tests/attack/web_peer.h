// HTTP and WebSocket by hand, as a hostile browser or script would speak
// them to the viewer: any Host, any Origin, any path, headers of any size,
// and binary WebSocket messages carrying wire frames (RFC 6455 framing, the
// client's masking included).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tests/attack/wire_peer.h"

namespace troupe::attack {

struct HttpReply {
  /// The status code, 0 when no status line came (the server closed).
  int status = 0;
  std::string head, body;
};

/// Sends `request` (the whole text, as given) to 127.0.0.1:`port` and reads
/// the reply's status line, headers and (with Content-Length) body.
HttpReply http_exchange(uint16_t port, const std::string& request, int timeout_ms = 10000);

/// A GET of `target` with `Host: 127.0.0.1:port`.
HttpReply http_get(uint16_t port, const std::string& target);

/// A WebSocket client of the viewer's /ws.
class WebPeer {
 public:
  /// Asks for the upgrade with these Host and Origin values (an empty
  /// Origin is left out). Returns the HTTP status: 101 when accepted; a
  /// refusal's body goes to `body`.
  int handshake(uint16_t port, const std::string& host, const std::string& origin,
                std::string* body = nullptr);
  /// One binary message (`text`: a text message instead).
  bool send_message(const Bytes& payload, bool text = false);
  /// The next binary message's payload; nullopt when the server closed the
  /// WebSocket (close_code() then says why) or the time ran out.
  std::optional<Bytes> read_message(int timeout_ms);
  /// The close code the server sent, 0 before one came.
  int close_code() const { return close_code_; }
  /// Reads until the reply to `seq` (as WirePeer::wait_reply).
  std::optional<Bytes> wait_reply(uint32_t seq, int timeout_ms);
  TcpSocket& socket() { return socket_; }

 private:
  /// Reads until `in_` holds at least `n` bytes; false on close or timeout.
  bool fill(size_t n, Deadline deadline);

  TcpSocket socket_;
  Bytes in_;
  int close_code_ = 0;
};

/// The viewer's own page's visit over the WebSocket: handshake as the page
/// would (its own Host and Origin), Hello, DeviceList answered. False with `why`.
bool served_by_viewer(uint16_t port, std::string& why);

}  // namespace troupe::attack
