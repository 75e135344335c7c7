// A differential drive on two ODrive axes: body velocities to wheel turns/s,
// and wheel turns back to odometry. Plain functions on plain structs, so the
// tests check the arithmetic without a bus.
#pragma once

#include <cstdint>

namespace troupe::drivers::odrive_can {

struct DriveGeometry {
  float wheel_radius = 0;     // m
  float track_width = 0;      // m, between the wheels' contact points
  bool invert_left = false;   // the left motor turns backwards for forward travel
  bool invert_right = false;  // the right motor turns backwards for forward travel
};

/// Motor velocities as sent to the axes, turns/s (signs already inverted
/// where a side is mounted mirrored).
struct WheelTurnRates {
  float left = 0;   // turns/s
  float right = 0;  // turns/s
};

/// Wheel rates for forward speed `v` (m/s) and turn rate `w` (rad/s). When a
/// wheel would exceed `max_wheel_turns_s` both are scaled down together, so
/// the path's curvature is kept and only the pace drops.
WheelTurnRates wheel_rates(float v, float w, const DriveGeometry& g, float max_wheel_turns_s);

/// Body velocity (m/s, rad/s) from measured motor rates (turns/s, as the axes
/// report them).
void body_velocity(const WheelTurnRates& motor, const DriveGeometry& g, float& v, float& w);

/// The odometric pose, integrated in double: float metres lose millimetres
/// after a few kilometres.
struct Odometry {
  double x = 0, y = 0, a = 0;  // m, m, rad (a kept in (-pi, pi])
};

/// Advances the pose by the distances the left and right wheels rolled, m
/// (forward positive), along the arc they describe.
void integrate(Odometry& odom, double left_m, double right_m, double track_width);

/// Tracks one axis's reported position and turns it into travel. Positions
/// may wrap: with `wrap_turns` > 0 the axis reports within [0, wrap_turns)
/// (circular setpoints), so the shortest way round is the motion. A step
/// larger than the axis can turn in the time since the last sample (a reboot
/// resetting the count, a corrupted frame) is refused and tracking restarts
/// from the new value instead of teleporting the robot.
class PositionTracker {
 public:
  /// `wrap_turns`: 0 for a linear count. `max_turns_s`: the fastest the motor
  /// can turn, turns/s; steps beyond twice that rate are refused.
  void configure(float wrap_turns, float max_turns_s);

  enum class Step : uint8_t { First, Moved, Refused };
  /// Takes a new position (turns) at `time_us`; `delta_turns` is the motion
  /// since the previous accepted sample (0 for First and Refused).
  Step update(float pos_turns, uint64_t time_us, double& delta_turns);
  /// Forgets the last sample: the next one starts tracking afresh.
  void reset() { have_last_ = false; }

 private:
  float wrap_turns_ = 0;
  float max_turns_s_ = 0;
  bool have_last_ = false;
  float last_pos_ = 0;
  uint64_t last_us_ = 0;
};

}  // namespace troupe::drivers::odrive_can
