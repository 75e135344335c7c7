// Faults of a serial line, injected into what an emulated device sends:
// flipped bits, lost bytes, packets torn off mid-way, bursts of noise, and
// the garbage a UART makes of bytes sent at another baud. Seeded: the same
// seed and the same bytes give the same faults.
#pragma once

#include <cstddef>
#include <cstdint>
#include <random>
#include <span>

namespace troupe::emulators {

/// Probabilities; all zero is a clean line.
struct FaultRates {
  /// Per byte sent: one of its bits flips.
  double bit_flip = 0;
  /// Per byte sent: it is lost.
  double byte_drop = 0;
  /// Per packet sent: it is cut short at a random point, the rest lost.
  double tear = 0;
};

class LineFaults {
 public:
  explicit LineFaults(uint64_t seed) : rng_(seed) {}

  FaultRates rates;

  /// Passes one packet through the line: writes what arrives into `out`
  /// (at least `in.size()` bytes of room) and returns its size.
  size_t apply(std::span<const uint8_t> in, std::span<uint8_t> out);
  /// Fills `out` with line noise.
  void noise(std::span<uint8_t> out);
  /// What a receiver at the wrong baud makes of `bytes`: every byte becomes
  /// some other byte, in place. No header survives this.
  void mangle(std::span<uint8_t> bytes);

  struct Counts {
    uint64_t flipped = 0, dropped = 0, torn = 0, noise = 0, mangled = 0;
  };
  const Counts& counts() const { return counts_; }

 private:
  bool chance(double p) { return p > 0 && std::uniform_real_distribution<double>(0, 1)(rng_) < p; }

  std::mt19937_64 rng_;
  Counts counts_;
};

}  // namespace troupe::emulators
