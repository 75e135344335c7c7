#include "drivers/odrive_can/diff_drive.h"

#include <algorithm>
#include <cmath>

namespace troupe::drivers::odrive_can {
namespace {

constexpr double kTwoPi = 6.283185307179586;
// Samples queued behind a busy loop arrive back to back, so the time between
// arrivals understates the time between measurements: never judge a step
// over less than this, s.
constexpr double kMinJudgedInterval = 0.1;
// Allowance for estimator noise, turns.
constexpr double kStepMarginTurns = 0.05;

}  // namespace

WheelTurnRates wheel_rates(float v, float w, const DriveGeometry& g, float max_wheel_turns_s) {
  const float per_turn = float(kTwoPi) * g.wheel_radius;  // m of travel per wheel turn
  float left = (v - w * g.track_width * 0.5f) / per_turn;
  float right = (v + w * g.track_width * 0.5f) / per_turn;
  float fastest = std::max(std::fabs(left), std::fabs(right));
  if (max_wheel_turns_s > 0 && fastest > max_wheel_turns_s) {
    float scale = max_wheel_turns_s / fastest;
    left *= scale;
    right *= scale;
  }
  return {g.invert_left ? -left : left, g.invert_right ? -right : right};
}

void body_velocity(const WheelTurnRates& motor, const DriveGeometry& g, float& v, float& w) {
  const float per_turn = float(kTwoPi) * g.wheel_radius;
  float left = (g.invert_left ? -motor.left : motor.left) * per_turn;
  float right = (g.invert_right ? -motor.right : motor.right) * per_turn;
  v = 0.5f * (left + right);
  w = (right - left) / g.track_width;
}

void integrate(Odometry& odom, double left_m, double right_m, double track_width) {
  double ds = 0.5 * (left_m + right_m);
  double da = (right_m - left_m) / track_width;
  // Wheels turning at constant rates trace an arc: its chord points along
  // the mean heading and is shorter than the arc by sin(h)/h, h = da/2.
  double h = 0.5 * da;
  double chord = std::fabs(h) < 1e-9 ? ds : ds * std::sin(h) / h;
  odom.x += chord * std::cos(odom.a + h);
  odom.y += chord * std::sin(odom.a + h);
  odom.a = std::remainder(odom.a + da, kTwoPi);
}

void PositionTracker::configure(float wrap_turns, float max_turns_s) {
  wrap_turns_ = wrap_turns;
  max_turns_s_ = max_turns_s;
  have_last_ = false;
}

PositionTracker::Step PositionTracker::update(float pos_turns, uint64_t time_us, double& delta_turns) {
  delta_turns = 0;
  if (!std::isfinite(pos_turns)) return Step::Refused;
  if (!have_last_) {
    have_last_ = true;
    last_pos_ = pos_turns;
    last_us_ = time_us;
    return Step::First;
  }
  double delta = double(pos_turns) - double(last_pos_);
  if (wrap_turns_ > 0) delta = std::remainder(delta, double(wrap_turns_));
  double dt = std::max(double(time_us - last_us_) * 1e-6, kMinJudgedInterval);
  last_pos_ = pos_turns;
  last_us_ = time_us;
  if (std::fabs(delta) > 2.0 * double(max_turns_s_) * dt + kStepMarginTurns) return Step::Refused;
  delta_turns = delta;
  return Step::Moved;
}

}  // namespace troupe::drivers::odrive_can
