#include "drivers/ros2/stamps.h"

#include <algorithm>
#include <ctime>

namespace troupe::drivers::ros2 {

uint64_t StampMap::to_ros_us(uint64_t device_us, uint32_t source, uint64_t wall_now_us) {
  if (sim_) return device_us;
  Estimate& e = sources_[source];
  const int64_t candidate = int64_t(wall_now_us) - int64_t(device_us);
  const int64_t estimate = std::min(e.previous_min, e.current_min);
  if (!e.ok || candidate - estimate > kJumpUs || wall_now_us < e.window_start_us) {
    e = Estimate{INT64_MAX, candidate, wall_now_us, true};
  } else {
    if (int64_t(wall_now_us - e.window_start_us) >= kWindowUs) {
      e.previous_min = e.current_min;
      e.current_min = INT64_MAX;
      e.window_start_us = wall_now_us;
    }
    e.current_min = std::min(e.current_min, candidate);
  }
  const int64_t ros = int64_t(device_us) + std::min(e.previous_min, e.current_min);
  return ros > 0 ? uint64_t(ros) : 0;
}

uint64_t wall_clock_us() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return uint64_t(ts.tv_sec) * 1'000'000u + uint64_t(ts.tv_nsec) / 1000u;
}

}  // namespace troupe::drivers::ros2
