#include "host-sim/emulators/p2os/pioneer_motion.h"

#include <algorithm>
#include <cmath>

namespace troupe::emulators {
namespace {

constexpr double kPi = 3.14159265358979323846;
// A position target counts as reached this close: 0.5 mm, 0.05 degree.
constexpr double kDistanceDone = 0.0005, kHeadingDone = 0.05 * kPi / 180;

double wrap(double a) {
  return std::remainder(a, 2 * kPi);
}

// One axis one step closer to `want`: speeding up at `accel`, slowing down
// (or reversing) at `decel`.
double ramp(double now, double want, double accel, double decel, double dt) {
  const bool slowing = (now > 0 && want < now) || (now < 0 && want > now);
  const double step = (slowing ? decel : accel) * dt;
  return now + std::clamp(want - now, -step, step);
}

// The speed to drive towards a target `error` away: as fast as allowed,
// yet slow enough to stop on it at `decel` in steps of `dt` (a speed v
// covers v^2 / 2a + v dt / 2 while it brakes step by step).
double approach_speed(double error, double top, double decel, double dt) {
  const double half_step = decel * dt / 2;
  const double v = -half_step + std::sqrt(half_step * half_step + 2 * decel * std::fabs(error));
  return std::copysign(std::min(top, v), error);
}

// A position axis must not step past its target: the last step lands on it.
double no_overshoot(double speed, double error, double dt) {
  if (dt > 0 && speed * error > 0 && std::fabs(speed * dt) > std::fabs(error)) return error / dt;
  return speed;
}

}  // namespace

void PioneerMotion::set_velocity(double v) {
  wheels_ = false;
  trans_ = Trans::Velocity;
  v_target_ = std::clamp(v, -limits.trans_vel_max, limits.trans_vel_max);
}

void PioneerMotion::move(double distance) {
  wheels_ = false;
  trans_ = Trans::Distance;
  remaining_ = distance;
}

void PioneerMotion::set_turn_rate(double w) {
  wheels_ = false;
  rot_ = Rot::Velocity;
  w_target_ = std::clamp(w, -limits.rot_vel_max, limits.rot_vel_max);
}

void PioneerMotion::set_heading(double heading) {
  wheels_ = false;
  rot_ = Rot::Heading;
  heading_target_ = wrap(heading);
}

double PioneerMotion::heading_setpoint(double current) const {
  return rot_ == Rot::Heading ? heading_target_ : current;
}

void PioneerMotion::set_wheels(double left_mps, double right_mps) {
  if (!wheels_) {
    left_ = left();
    right_ = right();
  }
  wheels_ = true;
  left_target_ = std::clamp(left_mps, -wheel_max, wheel_max);
  right_target_ = std::clamp(right_mps, -wheel_max, wheel_max);
}

void PioneerMotion::stop() {
  if (wheels_) {
    left_target_ = right_target_ = 0;
    return;
  }
  trans_ = Trans::Velocity;
  rot_ = Rot::Velocity;
  v_target_ = w_target_ = 0;
}

void PioneerMotion::halt() {
  stop();
  v_ = w_ = left_ = right_ = 0;
}

double PioneerMotion::target_left() const {
  if (wheels_) return left_target_;
  return (trans_ == Trans::Velocity ? v_target_ : v_) - (rot_ == Rot::Velocity ? w_target_ : w_) * half_track;
}

double PioneerMotion::target_right() const {
  if (wheels_) return right_target_;
  return (trans_ == Trans::Velocity ? v_target_ : v_) + (rot_ == Rot::Velocity ? w_target_ : w_) * half_track;
}

void PioneerMotion::update(double dt, double heading, double travelled) {
  if (dt <= 0) return;
  if (wheels_) {
    left_ = ramp(left_, left_target_, limits.trans_accel, limits.trans_decel, dt);
    right_ = ramp(right_, right_target_, limits.trans_accel, limits.trans_decel, dt);
    v_ = 0.5 * (left_ + right_);
    w_ = (right_ - left_) / (2 * half_track);
    return;
  }
  if (trans_ == Trans::Distance) {
    remaining_ -= travelled;
    if (std::fabs(remaining_) < kDistanceDone && std::fabs(v_) < limits.trans_decel * dt) {
      trans_ = Trans::Velocity;
      v_target_ = v_ = remaining_ = 0;
    } else {
      double want = approach_speed(remaining_, limits.trans_vel_max, limits.trans_decel, dt);
      v_ = no_overshoot(ramp(v_, want, limits.trans_accel, limits.trans_decel, dt), remaining_, dt);
    }
  } else {
    v_ = ramp(v_, v_target_, limits.trans_accel, limits.trans_decel, dt);
  }
  if (rot_ == Rot::Heading) {
    double error = wrap(heading_target_ - heading);
    if (std::fabs(error) < kHeadingDone && std::fabs(w_) < limits.rot_decel * dt) {
      w_ = 0;  // holds the heading: the axis stays in heading mode
    } else {
      double want = approach_speed(error, limits.rot_vel_max, limits.rot_decel, dt);
      w_ = no_overshoot(ramp(w_, want, limits.rot_accel, limits.rot_decel, dt), error, dt);
    }
  } else {
    w_ = ramp(w_, w_target_, limits.rot_accel, limits.rot_decel, dt);
  }
  // The wheels cannot go faster than they can: scale both axes down alike.
  double fastest = std::max(std::fabs(v_ - w_ * half_track), std::fabs(v_ + w_ * half_track));
  if (fastest > wheel_max) {
    v_ *= wheel_max / fastest;
    w_ *= wheel_max / fastest;
  }
}

}  // namespace troupe::emulators
