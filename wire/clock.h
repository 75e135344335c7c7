// The one clock the clients and the node measure time with.
#pragma once

#include <cstdint>
#include <ctime>

namespace troupe::wire {

/// Monotonic time in microseconds (CLOCK_MONOTONIC): never jumps with the
/// wall clock, so deadlines and rates stay right.
inline uint64_t monotonic_us() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return uint64_t(ts.tv_sec) * 1000000u + uint64_t(ts.tv_nsec) / 1000u;
}

}  // namespace troupe::wire
