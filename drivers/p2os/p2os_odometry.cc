#include "drivers/p2os/p2os_odometry.h"

#include <cmath>
#include <cstdlib>

namespace troupe::drivers::p2os {
namespace {

constexpr uint32_t kPositionModulus = 0x8000;  // 15-bit counters

using geometry::compose;
using geometry::wrap_angle;

Pose inverse(const Pose& p) {
  return geometry::relative(p, {});
}

// A 15-bit counter read as a signed offset from zero.
int signed15(uint16_t v) {
  return v >= 0x4000 ? int(v) - int(kPositionModulus) : int(v);
}

}  // namespace

int wrap_delta(uint32_t from, uint32_t to, uint32_t modulus) {
  int d = int((to - from) % modulus);
  if (d < 0) d += int(modulus);
  return d > int(modulus / 2) ? d - int(modulus) : d;
}

Pose Odometry::robot_pose() const {
  return {robot_x_mm_ / 1000.0, robot_y_mm_ / 1000.0, robot_a_};
}

Pose Odometry::pose() const {
  return compose(frame_, robot_pose());
}

void Odometry::set_pose(const Pose& p) {
  frame_ = compose(p, inverse(robot_pose()));
}

void Odometry::reset() {
  frame_ = inverse(robot_pose());
  reset_wait_ = kResetWaitSips;
}

Odometry::Update Odometry::update(const Sip& sip) {
  const double heading = wrap_angle(sip.heading * params_->angle_conv);
  if (!have_reference_) {
    // The reported pose carries on from where it was: only the reference
    // of the robot's counters changes.
    Pose before = pose();
    have_reference_ = true;
    jumps_in_row_ = 0;
    last_x_ = sip.x;
    last_y_ = sip.y;
    robot_a_ = heading;
    frame_ = compose(before, inverse(robot_pose()));
    return Update::First;
  }
  robot_a_ = heading;
  if (reset_wait_ > 0) {
    // After SETO the counters restart: the first SIP whose counters lie
    // within what the robot can have moved since (two SIP periods at its
    // wheel speed, plus slack) is taken as the restart. The robot's frame
    // then begins at its origin again, and the reported frame with it.
    double speed_mm_s = 0.5 * std::fabs((sip.left_vel + sip.right_vel) * params_->vel_conv);
    double turn_rad_s =
        0.5 * std::fabs((sip.right_vel - sip.left_vel) * params_->vel_conv) * params_->diff_conv;
    double reach_mm = 20.0 + 0.2 * speed_mm_s;
    double reach_rad = 0.05 + 0.2 * turn_rad_s;
    double sx = signed15(sip.x) * params_->dist_conv, sy = signed15(sip.y) * params_->dist_conv;
    if (std::fabs(sx) <= reach_mm && std::fabs(sy) <= reach_mm && std::fabs(robot_a_) <= reach_rad) {
      reset_wait_ = 0;
      last_x_ = sip.x;
      last_y_ = sip.y;
      robot_x_mm_ = sx;
      robot_y_mm_ = sy;
      frame_ = Pose{};
      return Update::Rebased;
    }
    if (--reset_wait_ == 0) {
      // The robot ignored SETO: carry on with the driver-side reset alone.
      Update u = update(sip);
      return u == Update::Moved ? Update::ResetIgnored : u;
    }
  }
  int dx = wrap_delta(last_x_, sip.x, kPositionModulus);
  int dy = wrap_delta(last_y_, sip.y, kPositionModulus);
  double dx_mm = dx * params_->dist_conv, dy_mm = dy * params_->dist_conv;
  if (std::fabs(dx_mm) > kMaxJumpMm || std::fabs(dy_mm) > kMaxJumpMm) {
    if (++jumps_in_row_ < kJumpsToRebase) return Update::JumpRejected;
    jumps_in_row_ = 0;
    last_x_ = sip.x;
    last_y_ = sip.y;
    return Update::JumpAccepted;
  }
  jumps_in_row_ = 0;
  last_x_ = sip.x;
  last_y_ = sip.y;
  robot_x_mm_ += dx_mm;
  robot_y_mm_ += dy_mm;
  return Update::Moved;
}

}  // namespace troupe::drivers::p2os
