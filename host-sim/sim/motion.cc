// The position model: commands to velocities (within velocity and
// acceleration bounds), velocities to proposed poses, and after the
// collision phase, odometry and power.
#include <algorithm>
#include <cmath>

#include "host-sim/sim/engine.h"

namespace troupe::sim {
namespace {

// Stage's position-control gains: turn towards the goal, drive when facing it.
constexpr double kGotoSpeed = 0.4;         // m/s
constexpr double kGotoTurn = 1.0;          // rad/s
constexpr double kGotoCloseEnough = 0.02;  // m
constexpr double kGotoFacing = kPi / 16;   // rad
// Stage's motion power: watts per kilogram per (m/s or rad/s).
constexpr double kWattsPerKgPerSpeed = 10.0;

double clamp_range(double v, const Range& r) {
  return std::clamp(v, std::min(r.min, r.max), std::max(r.min, r.max));
}

Pose goto_velocity(const Pose& goal, const Odometry& o, Drive drive) {
  const Pose& est = o.estimate;
  double ex = goal.x - est.x, ey = goal.y - est.y;
  double dist = std::hypot(ex, ey);
  Pose v;
  if (drive == Drive::Omni) {
    // Errors in the robot frame, each axis driven on its own.
    double c = std::cos(est.a), s = std::sin(est.a);
    v.x = std::clamp(c * ex + s * ey, -kGotoSpeed, kGotoSpeed);
    v.y = std::clamp(-s * ex + c * ey, -kGotoSpeed, kGotoSpeed);
    v.a = std::clamp(wrap_angle(goal.a - est.a), -kGotoTurn, kGotoTurn);
    return v;
  }
  if (dist < kGotoCloseEnough) {
    v.a = std::clamp(wrap_angle(goal.a - est.a), -kGotoTurn, kGotoTurn);
    return v;
  }
  double err = wrap_angle(std::atan2(ey, ex) - est.a);
  v.a = std::clamp(err, -kGotoTurn, kGotoTurn);
  if (std::fabs(err) < kGotoFacing) v.x = std::min(dist, kGotoSpeed);
  return v;
}

}  // namespace

void Engine::control() {
  const double dt = desc.interval_sim;
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (!owns(RobotId(i))) continue;
    Body& b = bodies[i];
    const Kinematics& k = kinematics[i];
    Pose target;
    if (b.cmd.mode == CommandMode::Goto) {
      target = goto_velocity(b.cmd.value, odom[i], k.drive);
      if (k.drive == Drive::Car) target.a = std::atan2(target.a * k.wheelbase, std::max(target.x, 1e-3));
    } else {
      target = b.cmd.value;
    }
    switch (k.drive) {
      case Drive::Diff:
        target.y = 0;
        break;
      case Drive::Omni:
        break;
      case Drive::Car: {
        // Speed and steering angle to body velocities.
        const double v = target.x, steer = target.a;
        target = {v * std::cos(steer), 0, v * std::sin(steer) / k.wheelbase};
        break;
      }
    }
    if (b.disabled) target = {};
    target.x = clamp_range(target.x, k.velocity[0]);
    target.y = clamp_range(target.y, k.velocity[1]);
    target.a = clamp_range(target.a, k.velocity[2]);
    auto approach = [dt](double v, double to, const Range& acc) {
      return v + std::clamp(to - v, std::min(acc.min, 0.0) * dt, std::max(acc.max, 0.0) * dt);
    };
    b.vel.x = approach(b.vel.x, target.x, k.acceleration[0]);
    b.vel.y = approach(b.vel.y, target.y, k.acceleration[1]);
    b.vel.a = approach(b.vel.a, target.a, k.acceleration[2]);
  }
}

void Engine::integrate() {
  const double dt = desc.interval_sim;
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (owns(RobotId(i))) integrate_body(bodies[i], dt);
  }
}

void Engine::integrate_body(Body& b, double dt) {
  const double vx = b.vel.x, vy = b.vel.y, w = b.vel.a;
  if (vx == 0 && vy == 0 && w == 0) {
    b.proposed = b.pose;
    b.moved = false;
    return;
  }
  // Exact motion under a constant body twist: the displacement in the
  // starting frame, then rotated into the world.
  double dx, dy;
  const double th = w * dt;
  if (std::fabs(th) < 1e-9) {
    dx = vx * dt;
    dy = vy * dt;
  } else {
    const double s = std::sin(th) / w, c = (1 - std::cos(th)) / w;
    dx = s * vx - c * vy;
    dy = c * vx + s * vy;
  }
  const double ca = std::cos(b.pose.a), sa = std::sin(b.pose.a);
  b.proposed = {b.pose.x + ca * dx - sa * dy, b.pose.y + sa * dx + ca * dy, wrap_angle(b.pose.a + th)};
  b.moved = true;
}

void Engine::odometry() {
  const double dt = desc.interval_sim;
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (!owns(RobotId(i))) continue;
    Body& b = bodies[i];
    Odometry& o = odom[i];
    if (kinematics[i].localization == Localization::Gps) {
      o.estimate = relative(o.origin, b.pose);
    } else if (b.moved) {
      // Dead reckoning with this robot's scale errors, midpoint heading.
      const double da = b.vel.a * dt * (1 + o.error.a);
      const double dx = b.vel.x * dt * (1 + o.error.x), dy = b.vel.y * dt * (1 + o.error.y);
      const double mid = o.estimate.a + da / 2;
      o.estimate.x += dx * std::cos(mid) - dy * std::sin(mid);
      o.estimate.y += dx * std::sin(mid) + dy * std::cos(mid);
      o.estimate.a = wrap_angle(o.estimate.a + da);
    }
    PowerState& p = power[i];
    if (p.enabled) {
      const double speed = b.moved ? std::fabs(b.vel.x) + std::fabs(b.vel.y) + std::fabs(b.vel.a) : 0;
      p.watts = p.base_watts + kWattsPerKgPerSpeed * desc.robots[i].mass * speed;
      p.joules = std::max(0.0, p.joules - p.watts * dt);
      b.disabled = p.joules <= 0;
    }
  }
}

void Engine::publish_states() {
  for (size_t i = 0; i < bodies.size(); ++i) {
    const Body& b = bodies[i];
    states[i] = {b.pose, b.vel, odom[i].estimate, b.stalled, b.disabled};
  }
}

}  // namespace troupe::sim
