#include "drivers/common_desktop/odometry_noise.h"

#include "drivers/common_desktop/motion_model.h"

namespace troupe::desktop {

OdometrySynthesizer::OdometrySynthesizer(const OdometryNoise& noise, Rng& rng, Pose2 odom_start)
    : noise_(noise), odom_(odom_start) {
  scale_ = 1.0 + gaussian(rng, noise.scale_sigma);
  turn_bias_ = gaussian(rng, noise.turn_bias_sigma);
}

Pose2 OdometrySynthesizer::next(const Pose2& truth, Rng& rng) {
  if (!started_) {
    started_ = true;
    last_truth_ = truth;
    return odom_;
  }
  OdometryMotion m = decompose(last_truth_, truth);
  last_truth_ = truth;
  double d = m.trans;
  double trans = d * scale_ + gaussian(rng, noise_.trans_per_m * d);
  if (noise_.slip_probability > 0 && uniform01(rng) < noise_.slip_probability) {
    trans += d * noise_.slip_max_extra * uniform01(rng);
  }
  // The bias turns the robot evenly along the way: half before, half after.
  double bias = turn_bias_ * d;
  double rot1 = m.rot1 + 0.5 * bias +
                gaussian(rng, noise_.rot_per_rad * noise_turn(m.rot1) + 0.5 * noise_.rot_per_m * d);
  double rot2 = m.rot2 + 0.5 * bias +
                gaussian(rng, noise_.rot_per_rad * noise_turn(m.rot2) + 0.5 * noise_.rot_per_m * d);
  double heading = odom_.a + rot1;
  odom_ = {odom_.x + trans * std::cos(heading), odom_.y + trans * std::sin(heading),
           wrap_angle(heading + rot2)};
  return odom_;
}

}  // namespace troupe::desktop
