#pragma once

#include <algorithm>

namespace troupe::robocup::plugins {

/// `current` moved towards `target` by at most `max_change`.
inline double approach(double current, double target, double max_change) {
  return current + std::clamp(target - current, -max_change, max_change);
}

}  // namespace troupe::robocup::plugins
