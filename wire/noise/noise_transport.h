// A secure session as the connection core's Transport (wire/connection/
// transport.h): the IK handshake, then every byte of the frame stream in
// Noise transport messages. I/O-free, like the connection core.
//
// On the wire (wire/README.md, "Secure sessions"): every Noise message,
// handshake or transport, is preceded by its length as 2 bytes big-endian.
// The plaintexts of the transport messages, concatenated, are the same
// frame stream plain TCP carries; a frame over 65,519 bytes spans several
// messages and the receiver's frame reader reassembles it.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "wire/connection/transport.h"
#include "wire/noise/handshake.h"

namespace troupe::wire::noise {

/// Bound into every handshake as the Noise prologue: a peer of another
/// protocol or version fails the handshake instead of misreading it.
inline constexpr std::string_view kPrologue = "troupe secure session 1";
/// Plaintext bytes in one transport message, at most (65,535 - tag).
inline constexpr size_t kMaxPlainBytes = kMaxMessageBytes - kTagBytes;

/// Handshake payload bytes a peer may send, at most: empty in this version,
/// room for a later one. Bounds what a half-open handshake holds, and lets a
/// plain frame's length prefix be told from a handshake at once.
inline constexpr size_t kMaxHandshakePayloadBytes = 256;
/// Handshake messages with an empty payload, bytes: message 1 is e, the
/// encrypted s and the payload's tag; message 2 is e and the payload's tag.
inline constexpr size_t kMessage1Bytes = kKeyBytes + (kKeyBytes + kTagBytes) + kTagBytes;
inline constexpr size_t kMessage2Bytes = kKeyBytes + kTagBytes;

struct SecureOptions {
  Role role = Role::Initiator;
  /// Our static key pair.
  KeyPair identity;
  /// The initiator's: the responder's public key it expects.
  Key peer_key{};
  /// The responder's: whether a client with this public key may connect
  /// (false: refused with `why`). Unset: any key that completes the
  /// handshake is let in.
  std::function<bool(const Key& client, std::string& why)> accept;
};

class NoiseTransport final : public Transport {
 public:
  explicit NoiseTransport(SecureOptions options);

  void begin(std::vector<uint8_t>& out) override;
  bool ready() const override { return ready_; }
  bool inbound(std::span<const uint8_t> bytes, FrameReader& frames, std::vector<uint8_t>& out,
               std::string& error) override;
  void outbound(std::span<const uint8_t> frames, std::vector<uint8_t>& out) override;
  std::string peer_identity() const override;

  /// The peer's static public key once the handshake has told it (the
  /// responder's from the start).
  const Key& peer_key() const;
  /// Transport messages opened and sealed in this session.
  uint64_t messages_in() const { return receive_.nonce(); }
  uint64_t messages_out() const { return send_.nonce(); }

 private:
  bool handle(Bytes message, FrameReader& frames, std::vector<uint8_t>& out, std::string& error);
  bool write_handshake(std::vector<uint8_t>& out, std::string& error);
  /// Refuses a handshake length outside what this pattern can send.
  bool check_handshake_length(size_t n, std::string& error) const;
  bool read_handshake(Bytes message, std::vector<uint8_t>& out, std::string& error);
  /// Once both handshake messages went through: the transport keys.
  void finish_handshake();
  bool seal(Bytes plain, std::vector<uint8_t>& out);

  SecureOptions options_;
  std::unique_ptr<HandshakeIK> handshake_;
  CipherState send_;
  CipherState receive_;
  std::vector<uint8_t> in_;  // socket bytes not yet a whole Noise message
  bool ready_ = false;
  std::string failure_;  // set once the session failed: it stays failed
};

}  // namespace troupe::wire::noise
