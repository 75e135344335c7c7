// The differential-drive odometry motion model (Thrun, Burgard, Fox,
// "Probabilistic Robotics", sample_motion_model_odometry): a motion between
// two odometry poses is a turn, a straight move and a second turn, each
// perturbed by noise that grows with the size of the motion.
#pragma once

#include "drivers/common_desktop/pose2.h"
#include "drivers/common_desktop/rng.h"

namespace troupe::desktop {

/// Noise of the odometry motion model. Each turn's variance is
/// rot_rot * turn^2 + rot_trans * distance^2; the distance's variance is
/// trans_trans * distance^2 + trans_rot * (turn1^2 + turn2^2).
struct MotionNoise {
  double rot_rot = 0.2;      // rad^2 per rad^2 turned (alpha1)
  double rot_trans = 0.2;    // rad^2 per m^2 travelled (alpha2)
  double trans_trans = 0.2;  // m^2 per m^2 travelled (alpha3)
  double trans_rot = 0.2;    // m^2 per rad^2 turned (alpha4)
};

/// The three parts of a motion between odometry poses `from` and `to`.
struct OdometryMotion {
  double rot1 = 0;   // turn before moving, rad
  double trans = 0;  // straight distance, m
  double rot2 = 0;   // turn after moving, rad
};

/// Splits the motion between two odometry poses. A motion shorter than 1 mm
/// is a pure turn (its direction is noise). A backward move gets rot1 near
/// pi: see noise_turn().
OdometryMotion decompose(const Pose2& from, const Pose2& to);

/// The size of a turn for the noise: a backward move's turn of ~pi is in
/// truth a small turn plus reversing, so min(|t|, pi - |t|), rad.
double noise_turn(double rot_rad);

/// One noisy sample of the motion applied to `pose`.
Pose2 sample_motion(const Pose2& pose, const OdometryMotion& motion, const MotionNoise& noise, Rng& rng);

}  // namespace troupe::desktop
