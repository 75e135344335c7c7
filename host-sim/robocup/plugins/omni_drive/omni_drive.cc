// omni_drive: a three-wheel holonomic base (omni wheels 120 degrees apart,
// a common goalkeeper design). The command is turned into wheel speeds;
// each wheel has a speed and an acceleration limit, and a command no wheel
// set can follow is scaled down as a whole, so the robot keeps its
// direction of travel.
//
//   motion omni_drive radius=0.2 wheel_speed=2 wheel_accel=4 angles=1.5708,3.6652,5.7596
//
// radius: wheel distance from the centre, m; wheel_speed m/s; wheel_accel
// m/s^2; angles: wheel positions around the centre, rad.
#include <array>
#include <cmath>

#include "host-sim/robocup/api/plugin.h"
#include "host-sim/robocup/plugins/common/approach.h"

namespace troupe::robocup::plugins {
namespace {

class OmniDrive final : public MotionPlugin {
 public:
  bool configure(Options& o, std::string& error) override {
    radius_ = o.number("radius", 0.2, 0.01, 5);
    wheel_speed_ = o.number("wheel_speed", 2, 0.01, 50);
    wheel_accel_ = o.number("wheel_accel", 4, 0.01, 1000);
    std::vector<double> a = o.numbers("angles", 3);
    if (!a.empty()) std::copy(a.begin(), a.end(), angles_.begin());
    if (o.ok() && !invert()) o.fail("angles", "the three wheels must not be parallel");
    return o.finish(error);
  }

  Twist drive(const MotionCommand& cmd, const Twist& now, double dt) override {
    std::array<double, 3> target = wheels({cmd.vx, cmd.vy, cmd.w}), current = wheels(now);
    double over = 1;
    for (double u : target) over = std::max(over, std::fabs(u) / wheel_speed_);
    for (int i = 0; i < 3; ++i) current[i] = approach(current[i], target[i] / over, wheel_accel_ * dt);
    return body(current);
  }

 private:
  // Wheel i rolls along its tangent (-sin t, cos t) at distance `radius`.
  std::array<double, 3> wheels(const Twist& t) const {
    std::array<double, 3> u;
    for (int i = 0; i < 3; ++i)
      u[i] = -std::sin(angles_[i]) * t.vx + std::cos(angles_[i]) * t.vy + radius_ * t.w;
    return u;
  }
  Twist body(const std::array<double, 3>& u) const {
    Twist t;
    t.vx = inverse_[0][0] * u[0] + inverse_[0][1] * u[1] + inverse_[0][2] * u[2];
    t.vy = inverse_[1][0] * u[0] + inverse_[1][1] * u[1] + inverse_[1][2] * u[2];
    t.w = inverse_[2][0] * u[0] + inverse_[2][1] * u[1] + inverse_[2][2] * u[2];
    return t;
  }
  // Inverts the 3x3 wheel matrix by cofactors.
  bool invert() {
    double m[3][3];
    for (int i = 0; i < 3; ++i) {
      m[i][0] = -std::sin(angles_[i]);
      m[i][1] = std::cos(angles_[i]);
      m[i][2] = radius_;
    }
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    if (std::fabs(det) < 1e-9) return false;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        const int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
        inverse_[r][c] = (m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]) / det;
      }
    }
    return true;
  }

  double radius_ = 0.2, wheel_speed_ = 2, wheel_accel_ = 4;
  std::array<double, 3> angles_{kPi / 2, kPi / 2 + 2 * kPi / 3, kPi / 2 + 4 * kPi / 3};
  double inverse_[3][3] = {};
};

}  // namespace
}  // namespace troupe::robocup::plugins

TROUPE_PLUGIN_EXPORT const TroupePluginInfo* troupe_plugin_v1() {
  using namespace troupe::robocup;
  return plugin_info<MotionPlugin, plugins::OmniDrive>(PluginKind::Motion, "omni_drive");
}
