// The one random generator type of the desktop algorithms. Every function
// that draws takes it by reference: callers seed it, so the same seed gives
// the same run (there is no global generator).
#pragma once

#include <cstdint>
#include <random>

namespace troupe::desktop {

using Rng = std::mt19937_64;

/// A zero-mean normal draw with standard deviation `sigma` (0 gives 0).
inline double gaussian(Rng& rng, double sigma) {
  if (!(sigma > 0)) return 0;
  return std::normal_distribution<double>(0.0, sigma)(rng);
}

/// Uniform in [0, 1).
inline double uniform01(Rng& rng) {
  return std::uniform_real_distribution<double>(0.0, 1.0)(rng);
}

}  // namespace troupe::desktop
