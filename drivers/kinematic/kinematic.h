// kinematic: an ideal differential-drive base. It integrates the commanded
// forward and turn velocities, within speed and acceleration limits, and
// publishes the odometry as position2d data. No hardware: it is the node's
// built-in robot for trying clients, and the reference the hardware drivers
// are compared against.
//
// Provides: position2d (exactly one).
// Commands: Vel (vx, va; vy is ignored: a differential drive cannot move
// sideways), Goto (turn towards the goal, drive, turn to its heading).
// Requests: Geometry, MotorPower, SetOdometry, ResetOdometry.
#pragma once

#include "runtime/driver.h"
#include "runtime/node_config.h"

namespace troupe::drivers::kinematic {

/// The base's motion state, SI units; a plain struct so tests can drive the
/// integration step directly.
struct Base {
  float x = 0, y = 0, a = 0;  // pose in the odometry frame: m, m, rad
  float v = 0, w = 0;         // current velocities: m/s, rad/s
  float target_v = 0, target_w = 0;
};

struct Limits {
  float max_speed, max_turn_rate, max_accel, max_turn_accel;  // m/s, rad/s, m/s^2, rad/s^2
};

/// Advances `base` by `dt_s` seconds: velocities move towards their targets
/// within the acceleration limits, then the pose follows the arc they trace.
void step(Base& base, const Limits& limits, float dt_s);

class Kinematic : public Driver {
 public:
  bool setup(Node& node, const DriverSetup& setup, std::string& error) override;
  void on_command(DeviceId device, const wire::Message& command) override;
  void on_request(DeviceId device, const wire::Message& request, RequestToken token) override;
  void on_timer(TimerId id) override;

 private:
  void steer_to_goal();
  void publish();

  DeviceId device_ = kNoDevice;
  Base base_;
  Limits limits_{};
  float length_ = 0, width_ = 0;
  uint64_t period_us_ = 0;
  uint64_t last_step_us_ = 0;
  uint64_t command_timeout_us_ = 0;
  uint64_t last_command_us_ = 0;
  bool motors_on_ = true;
  bool has_goal_ = false;
  wire::Pose2d goal_{};
  float goal_max_v_ = 0, goal_max_w_ = 0;
};

}  // namespace troupe::drivers::kinematic
