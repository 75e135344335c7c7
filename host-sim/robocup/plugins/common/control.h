// Driving helpers for player plugins: commands that bring a robot to a
// point and heading, for holonomic (omni) and differential drives, and the
// approach-and-kick manoeuvre shared by strikers.
#pragma once

#include <algorithm>
#include <cmath>

#include "host-sim/robocup/api/plugin.h"

namespace troupe::robocup::plugins {

struct DriveLimits {
  /// m/s and rad/s.
  double max_speed = 1.5, max_turn = 4;
  /// Proportional gains: 1/s (position), 1/s (heading).
  double gain = 3, turn_gain = 4;
  /// Close enough to a target point, m.
  double tolerance = 0.03;
};

/// Holonomic: straight to `target` (world, m) while turning to `heading`
/// (world, rad).
inline MotionCommand omni_to(const Pose2& me, Vec2 target, double heading, const DriveLimits& l) {
  Vec2 v = (target - me.position()) * l.gain;
  if (length(v) > l.max_speed) v = normalized(v) * l.max_speed;
  const Vec2 local = rotate(v, -me.a);
  const double w = std::clamp(l.turn_gain * wrap_angle(heading - me.a), -l.max_turn, l.max_turn);
  return {local.x, local.y, w};
}

/// Differential: turn towards `target` and drive (backwards when it is
/// close behind), then turn to `heading` once there.
inline MotionCommand diff_to(const Pose2& me, Vec2 target, double heading, const DriveLimits& l) {
  const Vec2 d = target - me.position();
  const double dist = length(d);
  if (dist < l.tolerance)
    return {0, 0, std::clamp(l.turn_gain * wrap_angle(heading - me.a), -l.max_turn, l.max_turn)};
  double err = wrap_angle(std::atan2(d.y, d.x) - me.a);
  double sign = 1;
  if (std::fabs(err) > kPi / 2 && dist < 1.0) {
    err = wrap_angle(err + kPi);
    sign = -1;
  }
  const double w = std::clamp(l.turn_gain * err, -l.max_turn, l.max_turn);
  const double v = std::min(l.max_speed, l.gain * dist) * std::max(0.0, std::cos(err)) * sign;
  return {v, 0, w};
}

inline MotionCommand drive_to(bool omni, const Pose2& me, Vec2 target, double heading, const DriveLimits& l) {
  return omni ? omni_to(me, target, heading, l) : diff_to(me, target, heading, l);
}

/// Approach-and-kick: get behind the ball on the line to `aim`, face it,
/// drive through the ball and kick when it is at the kicker.
struct ShotSettings {
  /// Robot front (kicker plate) ahead of its origin, m; ball radius, m.
  double front = 0.25, ball_radius = 0.11;
  /// Speed driving onto the ball, m/s.
  double charge_speed = 1.0;
  /// Kick when the ball is this close to the plate, m.
  double kick_gap = 0.05;
};

struct ShotStep {
  MotionCommand command;
  bool kick = false;
  /// True while driving onto the ball (aligned).
  bool charging = false;
};

inline ShotStep shoot(bool omni, const Pose2& me, Vec2 ball, Vec2 aim, bool kicker_ready,
                      const ShotSettings& s, const DriveLimits& l) {
  ShotStep out;
  const Vec2 dir = normalized(aim - ball);
  const double heading = std::atan2(dir.y, dir.x);
  const Vec2 local = me.to_local(ball);
  const double reach = s.front + s.ball_radius;
  const bool aligned =
      std::fabs(wrap_angle(heading - me.a)) < 0.15 && std::fabs(local.y) < 0.07 && local.x > 0;
  if (aligned && local.x < reach + 0.4) {
    out.charging = true;
    out.command = {s.charge_speed, omni ? std::clamp(3 * local.y, -0.3, 0.3) : 0.0,
                   std::clamp(l.turn_gain * wrap_angle(heading - me.a), -l.max_turn, l.max_turn)};
    out.kick = kicker_ready && local.x < reach + s.kick_gap;
    return out;
  }
  // Behind the ball; detour sideways when standing on the wrong side.
  Vec2 target = ball - dir * (reach + 0.2);
  const Vec2 from_ball = me.position() - ball;
  if (dot(from_ball, dir) > -0.1) {
    const double side = cross(dir, from_ball) >= 0 ? 1 : -1;
    target = ball - dir * (reach + 0.3) + perp(dir) * (side * (reach + 0.3));
  }
  DriveLimits careful = l;
  careful.tolerance = 0.04;
  out.command = drive_to(omni, me, target, heading, careful);
  if (!omni && length(target - me.position()) < 0.05) {
    out.command = {0, 0, std::clamp(l.turn_gain * wrap_angle(heading - me.a), -l.max_turn, l.max_turn)};
  }
  return out;
}

}  // namespace troupe::robocup::plugins
