// A motion model learned from a logged run: from (velocity, command) to
// the velocity one cycle later. Per axis it is a linear combination of a
// fixed basis: the velocity, the command, the velocity turned by the spin
// (a robot-frame velocity changes as the robot turns), and clipped ramps of
// the velocity error and of the command at several scales. Clipped ramps
// add up to any monotone saturating curve, which is what acceleration and
// speed limits look like, so the model stays a small least-squares fit.
//
// Log format (one line per cycle, robot frame, SI units; '#' comments):
//   time_s vx vy w cmd_vx cmd_vy cmd_w
// The command on a line is the one applied from that time until the next
// line. A line `break` ends a segment (the robot was moved by hand).
#pragma once

#include <span>
#include <string>
#include <vector>

#include "host-sim/robocup/api/plugin.h"

namespace troupe::robocup {

struct MotionSample {
  /// Robot-frame velocity (m/s, m/s, rad/s), the command applied, and the
  /// velocity one cycle later.
  Twist velocity;
  MotionCommand command;
  Twist next;
};

class MotionModel {
 public:
  static constexpr int kFeatures = 45;

  /// Least-squares fit (slightly regularised) on `samples` taken every
  /// `cycle_s` seconds. False with `error` when there are too few.
  static bool fit(std::span<const MotionSample> samples, double cycle_s, MotionModel& out,
                  std::string& error);
  /// The velocity one cycle after `velocity` under `command`.
  Twist predict(const Twist& velocity, const MotionCommand& command) const;
  /// The cycle the model was trained at, s: it predicts one such step.
  double cycle_s() const { return cycle_s_; }

  bool save(const std::string& path, std::string& error) const;
  /// False with "path:line: why" on anything malformed.
  static bool load(const std::string& path, MotionModel& out, std::string& error);

 private:
  static void features(const Twist& v, const MotionCommand& c, double* phi);
  double cycle_s_ = 0;
  double weights_[3][kFeatures] = {};
};

/// Reads a motion log into samples and the median cycle, s.
bool read_motion_log(const std::string& path, std::vector<MotionSample>& out, double& cycle_s,
                     std::string& error);

}  // namespace troupe::robocup
