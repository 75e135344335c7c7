// Seeded noise for sensor plugins: every draw comes from the generator the
// simulator hands the plugin, so a run repeats exactly.
#pragma once

#include <algorithm>
#include <random>

#include "host-sim/robocup/api/plugin.h"

namespace troupe::robocup::plugins {

/// A normal draw with standard deviation `sigma` (0 draws nothing, so a
/// noiseless sensor leaves the generator untouched).
inline double gaussian(Rng& rng, double sigma) {
  if (sigma <= 0) return 0;
  return std::normal_distribution<double>(0.0, sigma)(rng);
}

/// True with probability `p`.
inline bool chance(Rng& rng, double p) {
  if (p <= 0) return false;
  return std::uniform_real_distribution<double>(0.0, 1.0)(rng) < p;
}

}  // namespace troupe::robocup::plugins
