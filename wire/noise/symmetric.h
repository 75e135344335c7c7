// The Noise protocol framework's symmetric layer (revision 34, sections 4
// and 5.1-5.2) for the suite 25519_ChaChaPoly_BLAKE2b, on libsodium: the
// hash, HMAC and HKDF the spec builds from BLAKE2b, CipherState (a key and
// a counter nonce) and SymmetricState (chaining key and handshake hash).
// Nothing here invents a primitive: X25519, ChaCha20-Poly1305 (IETF) and
// BLAKE2b are libsodium's; HMAC and HKDF are the spec's constructions.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace troupe::wire::noise {

/// X25519 keys and ChaCha20-Poly1305 keys, bytes.
inline constexpr size_t kKeyBytes = 32;
/// BLAKE2b-512 output (the spec's HASHLEN), bytes.
inline constexpr size_t kHashBytes = 64;
/// Poly1305 tag appended to every encrypted payload, bytes.
inline constexpr size_t kTagBytes = 16;
/// The largest Noise message, bytes (the spec's limit, tag included).
inline constexpr size_t kMaxMessageBytes = 65535;

using Key = std::array<uint8_t, kKeyBytes>;
using Digest = std::array<uint8_t, kHashBytes>;
using Bytes = std::span<const uint8_t>;

/// Initializes libsodium once (thread-safe); aborts the process when it
/// cannot (no entropy source): nothing secure can run then.
void init_sodium();

/// BLAKE2b-512 of a || b.
Digest hash(Bytes a, Bytes b = {});
/// HMAC-BLAKE2b (RFC 2104 with a 128-byte block) of data_a || data_b.
Digest hmac(Bytes key, Bytes data_a, Bytes data_b = {});
/// The spec's HKDF(chaining_key, ikm, 2 or 3): `out3` may be nullptr.
void hkdf(const Digest& chaining_key, Bytes ikm, Digest& out1, Digest& out2, Digest* out3 = nullptr);

/// A key and its counter nonce. Without a key, "encryption" is the identity
/// (the spec's handshake before the first DH).
class CipherState {
 public:
  CipherState() = default;
  ~CipherState();
  CipherState(const CipherState&) = delete;
  CipherState& operator=(const CipherState&) = delete;
  CipherState(CipherState&& other) noexcept;
  CipherState& operator=(CipherState&& other) noexcept;

  /// Sets the key (kKeyBytes bytes) and resets the nonce to 0.
  void initialize_key(const uint8_t* key);
  /// Forgets the key (zeroed) and the nonce.
  void clear();
  bool has_key() const { return has_key_; }
  /// The nonce the next message uses: messages so far in this direction.
  uint64_t nonce() const { return n_; }

  /// Appends the ciphertext of `plain` (plain.size() + kTagBytes bytes with
  /// a key) to `out`. False when the nonce space is used up (2^64 - 1
  /// messages): the session must end.
  bool encrypt_with_ad(Bytes ad, Bytes plain, std::vector<uint8_t>& out);
  /// Writes the plaintext of `cipher` (cipher.size() - kTagBytes bytes with
  /// a key) at `plain`. False when the tag does not verify (an altered,
  /// replayed, reordered or dropped message) or the nonce space is used up;
  /// the nonce then stays where it was.
  bool decrypt_with_ad(Bytes ad, Bytes cipher, uint8_t* plain);

 private:
  Key k_{};
  bool has_key_ = false;
  uint64_t n_ = 0;
};

/// The chaining key, the handshake hash and the handshake's CipherState.
class SymmetricState {
 public:
  /// InitializeSymmetric(protocol_name).
  void initialize(std::string_view protocol_name);
  void mix_key(Bytes input_key_material);
  void mix_hash(Bytes data);
  /// Appends the encrypted `plain` to `out` and hashes the ciphertext.
  bool encrypt_and_hash(Bytes plain, std::vector<uint8_t>& out);
  /// Replaces `plain` with the decrypted `cipher`; false when it does not
  /// authenticate (nothing hashed then).
  bool decrypt_and_hash(Bytes cipher, std::vector<uint8_t>& plain);
  /// The two transport keys: `first` for initiator to responder, `second`
  /// for the way back.
  void split(CipherState& first, CipherState& second) const;
  /// The handshake hash h (binds the whole handshake: a channel binding).
  const Digest& handshake_hash() const { return h_; }
  /// Whether a DH has been mixed in (payloads are encrypted from then on).
  bool has_key() const { return cs_.has_key(); }
  ~SymmetricState();

 private:
  Digest ck_{};
  Digest h_{};
  CipherState cs_;
};

}  // namespace troupe::wire::noise
