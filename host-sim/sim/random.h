// The run's random numbers: a counter-based generator. A value is a pure
// function of (seed, stream, counter), so a sensor's noise at a given step
// does not depend on which other sensors were read before it, or in which
// order, or on which thread. One Random per run, passed in; never global.
#pragma once

#include <cmath>
#include <cstdint>

namespace troupe::sim {

class Random {
 public:
  explicit Random(uint64_t seed = 0) : seed_(seed) {}
  uint64_t seed() const { return seed_; }

  /// Names a stream from up to three numbers (kind, owner, step...).
  static constexpr uint64_t stream(uint64_t a, uint64_t b = 0, uint64_t c = 0) {
    return mix(mix(mix(a) ^ (b + 0x9E3779B97F4A7C15ull)) ^ (c + 0xC2B2AE3D27D4EB4Full));
  }

  /// 64 random bits: value `counter` of stream `stream`.
  constexpr uint64_t bits(uint64_t stream_id, uint64_t counter) const {
    return mix(mix(seed_ ^ stream_id) + counter * 0x9E3779B97F4A7C15ull);
  }

  /// Uniform in [0, 1).
  double uniform(uint64_t stream_id, uint64_t counter) const {
    return double(bits(stream_id, counter) >> 11) * 0x1.0p-53;
  }
  /// Uniform in [-1, 1).
  double symmetric(uint64_t stream_id, uint64_t counter) const { return 2 * uniform(stream_id, counter) - 1; }

  /// Standard normal (Box-Muller on counters 2n and 2n+1).
  double gaussian(uint64_t stream_id, uint64_t counter) const {
    double u1 = 1.0 - uniform(stream_id, 2 * counter);  // (0, 1]: log is finite
    double u2 = uniform(stream_id, 2 * counter + 1);
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }

 private:
  // SplitMix64's finalizer: a bijection that spreads every input bit.
  static constexpr uint64_t mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

  uint64_t seed_;
};

/// Stream kinds, so two uses of the same owner never share numbers.
enum class RandomKind : uint64_t {
  OdomError = 1,
  RangerNoise = 2,
  RangerAngle = 3,
  RangerGauss = 6,
  Controller = 4,
  Color = 5,
};

}  // namespace troupe::sim
