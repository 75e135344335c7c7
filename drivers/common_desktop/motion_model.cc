#include "drivers/common_desktop/motion_model.h"

#include <algorithm>

namespace troupe::desktop {

OdometryMotion decompose(const Pose2& from, const Pose2& to) {
  OdometryMotion m;
  double dx = to.x - from.x, dy = to.y - from.y;
  m.trans = std::hypot(dx, dy);
  m.rot1 = m.trans < 1e-3 ? 0.0 : wrap_angle(std::atan2(dy, dx) - from.a);
  m.rot2 = wrap_angle(to.a - from.a - m.rot1);
  return m;
}

double noise_turn(double rot) {
  double a = std::fabs(wrap_angle(rot));
  return std::min(a, kPi - a);
}

Pose2 sample_motion(const Pose2& p, const OdometryMotion& m, const MotionNoise& n, Rng& rng) {
  double t1 = noise_turn(m.rot1), t2 = noise_turn(m.rot2);
  double d2 = m.trans * m.trans;
  double r1 = m.rot1 - gaussian(rng, std::sqrt(n.rot_rot * t1 * t1 + n.rot_trans * d2));
  double tr = m.trans - gaussian(rng, std::sqrt(n.trans_trans * d2 + n.trans_rot * (t1 * t1 + t2 * t2)));
  double r2 = m.rot2 - gaussian(rng, std::sqrt(n.rot_rot * t2 * t2 + n.rot_trans * d2));
  double heading = p.a + r1;
  return {p.x + tr * std::cos(heading), p.y + tr * std::sin(heading), wrap_angle(heading + r2)};
}

}  // namespace troupe::desktop
