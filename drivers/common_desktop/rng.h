// The random generator of the desktop algorithms: the project's counter-based
// one (runtime/random.h), read as a sequence. Every function that draws takes
// it by reference: callers seed it, so the same seed gives the same run, with
// the same numbers on every platform (there is no global generator).
#pragma once

#include "runtime/random.h"

namespace troupe::desktop {

using Rng = RandomSequence;

/// A zero-mean normal draw with standard deviation `sigma` (0 gives 0).
inline double gaussian(Rng& rng, double sigma) {
  return rng.gaussian(sigma);
}

/// Uniform in [0, 1).
inline double uniform01(Rng& rng) {
  return rng.uniform();
}

}  // namespace troupe::desktop
