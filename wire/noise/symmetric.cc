#include "wire/noise/symmetric.h"

#include <sodium.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>

namespace troupe::wire::noise {
namespace {

// BLAKE2b's block (the spec's BLOCKLEN): HMAC pads its key to it.
constexpr size_t kBlockBytes = 128;

class Blake2b {
 public:
  Blake2b() { crypto_generichash_init(&state_, nullptr, 0, kHashBytes); }
  ~Blake2b() { sodium_memzero(&state_, sizeof state_); }
  Blake2b& add(Bytes data) {
    if (!data.empty()) crypto_generichash_update(&state_, data.data(), data.size());
    return *this;
  }
  Digest finish() {
    Digest out;
    crypto_generichash_final(&state_, out.data(), out.size());
    return out;
  }

 private:
  crypto_generichash_state state_;
};

// ChaCha20-Poly1305 (IETF) nonce: 32 bits of zeros, then the counter
// little-endian (the spec's ChaChaPoly).
std::array<uint8_t, crypto_aead_chacha20poly1305_ietf_NPUBBYTES> nonce_bytes(uint64_t n) {
  std::array<uint8_t, crypto_aead_chacha20poly1305_ietf_NPUBBYTES> out{};
  for (int i = 0; i < 8; ++i) out[4 + i] = static_cast<uint8_t>(n >> (8 * i));
  return out;
}

// The spec reserves the last nonce (2^64 - 1) for rekeying.
constexpr uint64_t kNonceLimit = UINT64_MAX;

}  // namespace

void init_sodium() {
  if (sodium_init() < 0) {
    std::fprintf(stderr, "libsodium cannot initialize (no entropy source?)\n");
    std::abort();
  }
}

Digest hash(Bytes a, Bytes b) { return Blake2b().add(a).add(b).finish(); }

Digest hmac(Bytes key, Bytes data_a, Bytes data_b) {
  std::array<uint8_t, kBlockBytes> block{};
  if (key.size() > kBlockBytes) {
    Digest short_key = hash(key);
    std::memcpy(block.data(), short_key.data(), short_key.size());
  } else if (!key.empty()) {
    std::memcpy(block.data(), key.data(), key.size());
  }
  std::array<uint8_t, kBlockBytes> pad;
  for (size_t i = 0; i < kBlockBytes; ++i) pad[i] = block[i] ^ 0x36;
  Digest inner = Blake2b().add(pad).add(data_a).add(data_b).finish();
  for (size_t i = 0; i < kBlockBytes; ++i) pad[i] = block[i] ^ 0x5c;
  Digest out = Blake2b().add(pad).add(inner).finish();
  sodium_memzero(block.data(), block.size());
  sodium_memzero(pad.data(), pad.size());
  sodium_memzero(inner.data(), inner.size());
  return out;
}

void hkdf(const Digest& chaining_key, Bytes ikm, Digest& out1, Digest& out2, Digest* out3) {
  Digest temp_key = hmac(chaining_key, ikm);
  const uint8_t one = 0x01, two = 0x02, three = 0x03;
  out1 = hmac(temp_key, Bytes(&one, 1));
  out2 = hmac(temp_key, out1, Bytes(&two, 1));
  if (out3 != nullptr) *out3 = hmac(temp_key, out2, Bytes(&three, 1));
  sodium_memzero(temp_key.data(), temp_key.size());
}

CipherState::~CipherState() { clear(); }

CipherState::CipherState(CipherState&& other) noexcept : k_(other.k_), has_key_(other.has_key_), n_(other.n_) {
  other.clear();
}

CipherState& CipherState::operator=(CipherState&& other) noexcept {
  if (this != &other) {
    k_ = other.k_;
    has_key_ = other.has_key_;
    n_ = other.n_;
    other.clear();
  }
  return *this;
}

void CipherState::initialize_key(const uint8_t* key) {
  std::memcpy(k_.data(), key, k_.size());
  has_key_ = true;
  n_ = 0;
}

void CipherState::clear() {
  sodium_memzero(k_.data(), k_.size());
  has_key_ = false;
  n_ = 0;
}

bool CipherState::encrypt_with_ad(Bytes ad, Bytes plain, std::vector<uint8_t>& out) {
  if (!has_key_) {
    out.insert(out.end(), plain.begin(), plain.end());
    return true;
  }
  if (n_ >= kNonceLimit) return false;
  const size_t at = out.size();
  out.resize(at + plain.size() + kTagBytes);
  auto nonce = nonce_bytes(n_);
  unsigned long long written = 0;
  crypto_aead_chacha20poly1305_ietf_encrypt(out.data() + at, &written, plain.data(), plain.size(), ad.data(),
                                            ad.size(), nullptr, nonce.data(), k_.data());
  ++n_;
  return true;
}

bool CipherState::decrypt_with_ad(Bytes ad, Bytes cipher, uint8_t* plain) {
  if (!has_key_) {
    if (!cipher.empty()) std::memmove(plain, cipher.data(), cipher.size());
    return true;
  }
  if (n_ >= kNonceLimit || cipher.size() < kTagBytes) return false;
  auto nonce = nonce_bytes(n_);
  unsigned long long written = 0;
  if (crypto_aead_chacha20poly1305_ietf_decrypt(plain, &written, nullptr, cipher.data(), cipher.size(), ad.data(),
                                                ad.size(), nonce.data(), k_.data()) != 0) {
    return false;
  }
  ++n_;
  return true;
}

void SymmetricState::initialize(std::string_view protocol_name) {
  h_.fill(0);
  if (protocol_name.size() <= kHashBytes) {
    std::memcpy(h_.data(), protocol_name.data(), protocol_name.size());
  } else {
    h_ = hash({reinterpret_cast<const uint8_t*>(protocol_name.data()), protocol_name.size()});
  }
  ck_ = h_;
  cs_.clear();
}

void SymmetricState::mix_key(Bytes input_key_material) {
  Digest temp_k;
  hkdf(ck_, input_key_material, ck_, temp_k);
  // HASHLEN 64: the cipher key is the first 32 bytes.
  cs_.initialize_key(temp_k.data());
  sodium_memzero(temp_k.data(), temp_k.size());
}

void SymmetricState::mix_hash(Bytes data) { h_ = hash(h_, data); }

bool SymmetricState::encrypt_and_hash(Bytes plain, std::vector<uint8_t>& out) {
  const size_t at = out.size();
  if (!cs_.encrypt_with_ad(h_, plain, out)) return false;
  mix_hash({out.data() + at, out.size() - at});
  return true;
}

bool SymmetricState::decrypt_and_hash(Bytes cipher, std::vector<uint8_t>& plain) {
  const size_t tag = cs_.has_key() ? kTagBytes : 0;
  if (cipher.size() < tag) return false;
  plain.resize(cipher.size() - tag);
  if (!cs_.decrypt_with_ad(h_, cipher, plain.data())) return false;
  mix_hash(cipher);
  return true;
}

void SymmetricState::split(CipherState& first, CipherState& second) const {
  Digest k1, k2;
  hkdf(ck_, {}, k1, k2);
  first.initialize_key(k1.data());
  second.initialize_key(k2.data());
  sodium_memzero(k1.data(), k1.size());
  sodium_memzero(k2.data(), k2.size());
}

SymmetricState::~SymmetricState() {
  sodium_memzero(ck_.data(), ck_.size());
  sodium_memzero(h_.data(), h_.size());
}

}  // namespace troupe::wire::noise
