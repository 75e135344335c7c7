// Recording a robot's motion for the learned motion model: the robot is
// driven with seeded random commands on an otherwise empty field and every
// cycle is written in the motion log format (plugins/learned_motion/
// motion_model.h). When it nears the edge it is carried back to the centre
// and the log gets a `break`. Now and then it is pushed (a random velocity
// change, as a collision would give), so the log also shows how the drive
// takes out motion it did not command.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>

#include "host-sim/robocup/game/simulation.h"

namespace troupe::robocup {

struct MotionLogSettings {
  /// Simulated time to record, s.
  double seconds = 120;
  uint64_t seed = 1;
  /// Command ranges: m/s forward, m/s sideways, rad/s; each command is
  /// held for a random time in [hold_min_s, hold_max_s].
  double max_vx = 2, min_vx = -1, max_vy = 1, max_w = 4;
  double hold_min_s = 0.2, hold_max_s = 1.5;
  /// Pushes per second (on average) and their largest speed change, m/s.
  double push_rate = 0.5, push_speed = 0.5;
};

/// Drives robot `robot` of `sim` and writes its log to `out`.
bool write_motion_log(Simulation& sim, int robot, const MotionLogSettings& settings, std::ostream& out,
                      std::string& error);

}  // namespace troupe::robocup
