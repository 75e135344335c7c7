// A client-controlled RoboCup striker: drives one robot over the wire from
// features (ball and goal distance and bearing, whichever sensor sees
// them): get behind the ball on the line from the goal, drive through it,
// kick when it touches the kicker and the goal is ahead.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "examples/robocup/sensor_container.h"

namespace troupe::examples {

struct StrikerOptions {
  std::string robot = "yellow3";
  Team team = Team::Yellow;
  /// m/s, rad/s.
  double max_speed = 1.5, max_turn = 4;
  /// Centre-to-centre distance at which the ball touches the kicker, m.
  double kick_distance = 0.40;
  /// How far behind the ball (away from the goal) to line up, m.
  double line_up = 0.45;
};

/// What the striker decided in one tick (for logs and tests).
struct StrikerAction {
  /// Robot-frame command: m/s forward, rad/s.
  double vx = 0, w = 0;
  bool kick = false;
  /// "search", "line up", "dribble", "kick".
  const char* mode = "search";
};

/// The decision alone: from features to a command. Distances in m,
/// bearings in rad (robot frame); a goal distance <= 0 means not seen.
StrikerAction decide(const StrikerOptions& options, bool ball_seen, double ball_distance, double ball_bearing,
                     double goal_distance, double goal_bearing);

class Striker {
 public:
  Striker(client::Client& client, StrikerOptions options);
  /// Finds the robot's devices. False with `error`.
  bool start(std::string& error);
  /// Reads the features, decides and sends the command (and a kick).
  StrikerAction tick();
  /// Kicks fired so far.
  uint32_t kicks() const { return kicks_; }
  SensorContainer& sensors() { return sensors_; }

 private:
  client::Client& client_;
  StrikerOptions options_;
  SensorContainer sensors_;
  client::Position2dProxy* base_ = nullptr;
  client::ActuatorProxy* kicker_ = nullptr;
  uint32_t kicks_ = 0;
  /// The kicker's sample count when the last kick was sent.
  int64_t kick_samples_ = -2;
};

}  // namespace troupe::examples
