#include "tests/security/noise_test_util.h"

#include <cstdio>

namespace troupe::testing {

std::vector<uint8_t> from_hex(const std::string& hex) {
  std::vector<uint8_t> out;
  for (size_t i = 0; i + 1 < hex.size(); i += 2) {
    out.push_back(static_cast<uint8_t>(std::stoi(hex.substr(i, 2), nullptr, 16)));
  }
  return out;
}

std::string to_hex(std::span<const uint8_t> bytes) {
  std::string out;
  char b[3];
  for (uint8_t v : bytes) {
    std::snprintf(b, sizeof b, "%02x", v);
    out += b;
  }
  return out;
}

std::vector<uint8_t> test_frame(size_t body_bytes, uint8_t seed) {
  std::vector<uint8_t> f(wire::kPrefixBytes + body_bytes);
  for (size_t i = 0; i < wire::kPrefixBytes; ++i) f[i] = static_cast<uint8_t>(body_bytes >> (8 * i));
  for (size_t i = 0; i < body_bytes; ++i) f[wire::kPrefixBytes + i] = static_cast<uint8_t>(seed + i * 7);
  return f;
}

std::vector<std::vector<uint8_t>> split_messages(std::span<const uint8_t> stream) {
  std::vector<std::vector<uint8_t>> out;
  size_t at = 0;
  while (at + 2 <= stream.size()) {
    const size_t n = (size_t{stream[at]} << 8) | stream[at + 1];
    if (at + 2 + n > stream.size()) break;
    out.emplace_back(stream.begin() + static_cast<std::ptrdiff_t>(at),
                     stream.begin() + static_cast<std::ptrdiff_t>(at + 2 + n));
    at += 2 + n;
  }
  return out;
}

}  // namespace troupe::testing
