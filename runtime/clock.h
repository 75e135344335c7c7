#pragma once

#include "wire/clock.h"

namespace troupe {

/// Monotonic time in microseconds (wire/clock.h).
using wire::monotonic_us;

}  // namespace troupe
