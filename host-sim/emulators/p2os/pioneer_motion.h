// The motion controller of P2OS/AROS firmware, as its manual describes it:
// two independent axes, translation and rotation, each either held at a
// velocity (VEL, RVEL/ROTATE) or driven to a position (MOVE: a distance;
// HEAD, DHEAD, DCHEAD: a heading), with a trapezoidal profile: accelerate
// at the set acceleration up to the set top speed, decelerate at the set
// deceleration so as to stop on the target. VEL2 bypasses both and sets
// the wheels, ramped at the translational limits. STOP decelerates both
// axes to rest; ESTOP stops at once.
//
// No I/O, no clock: update(dt) advances the profile. SI units throughout
// (m, m/s, m/s^2, rad, rad/s, rad/s^2).
#pragma once

#include <cstdint>

namespace troupe::emulators {

/// The limits a client sets (SETV, SETA, SETRV, SETRA).
struct MotionLimits {
  double trans_vel_max = 0.75;  // m/s
  double trans_accel = 1.0;     // m/s^2
  double trans_decel = 1.0;     // m/s^2
  double rot_vel_max = 1.75;    // rad/s
  double rot_accel = 5.2;       // rad/s^2
  double rot_decel = 5.2;       // rad/s^2
};

class PioneerMotion {
 public:
  enum class Trans : uint8_t { Velocity, Distance };
  enum class Rot : uint8_t { Velocity, Heading };

  MotionLimits limits;
  /// Fastest the wheels turn, m/s; half the wheel track, m.
  double wheel_max = 2.0, half_track = 0.17;

  /// VEL: translate at `v` m/s (clamped to the top speed).
  void set_velocity(double v);
  /// MOVE: translate `distance_m` (signed) and stop there.
  void move(double distance_m);
  /// RVEL, ROTATE: turn at `w` rad/s (clamped to the top turn rate).
  void set_turn_rate(double w);
  /// HEAD: turn to `heading` rad in the odometric frame and hold it.
  void set_heading(double heading);
  /// The heading the rotation axis aims at, rad (the current heading when
  /// it holds a turn rate).
  double heading_setpoint(double current_heading) const;
  /// VEL2: wheel speeds, m/s.
  void set_wheels(double left, double right);
  /// STOP: both axes decelerate to rest.
  void stop();
  /// ESTOP, motors off, a stall: at rest now.
  void halt();

  /// Advances the profile by `dt` s; `heading` is the robot's odometric
  /// heading (rad) and `travelled` the distance driven (m, signed) since
  /// the last update. Afterwards left()/right() are the wheel speeds.
  void update(double dt, double heading, double travelled);

  double v() const { return v_; }
  double w() const { return w_; }
  double left() const { return wheels_ ? left_ : v_ - w_ * half_track; }
  double right() const { return wheels_ ? right_ : v_ + w_ * half_track; }
  /// What the wheels are driven towards, m/s.
  double target_left() const;
  double target_right() const;
  Rot rot_mode() const { return rot_; }
  /// Metres of a MOVE still to go (0 in velocity mode).
  double remaining() const { return trans_ == Trans::Distance ? remaining_ : 0; }

 private:
  bool wheels_ = false;  // VEL2 in force
  Trans trans_ = Trans::Velocity;
  Rot rot_ = Rot::Velocity;
  double v_ = 0, w_ = 0;                  // now
  double v_target_ = 0, w_target_ = 0;    // velocity modes
  double remaining_ = 0;                  // Distance mode, m
  double heading_target_ = 0;             // Heading mode, rad
  double left_ = 0, right_ = 0, left_target_ = 0, right_target_ = 0;  // VEL2
};

}  // namespace troupe::emulators
