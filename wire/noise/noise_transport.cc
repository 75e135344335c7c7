#include "wire/noise/noise_transport.h"

#include <algorithm>
#include <utility>

#include "wire/noise/key_file.h"

namespace troupe::wire::noise {
namespace {

constexpr size_t kLengthBytes = 2;

Bytes prologue_bytes() { return {reinterpret_cast<const uint8_t*>(kPrologue.data()), kPrologue.size()}; }

}  // namespace

NoiseTransport::NoiseTransport(SecureOptions options) : options_(std::move(options)) { init_sodium(); }

const Key& NoiseTransport::peer_key() const {
  static const Key kNone{};
  if (options_.role == Role::Initiator) return options_.peer_key;
  return handshake_ != nullptr ? handshake_->remote_static() : kNone;
}

std::string NoiseTransport::peer_identity() const { return ready_ ? key_hex(peer_key()) : std::string(); }

void NoiseTransport::begin(std::vector<uint8_t>& out) {
  handshake_ = std::make_unique<HandshakeIK>(options_.role, options_.identity, prologue_bytes(),
                                             options_.role == Role::Initiator ? &options_.peer_key : nullptr);
  send_.clear();
  receive_.clear();
  in_.clear();
  ready_ = false;
  failure_.clear();
  if (options_.role == Role::Initiator) {
    std::string error;
    if (!write_handshake(out, error)) failure_ = error;
  }
}

bool NoiseTransport::write_handshake(std::vector<uint8_t>& out, std::string& error) {
  // The length goes first: room for it, filled in once the message is known.
  const size_t at = out.size();
  out.resize(at + kLengthBytes);
  if (!handshake_->write_message({}, out, error)) {
    out.resize(at);
    return false;
  }
  const size_t n = out.size() - at - kLengthBytes;
  out[at] = static_cast<uint8_t>(n >> 8);
  out[at + 1] = static_cast<uint8_t>(n);
  finish_handshake();
  return true;
}

bool NoiseTransport::check_handshake_length(size_t n, std::string& error) const {
  const size_t least = options_.role == Role::Responder ? kMessage1Bytes : kMessage2Bytes;
  if (n >= least && n <= least + kMaxHandshakePayloadBytes) return true;
  const std::string range = std::to_string(least) + " to " + std::to_string(least + kMaxHandshakePayloadBytes);
  if (options_.role == Role::Responder) {
    error = "the client did not open a secure session (its first bytes announce a " + std::to_string(n) +
            "-byte handshake message, not " + range + "): an insecure client? This node accepts secure sessions only";
  } else {
    error = "the node did not answer with a secure handshake (" + std::to_string(n) + " bytes announced, not " +
            range + "): an insecure node?";
  }
  return false;
}

bool NoiseTransport::read_handshake(Bytes message, std::vector<uint8_t>& out, std::string& error) {
  // Payloads are empty in this version; one from a later version is ignored.
  std::vector<uint8_t> payload;
  if (!handshake_->read_message(message, payload, error)) return false;
  if (options_.role == Role::Initiator) {
    finish_handshake();
    return true;
  }
  std::string why;
  if (options_.accept && !options_.accept(handshake_->remote_static(), why)) {
    error = "client refused: " + why;
    return false;
  }
  return write_handshake(out, error);
}

void NoiseTransport::finish_handshake() {
  if (!handshake_->complete()) return;
  handshake_->split(send_, receive_);
  ready_ = true;
}

bool NoiseTransport::handle(Bytes message, FrameReader& frames, std::vector<uint8_t>& out, std::string& error) {
  if (!ready_) {
    return read_handshake(message, out, error);
  }
  if (message.size() < kTagBytes) {
    error = "transport message of " + std::to_string(message.size()) + " bytes, shorter than its " +
            std::to_string(kTagBytes) + "-byte tag";
    return false;
  }
  const size_t plain = message.size() - kTagBytes;
  std::span<uint8_t> space = frames.write_space(std::max<size_t>(plain, 1));
  if (!receive_.decrypt_with_ad({}, message, space.data())) {
    error = "transport message " + std::to_string(receive_.nonce()) +
            " does not authenticate (altered, replayed, reordered or a message dropped): session ended";
    return false;
  }
  frames.commit(plain);
  return true;
}

bool NoiseTransport::inbound(std::span<const uint8_t> bytes, FrameReader& frames, std::vector<uint8_t>& out,
                             std::string& error) {
  if (handshake_ == nullptr) {
    error = "secure transport used before begin()";
    return false;
  }
  if (!failure_.empty()) {
    error = failure_;
    return false;
  }
  in_.insert(in_.end(), bytes.begin(), bytes.end());
  size_t at = 0;
  bool ok = true;
  while (ok && in_.size() - at >= kLengthBytes) {
    const size_t n = (size_t{in_[at]} << 8) | in_[at + 1];
    if (!ready_ && !check_handshake_length(n, error)) {
      ok = false;
      break;
    }
    if (in_.size() - at - kLengthBytes < n) break;
    ok = handle({in_.data() + at + kLengthBytes, n}, frames, out, error);
    at += kLengthBytes + n;
  }
  in_.erase(in_.begin(), in_.begin() + static_cast<std::ptrdiff_t>(at));
  if (!ok) {
    failure_ = error;
    in_.clear();
    in_.shrink_to_fit();
  }
  return ok;
}

bool NoiseTransport::seal(Bytes plain, std::vector<uint8_t>& out) {
  const size_t at = out.size();
  const size_t n = plain.size() + kTagBytes;
  out.push_back(static_cast<uint8_t>(n >> 8));
  out.push_back(static_cast<uint8_t>(n));
  if (!send_.encrypt_with_ad({}, plain, out)) {
    out.resize(at);
    return false;
  }
  return true;
}

void NoiseTransport::outbound(std::span<const uint8_t> frames, std::vector<uint8_t>& out) {
  if (!ready_ || !failure_.empty()) return;
  for (size_t at = 0; at < frames.size(); at += kMaxPlainBytes) {
    if (!seal(frames.subspan(at, std::min(kMaxPlainBytes, frames.size() - at)), out)) {
      // 2^64 - 1 messages: the spec forbids another nonce. The next inbound
      // call reports it and the connection is dropped.
      failure_ = "nonce space used up: the session must be renewed";
      return;
    }
  }
}

}  // namespace troupe::wire::noise
