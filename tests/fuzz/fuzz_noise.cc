// libFuzzer target: the secure-session decoder (wire/noise). The first byte
// picks what the rest is, the second how the stream is cut into reads:
//   0  a client's bytes at a secure node (handshake message 1 decoder)
//   1  a node's answer at a client that sent message 1 (message 2 decoder)
//   2  bytes at a node after a real handshake (transport framing, tags)
//   3  a plaintext frame stream sealed and opened through a real session:
//      what comes out must be what went in, however it was split
// Nothing may crash, leak or read out of bounds; forged messages cannot
// authenticate, so modes 0-2 must end (or keep waiting) without a frame.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "wire/noise/noise_transport.h"

namespace {

using namespace troupe::wire;
using namespace troupe::wire::noise;

KeyPair fixed_key(uint8_t fill) {
  Key secret;
  secret.fill(fill);
  return keypair_from_secret(secret);
}

struct Pair {
  KeyPair node = fixed_key(1), client = fixed_key(2);
  NoiseTransport c{SecureOptions{Role::Initiator, client, node.public_key, nullptr}};
  NoiseTransport n{SecureOptions{Role::Responder, node, {}, nullptr}};
  FrameReader c_frames{1u << 20}, n_frames{1u << 20};
  std::vector<uint8_t> c_out, n_out;
  std::string error;

  bool handshake() {
    c.begin(c_out);
    n.begin(n_out);
    bool ok = n.inbound(c_out, n_frames, n_out, error) && c.inbound(n_out, c_frames, c_out, error);
    c_out.clear();
    n_out.clear();
    return ok && c.ready() && n.ready();
  }
};

// Feeds `bytes` in reads of `chunk` bytes; false once refused.
bool feed(NoiseTransport& t, const uint8_t* bytes, size_t size, size_t chunk, FrameReader& frames,
          std::vector<uint8_t>& out, std::string& error) {
  for (size_t at = 0; at < size; at += chunk) {
    if (!t.inbound({bytes + at, std::min(chunk, size - at)}, frames, out, error)) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const uint8_t mode = data[0] % 4;
  const size_t chunk = 1 + data[1] % 128;
  data += 2;
  size -= 2;
  Pair p;
  switch (mode) {
    case 0:
      p.n.begin(p.n_out);
      feed(p.n, data, size, chunk, p.n_frames, p.n_out, p.error);
      if (!p.n_frames.next().empty()) std::abort();
      break;
    case 1:
      p.c.begin(p.c_out);
      feed(p.c, data, size, chunk, p.c_frames, p.c_out, p.error);
      if (!p.c_frames.next().empty()) std::abort();
      break;
    case 2:
      if (!p.handshake()) std::abort();
      feed(p.n, data, size, chunk, p.n_frames, p.n_out, p.error);
      if (!p.n_frames.next().empty()) std::abort();
      break;
    default: {
      if (!p.handshake()) std::abort();
      std::vector<uint8_t> wire;
      p.c.outbound({data, size}, wire);
      if (!feed(p.n, wire.data(), wire.size(), chunk, p.n_frames, p.n_out, p.error)) std::abort();
      // The opened stream, frame by frame, is a prefix of what was sealed.
      size_t at = 0;
      for (auto f = p.n_frames.next(); !f.empty(); f = p.n_frames.next()) {
        if (at + f.size() > size || std::memcmp(f.data(), data + at, f.size()) != 0) std::abort();
        at += f.size();
      }
      break;
    }
  }
  return 0;
}
