// Seeded noise for sensor plugins: every draw comes from the generator the
// simulator hands the plugin, so a run repeats exactly.
#pragma once


#include "host-sim/robocup/api/plugin.h"

namespace troupe::robocup::plugins {

/// A normal draw with standard deviation `sigma` (0 draws nothing, so a
/// noiseless sensor leaves the generator untouched).
inline double gaussian(Rng& rng, double sigma) {
  return rng.gaussian(sigma);
}

/// True with probability `p`.
inline bool chance(Rng& rng, double p) {
  return rng.chance(p);
}

}  // namespace troupe::robocup::plugins
