// Noise_IK_25519_ChaChaPoly_BLAKE2b's handshake (Noise revision 34, section
// 5.3 with the IK pattern of section 7.5):
//
//   IK:
//     <- s
//     ...
//     -> e, es, s, ss
//     <- e, ee, se
//
// The initiator (a client) knows the responder's (the node's) static key
// beforehand; one round trip authenticates both and hides the client's
// identity from eavesdroppers. I/O-free: messages in, messages out.
#pragma once

#include <string>
#include <vector>

#include "wire/noise/symmetric.h"

namespace troupe::wire::noise {

/// "Noise_IK_25519_ChaChaPoly_BLAKE2b".
extern const char kProtocolName[];

/// An X25519 key pair.
struct KeyPair {
  Key secret{};
  Key public_key{};
};

/// A fresh key pair from libsodium's system random source.
KeyPair generate_keypair();
/// The key pair whose secret is `secret` (clamped by X25519 itself).
KeyPair keypair_from_secret(const Key& secret);

enum class Role : uint8_t { Initiator, Responder };

class HandshakeIK {
 public:
  /// `local` is our static key pair; `remote_static` the responder's public
  /// key (the initiator's only; the responder learns the initiator's from
  /// message 1). `prologue` is bound into the handshake hash: both sides
  /// must give the same bytes. `ephemeral` replaces the random ephemeral key
  /// (test vectors only).
  HandshakeIK(Role role, const KeyPair& local, Bytes prologue, const Key* remote_static = nullptr,
              const KeyPair* ephemeral = nullptr);
  ~HandshakeIK();
  HandshakeIK(const HandshakeIK&) = delete;
  HandshakeIK& operator=(const HandshakeIK&) = delete;

  /// Whether it is our turn to write (initiator first, then responder).
  bool our_turn() const;
  /// Appends the next handshake message carrying `payload` to `out`.
  /// False with `error` out of turn or once the handshake is over.
  bool write_message(Bytes payload, std::vector<uint8_t>& out, std::string& error);
  /// Reads the peer's next handshake message; its payload into `payload`.
  /// False with `error` when it does not authenticate or is malformed: the
  /// handshake is then failed for good.
  bool read_message(Bytes message, std::vector<uint8_t>& payload, std::string& error);

  /// Both messages went through.
  bool complete() const { return step_ == 2; }
  bool failed() const { return failed_; }
  /// The peer's static public key (the responder's from the start; the
  /// initiator's once message 1 was read).
  const Key& remote_static() const { return rs_; }
  /// The handshake hash (after complete(): the same on both sides).
  const Digest& handshake_hash() const { return symmetric_.handshake_hash(); }
  /// After complete(): the transport keys for each direction.
  void split(CipherState& send, CipherState& receive) const;

 private:
  bool dh_into_key(const Key& secret, const Key& public_key, std::string& error);
  bool fail(std::string& error, std::string why);

  Role role_;
  KeyPair s_;
  KeyPair e_;
  bool fixed_e_ = false;
  Key rs_{};
  Key re_{};
  SymmetricState symmetric_;
  int step_ = 0;  // messages done: 0, 1 or 2
  bool failed_ = false;
};

}  // namespace troupe::wire::noise
