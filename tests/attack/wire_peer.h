// A raw wire-protocol peer over loopback TCP for the attack suite: it sends
// whatever bytes it is given, well-formed or not, and reads frames back
// with deadlines. It trusts nothing it receives (every frame goes through
// the verifier before it is looked at).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "tests/attack/tcp_socket.h"
#include "wire/frame.h"
#include "wire/noise/noise_transport.h"
#include "wire/writer.h"

namespace troupe::attack {

using Bytes = std::vector<uint8_t>;

class WirePeer {
 public:
  /// Connects to 127.0.0.1:`port`, forgetting any earlier connection.
  bool connect(uint16_t port);
  /// Connects and runs a secure session's handshake as `options` say (the
  /// initiator's); afterwards send() seals and read_frame() opens. False
  /// when the connection failed or the node ended it during the handshake
  /// (`why` then says what the transport saw, if anything).
  bool connect_secure(uint16_t port, wire::noise::SecureOptions options, std::string* why = nullptr,
                      int timeout_ms = 5000);
  /// The connection itself: send, send_now, close, reset. On a secure
  /// session its bytes go unsealed: what a man in the middle would send.
  TcpSocket& socket() { return socket_; }
  /// Sends `bytes`, sealed on a secure session.
  bool send(std::span<const uint8_t> bytes, int timeout_ms = 5000);
  /// On a secure session: `bytes` sealed as the next transport message(s),
  /// each with its length prefix, not sent (the session's nonce moves on):
  /// for an attacker to replay, reorder or alter before sending them
  /// through socket().
  Bytes seal(std::span<const uint8_t> bytes);
  /// On a secure session, every byte this peer put on the socket through
  /// the handshake and send(), as the wire saw it: what a recording
  /// attacker replays. (A plain peer keeps nothing: floods send a lot.)
  const Bytes& sent() const { return sent_; }
  /// Why a secure session ended on our side (a message that did not open).
  const std::string& session_error() const { return session_error_; }
  /// The next whole frame (prefix included) within `timeout_ms`; nullopt
  /// when the connection ended (closed()) or the time ran out.
  std::optional<Bytes> read_frame(int timeout_ms);
  /// Reads until the reply to `seq` (Ack, Nack, DeviceList or TimeSync
  /// echoing it) or an Error; Data and Hello are skipped. nullopt when the
  /// connection ended or the time ran out.
  std::optional<Bytes> wait_reply(uint32_t seq, int timeout_ms);
  /// send() then wait_reply(): the reply, or nullopt.
  std::optional<Bytes> ask(const Bytes& frame, uint32_t seq, int timeout_ms);
  /// The other side closed or reset the connection.
  bool closed() const { return socket_.closed(); }

 private:
  /// Reads what arrives within the deadline into reader_ (opened, on a
  /// secure session); false once the connection or the session ended.
  bool receive(Deadline deadline);

  TcpSocket socket_;
  wire::FrameReader reader_{2u << 20};
  std::unique_ptr<wire::noise::NoiseTransport> transport_;  // null: plain
  Bytes sent_;
  std::string session_error_;
};

/// wait_reply()'s test: is `m` the reply to `seq` (or an Error)?
bool is_reply_to(const wire::Message& m, uint32_t seq);

/// Frames for the peer to send, built with the project's writer.
class Frames {
 public:
  /// A frame without a body (DeviceList, Pull, Close, requests without one).
  Bytes bare(wire::Address addr, wire::Kind kind, uint8_t subtype, uint32_t seq);
  /// A frame whose union type says `type` but whose body is absent: what
  /// verifiers accept and careless readers dereference (44 bytes).
  Bytes null_body(wire::Address addr, wire::Kind kind, uint8_t subtype, uint32_t seq, wire::Body type);
  /// A frame carrying a small valid body of `type` (Hello, Open, TimeSync,
  /// Error, Position2dVel or SimPoses; any other type: no body), whether or
  /// not it fits `kind`.
  Bytes with_body(wire::Address addr, wire::Kind kind, uint8_t subtype, uint32_t seq, wire::Body type);
  Bytes hello(uint32_t seq);
  Bytes open(wire::Address addr, uint32_t seq, wire::Access access = wire::Access::All,
             wire::Delivery delivery = wire::Delivery::Push);
  /// position2d velocity command: m/s, m/s, rad/s.
  Bytes vel(wire::Address addr, float x, float y, float a);
  /// position2d goto command: m, m, rad.
  Bytes go_to(wire::Address addr, float x, float y, float a);
  /// position2d SetOdometry request: m, m, rad.
  Bytes set_odometry(wire::Address addr, uint32_t seq, float x, float y, float a);
  /// simulation:0 requests.
  Bytes sim_step(uint32_t seq, uint32_t steps);
  Bytes sim_speed(uint32_t seq, float speed);
  Bytes sim_set_pose(uint32_t seq, const std::string& model, float x, float y, float a);
  Bytes sim_get_pose(uint32_t seq, const std::string& model);
  Bytes sim_request(uint32_t seq, wire::SimulationReqSub sub);

 private:
  Bytes take(std::span<const uint8_t> frame) { return Bytes(frame.begin(), frame.end()); }
  Bytes pose_command(wire::Address addr, wire::Position2dCmdSub sub, wire::Body type,
                     flatbuffers::Offset<void> body);
  wire::MessageWriter w_;
};

/// simulation:0 and map:0 (robot 0 of troupe-sim's numbering).
inline const wire::Address kSimulation{0, uint16_t(wire::Interface::Simulation), 0};
inline const wire::Address kPosition0{0, uint16_t(wire::Interface::Position2d), 0};

/// The verified message of a received frame (nullptr when it does not verify).
const wire::Message* message(const Bytes& frame);
/// The reply's kind, Invalid for none.
wire::Kind reply_kind(const std::optional<Bytes>& reply);

/// A legitimate client's visit: connect (through a secure session when
/// `secure` is given), Hello, DeviceList, then a request to the first
/// listed device, each answered (Ack or Nack) within `timeout_ms` (a bound
/// against hangs, not a latency requirement). False with `why` saying what
/// did not happen.
bool served(uint16_t port, std::string& why, int timeout_ms = 20000,
            const wire::noise::SecureOptions* secure = nullptr);

/// served(), retried until it succeeds or `timeout_ms` passes: a client
/// that finds every slot taken tries again, as a person would.
bool served_eventually(uint16_t port, std::string& why, int timeout_ms,
                       const wire::noise::SecureOptions* secure = nullptr);

}  // namespace troupe::attack
