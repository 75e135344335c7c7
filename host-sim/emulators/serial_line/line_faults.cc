#include "host-sim/emulators/serial_line/line_faults.h"

namespace troupe::emulators {

size_t LineFaults::apply(std::span<const uint8_t> in, std::span<uint8_t> out) {
  size_t end = in.size();
  if (end > 1 && chance(rates.tear)) {
    end = std::uniform_int_distribution<size_t>(1, in.size() - 1)(rng_);
    ++counts_.torn;
  }
  size_t n = 0;
  for (size_t i = 0; i < end; ++i) {
    if (chance(rates.byte_drop)) {
      ++counts_.dropped;
      continue;
    }
    uint8_t b = in[i];
    if (chance(rates.bit_flip)) {
      b ^= uint8_t(1u << std::uniform_int_distribution<int>(0, 7)(rng_));
      ++counts_.flipped;
    }
    out[n++] = b;
  }
  return n;
}

void LineFaults::noise(std::span<uint8_t> out) {
  std::uniform_int_distribution<int> byte(0, 255);
  for (uint8_t& b : out) b = uint8_t(byte(rng_));
  counts_.noise += out.size();
}

void LineFaults::mangle(std::span<uint8_t> bytes) {
  std::uniform_int_distribution<int> other(1, 255);
  for (uint8_t& b : bytes) b = uint8_t(b ^ other(rng_));
  counts_.mangled += bytes.size();
}

}  // namespace troupe::emulators
