#include "examples/robocup/striker/striker.h"

#include <algorithm>
#include <cmath>

#include "wire/geometry.h"

namespace troupe::examples {
namespace {

using geometry::wrap_angle;

/// Drive towards a robot-frame point: turn towards it, go forward as far
/// as it lies ahead.
StrikerAction drive_to(const StrikerOptions& o, double x, double y, double speed_scale) {
  const double bearing = std::atan2(y, x), distance = std::hypot(x, y);
  StrikerAction a;
  a.w = std::clamp(3.0 * bearing, -o.max_turn, o.max_turn);
  const double ahead = std::max(0.0, std::cos(bearing));
  a.vx = o.max_speed * speed_scale * ahead * ahead * std::min(1.0, 1.5 * distance);
  return a;
}

}  // namespace

StrikerAction decide(const StrikerOptions& o, bool ball_seen, double ball_distance, double ball_bearing,
                     double goal_distance, double goal_bearing) {
  if (!ball_seen) {
    StrikerAction a;
    a.w = o.max_turn / 2;  // look around
    return a;
  }
  const double bx = ball_distance * std::cos(ball_bearing), by = ball_distance * std::sin(ball_bearing);
  const bool goal_seen = goal_distance > 0;
  // Lined up: ball and goal in nearly the same direction, ball in front.
  const bool aligned = !goal_seen || std::abs(wrap_angle(ball_bearing - goal_bearing)) < 0.3;
  if (ball_distance < o.kick_distance && std::abs(ball_bearing) < 0.35 && aligned) {
    StrikerAction a = drive_to(o, bx, by, 0.5);
    a.kick = true;
    a.mode = "kick";
    return a;
  }
  if (aligned && std::abs(ball_bearing) < 0.5) {
    StrikerAction a = drive_to(o, bx, by, 1.0);
    a.mode = "dribble";
    return a;
  }
  // The point behind the ball, on the line from the goal through it.
  const double gx = goal_distance * std::cos(goal_bearing), gy = goal_distance * std::sin(goal_bearing);
  const double ux = bx - gx, uy = by - gy, n = std::max(1e-6, std::hypot(ux, uy));
  StrikerAction a = drive_to(o, bx + ux / n * o.line_up, by + uy / n * o.line_up, 1.0);
  a.mode = "line up";
  return a;
}

Striker::Striker(client::Client& client, StrikerOptions options)
    : client_(client), options_(std::move(options)), sensors_(client) {}

bool Striker::start(std::string& error) {
  if (!sensors_.add_robot(options_.robot, error)) return false;
  sensors_.set_team(options_.team);
  const auto bases = sensors_.of_type(wire::Interface::Position2d);
  const auto kickers = sensors_.of_type(wire::Interface::Actuator);
  if (bases.empty()) {
    error = "robot '" + options_.robot + "' has no position2d device";
    return false;
  }
  base_ = static_cast<client::Position2dProxy*>(bases.front());
  kicker_ = kickers.empty() ? nullptr : static_cast<client::ActuatorProxy*>(kickers.front());
  return true;
}

StrikerAction Striker::tick() {
  const auto ball_distance = sensors_.feature("ballDistance");
  const auto ball_bearing = sensors_.feature("ballBearing");
  const auto goal_distance = sensors_.feature("goalDistance");
  const auto goal_bearing = sensors_.feature("goalBearing");
  const bool goal = goal_distance && goal_bearing;
  StrikerAction a = decide(options_, ball_distance && ball_bearing, ball_distance ? ball_distance->value : 0,
                           ball_bearing ? ball_bearing->value : 0, goal ? goal_distance->value : 0,
                           goal ? goal_bearing->value : 0);
  base_->set_velocity(float(a.vx), 0, float(a.w));
  // The kicker reports Kicking and then Ready again after a kick: until both
  // came, a kick sent is still under way.
  if (a.kick && kicker_ != nullptr && kicker_->mode() == wire::ActuatorMode::Ready &&
      int64_t(kicker_->samples()) >= kick_samples_ + 2) {
    kicker_->kick();
    kick_samples_ = int64_t(kicker_->samples());
    ++kicks_;
  }
  return a;
}

}  // namespace troupe::examples
