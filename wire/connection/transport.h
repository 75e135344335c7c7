// The seam between frames and the socket. Without a Transport the connection
// sends and receives frames as plain bytes (and reads straight into its frame
// reader, with no copy). An authenticated, encrypted transport (a Noise
// session, a later issue) implements this interface once, here, for every
// C++ peer: its handshake runs first, in the Handshake state before Hello,
// and then it seals every outbound byte and opens every inbound one.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "wire/frame.h"

namespace troupe::wire {

class Transport {
 public:
  virtual ~Transport() = default;

  /// A new transport connection is up: forget the previous one's state, and
  /// append to `out` the first handshake message if this side sends first.
  virtual void begin(std::vector<uint8_t>& out) = 0;
  /// The handshake is complete: frames may travel.
  virtual bool ready() const = 0;
  /// Bytes from the socket. Handshake messages are consumed (any reply
  /// appended to `out`); once ready, the opened bytes go into `frames`.
  /// False with `error` when the peer's bytes are refused: the connection
  /// is then dropped.
  virtual bool inbound(std::span<const uint8_t> bytes, FrameReader& frames, std::vector<uint8_t>& out,
                       std::string& error) = 0;
  /// Whole frames to send (only once ready): appends what goes on the socket.
  virtual void outbound(std::span<const uint8_t> frames, std::vector<uint8_t>& out) = 0;
  /// Who the peer proved to be, as text for logs (a public key in hex),
  /// once ready; empty when the transport does not authenticate.
  virtual std::string peer_identity() const { return {}; }
};

}  // namespace troupe::wire
