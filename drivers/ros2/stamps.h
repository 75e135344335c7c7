// Device timestamps onto the ROS clock.
//
// Troupe stamps data with the sending node's clock in microseconds: its
// monotonic clock for a robot's troupe-node (passthrough keeps the robot's
// stamps), simulated time for troupe-sim. ROS stamps are either simulated
// time (a simulator publishes /clock and nodes run with use_sim_time) or
// this host's wall clock since 1970.
//
// Wall mode estimates, per clock source (a robot), the offset between the
// source's clock and this host's wall clock as the smallest (wall arrival -
// device stamp) seen lately: the sample that travelled fastest. Windows of
// 10 s let the estimate follow drift; a source whose clock jumps (a robot
// rebooted) starts a new estimate.
#pragma once

#include <cstdint>
#include <unordered_map>

namespace troupe::drivers::ros2 {

class StampMap {
 public:
  /// Wall: device clocks onto the wall clock. Sim: stamps kept as they are.
  explicit StampMap(bool sim) : sim_(sim) {}
  bool sim() const { return sim_; }

  /// The ROS time (us) of a sample stamped `device_us` by clock source
  /// `source`, which arrived at wall time `wall_now_us` (us since 1970).
  uint64_t to_ros_us(uint64_t device_us, uint32_t source, uint64_t wall_now_us);

  /// A window's length, us.
  static constexpr int64_t kWindowUs = 10'000'000;
  /// An arrival this much later than the estimate says is a clock jump, us.
  static constexpr int64_t kJumpUs = 1'000'000;

 private:
  struct Estimate {
    int64_t previous_min = INT64_MAX;  // wall - device over the previous window
    int64_t current_min = INT64_MAX;   // ... over the current one
    uint64_t window_start_us = 0;      // wall time the current window began
    bool ok = false;
  };

  bool sim_;
  std::unordered_map<uint32_t, Estimate> sources_;
};

/// This host's wall clock, us since 1970.
uint64_t wall_clock_us();

}  // namespace troupe::drivers::ros2
