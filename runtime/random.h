// The project's one random generator: counter-based. A value is a pure
// function of (seed, stream, counter), computed with integer arithmetic and
// the C library's log/cos only, so a seed gives the same numbers with every
// standard library (std::normal_distribution does not: its algorithm is the
// library's choice). Header-only, for drivers, the simulator and plugins
// built as separate libraries. Generators are seeded and passed in, never
// global.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

namespace troupe {

/// Random numbers addressed by (stream, counter): a sensor's noise at a
/// given step does not depend on which other sensors drew before it, in
/// which order, or on which thread.
class Random {
 public:
  explicit Random(uint64_t seed = 0) : seed_(seed) {}
  uint64_t seed() const { return seed_; }

  /// Names a stream from up to three numbers (kind, owner, step...).
  static constexpr uint64_t stream(uint64_t a, uint64_t b = 0, uint64_t c = 0) {
    return mix(mix(mix(a) ^ (b + 0x9E3779B97F4A7C15ull)) ^ (c + 0xC2B2AE3D27D4EB4Full));
  }

  /// 64 random bits: value `counter` of stream `stream_id`.
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
    return box_muller(uniform(stream_id, 2 * counter), uniform(stream_id, 2 * counter + 1));
  }

  /// A standard normal from two uniforms in [0, 1).
  static double box_muller(double u1, double u2) {
    return std::sqrt(-2.0 * std::log(1.0 - u1)) * std::cos(6.283185307179586 * u2);  // 1 - u1 in (0, 1]
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

/// One stream of `Random` read in order, for code that draws one number
/// after another (a particle filter, a noisy sensor plugin): each draw takes
/// the next counter. Also a UniformRandomBitGenerator, for std::shuffle and
/// the like (whose results then depend on the library again: prefer the
/// members).
class RandomSequence {
 public:
  using result_type = uint64_t;

  explicit RandomSequence(uint64_t seed = 0, uint64_t stream_id = 0) : random_(seed), stream_(stream_id) {}
  /// Starts over from `seed` (stream 0, counter 0).
  void seed(uint64_t seed) { *this = RandomSequence(seed); }

  /// Uniform in [0, 1).
  double uniform() { return random_.uniform(stream_, next_++); }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Standard normal; takes two counters, so no later draw reuses them.
  double gaussian() {
    const double u1 = uniform();
    return Random::box_muller(u1, uniform());
  }
  /// Normal with standard deviation `sigma` (0 or less gives exactly 0 and
  /// draws nothing).
  double gaussian(double sigma) { return sigma > 0 ? sigma * gaussian() : 0.0; }
  /// True with probability `p`.
  bool chance(double p) { return p > 0 && uniform() < p; }

  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return std::numeric_limits<result_type>::max(); }
  result_type operator()() { return random_.bits(stream_, next_++); }

 private:
  Random random_;
  uint64_t stream_;
  uint64_t next_ = 0;
};

}  // namespace troupe
