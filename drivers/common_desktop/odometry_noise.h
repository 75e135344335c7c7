// Odometry made from known poses: the true (or SLAM-corrected) motion
// between consecutive poses, corrupted the way wheel odometry goes wrong.
// troupe-mcl-eval and the logreplay driver use it to turn a corrected log
// into a localization test with a known answer.
#pragma once

#include "drivers/common_desktop/pose2.h"
#include "drivers/common_desktop/rng.h"

namespace troupe::desktop {

struct OdometryNoise {
  /// Drift, drawn once per run: a wheel-diameter error scales every
  /// distance by 1 + N(0, scale_sigma) (fraction), and an unequal-wheel
  /// error turns the robot by N(0, turn_bias_sigma) rad per m travelled.
  double scale_sigma = 0.02;
  double turn_bias_sigma = 0.02;
  /// Random error per step: distance sigma = trans_per_m * distance (m/m);
  /// heading sigma = rot_per_rad * |turn| + rot_per_m * distance (rad/rad,
  /// rad/m).
  double trans_per_m = 0.03;
  double rot_per_rad = 0.03;
  double rot_per_m = 0.01;
  /// Slip: with this probability per step the wheels spin, and odometry
  /// reports up to slip_max_extra more distance than was travelled (a
  /// uniform share 0..slip_max_extra of the step).
  double slip_probability = 0.02;
  double slip_max_extra = 0.5;
};

class OdometrySynthesizer {
 public:
  /// Draws the run's drift from `rng`; odometry starts at `odom_start`.
  OdometrySynthesizer(const OdometryNoise& noise, Rng& rng, Pose2 odom_start = {});

  /// The odometry pose after the robot moved to `truth`. The first call
  /// only records where the robot is and returns the start pose.
  Pose2 next(const Pose2& truth, Rng& rng);

  double scale() const { return scale_; }
  double turn_bias() const { return turn_bias_; }  // rad/m

 private:
  OdometryNoise noise_;
  double scale_ = 1;
  double turn_bias_ = 0;
  bool started_ = false;
  Pose2 last_truth_;
  Pose2 odom_;
};

}  // namespace troupe::desktop
