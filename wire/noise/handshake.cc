#include "wire/noise/handshake.h"

#include <sodium.h>

#include <cstring>

namespace troupe::wire::noise {

const char kProtocolName[] = "Noise_IK_25519_ChaChaPoly_BLAKE2b";

KeyPair generate_keypair() {
  init_sodium();
  Key secret;
  randombytes_buf(secret.data(), secret.size());
  KeyPair pair = keypair_from_secret(secret);
  sodium_memzero(secret.data(), secret.size());
  return pair;
}

KeyPair keypair_from_secret(const Key& secret) {
  init_sodium();
  KeyPair pair;
  pair.secret = secret;
  crypto_scalarmult_base(pair.public_key.data(), pair.secret.data());
  return pair;
}

HandshakeIK::HandshakeIK(Role role, const KeyPair& local, Bytes prologue, const Key* remote_static,
                         const KeyPair* ephemeral)
    : role_(role), s_(local) {
  init_sodium();
  if (ephemeral != nullptr) {
    e_ = *ephemeral;
    fixed_e_ = true;
  }
  symmetric_.initialize(kProtocolName);
  symmetric_.mix_hash(prologue);
  // The pre-message "<- s": the responder's static key, known to both.
  if (role_ == Role::Initiator) {
    if (remote_static != nullptr) rs_ = *remote_static;
    symmetric_.mix_hash(rs_);
  } else {
    symmetric_.mix_hash(s_.public_key);
  }
}

HandshakeIK::~HandshakeIK() {
  sodium_memzero(s_.secret.data(), s_.secret.size());
  sodium_memzero(e_.secret.data(), e_.secret.size());
}

bool HandshakeIK::our_turn() const {
  return !failed_ && ((step_ == 0 && role_ == Role::Initiator) || (step_ == 1 && role_ == Role::Responder));
}

bool HandshakeIK::fail(std::string& error, std::string why) {
  failed_ = true;
  error = std::move(why);
  return false;
}

bool HandshakeIK::dh_into_key(const Key& secret, const Key& public_key, std::string& error) {
  Key shared;
  // libsodium refuses a public key of small order (an all-zero result): a
  // peer sending one would fix the shared secret.
  if (crypto_scalarmult(shared.data(), secret.data(), public_key.data()) != 0) {
    return fail(error, "the peer's key is not a valid X25519 public key (small order)");
  }
  symmetric_.mix_key(shared);
  sodium_memzero(shared.data(), shared.size());
  return true;
}

bool HandshakeIK::write_message(Bytes payload, std::vector<uint8_t>& out, std::string& error) {
  if (!our_turn()) return fail(error, "handshake message written out of turn");
  const size_t at = out.size();
  if (!fixed_e_) e_ = generate_keypair();
  out.insert(out.end(), e_.public_key.begin(), e_.public_key.end());
  symmetric_.mix_hash(e_.public_key);
  if (role_ == Role::Initiator) {
    // -> e, es, s, ss
    if (!dh_into_key(e_.secret, rs_, error)) return false;
    if (!symmetric_.encrypt_and_hash(s_.public_key, out)) return fail(error, "nonce exhausted");
    if (!dh_into_key(s_.secret, rs_, error)) return false;
  } else {
    // <- e, ee, se
    if (!dh_into_key(e_.secret, re_, error)) return false;
    if (!dh_into_key(e_.secret, rs_, error)) return false;
  }
  if (!symmetric_.encrypt_and_hash(payload, out)) return fail(error, "nonce exhausted");
  if (out.size() - at > kMaxMessageBytes) return fail(error, "handshake payload too large for one Noise message");
  ++step_;
  return true;
}

bool HandshakeIK::read_message(Bytes message, std::vector<uint8_t>& payload, std::string& error) {
  if (failed_ || complete() || our_turn()) return fail(error, "handshake message received out of turn");
  if (message.size() > kMaxMessageBytes) return fail(error, "handshake message over 65535 bytes");
  // Message 1 holds e (32), the encrypted s (32 + tag) and the payload's
  // tag; message 2 holds e and the payload's tag.
  const size_t least = role_ == Role::Responder ? kKeyBytes + kKeyBytes + 2 * kTagBytes : kKeyBytes + kTagBytes;
  if (message.size() < least) {
    return fail(error, "handshake message " + std::to_string(step_ + 1) + " is " + std::to_string(message.size()) +
                           " bytes, shorter than the " + std::to_string(least) + " it needs");
  }
  std::memcpy(re_.data(), message.data(), kKeyBytes);
  symmetric_.mix_hash(re_);
  Bytes rest = message.subspan(kKeyBytes);
  if (role_ == Role::Responder) {
    // -> e, es, s, ss
    if (!dh_into_key(s_.secret, re_, error)) return false;
    std::vector<uint8_t> rs;
    if (!symmetric_.decrypt_and_hash(rest.first(kKeyBytes + kTagBytes), rs)) {
      return fail(error,
                  "handshake message 1 does not authenticate: the client does not hold this node's public key "
                  "(or speaks another protocol)");
    }
    std::memcpy(rs_.data(), rs.data(), kKeyBytes);
    rest = rest.subspan(kKeyBytes + kTagBytes);
    if (!dh_into_key(s_.secret, rs_, error)) return false;
  } else {
    // <- e, ee, se
    if (!dh_into_key(e_.secret, re_, error)) return false;
    if (!dh_into_key(s_.secret, re_, error)) return false;
  }
  if (!symmetric_.decrypt_and_hash(rest, payload)) {
    return fail(error, role_ == Role::Initiator
                           ? "handshake message 2 does not authenticate: the node does not hold the private key "
                             "of the public key we know for it (its key changed, or someone else answers)"
                           : "handshake message 1's payload does not authenticate");
  }
  ++step_;
  return true;
}

void HandshakeIK::split(CipherState& send, CipherState& receive) const {
  if (role_ == Role::Initiator) {
    symmetric_.split(send, receive);
  } else {
    symmetric_.split(receive, send);
  }
}

}  // namespace troupe::wire::noise
