// odometry: the robot's pose integrated from its wheel motion, with seeded
// errors that grow with the distance travelled, as real odometry drifts.
// The odometry frame starts on the robot's true pose.
//
//   sensor odometry translation_noise=0 rotation_noise=0 drift=0
//
// translation_noise: standard deviation of the travelled distance, as a
// fraction of it; rotation_noise: of the turned angle, as a fraction;
// drift: heading error per metre travelled, rad/m (standard deviation).
#include "host-sim/robocup/plugins/common/noise.h"

namespace troupe::robocup::plugins {
namespace {

class Odometry final : public SensorPlugin {
 public:
  bool configure(Options& o, std::string& error) override {
    translation_noise_ = o.number("translation_noise", 0, 0, 1);
    rotation_noise_ = o.number("rotation_noise", 0, 0, 1);
    drift_ = o.number("drift", 0, 0, 10);
    return o.finish(error);
  }

  void sense(const WorldView& world, const SensorContext& c, SensorReading& out) override {
    const RobotInfo me = world.robot(c.robot);
    out.kind = ReadingKind::Odometry;
    if (!started_) {
      started_ = true;
      last_ = me.pose;
      estimate_ = me.pose;
    }
    // The motion since the last reading, in the robot frame at its start.
    const Vec2 step = rotate(me.pose.position() - last_.position(), -last_.a);
    const double turn = wrap_angle(me.pose.a - last_.a);
    const double dist = length(step);
    const double scale = 1 + gaussian(*c.rng, translation_noise_);
    const double turn_measured =
        turn * (1 + gaussian(*c.rng, rotation_noise_)) + gaussian(*c.rng, drift_ * dist);
    const Vec2 moved = rotate(step * scale, estimate_.a);
    estimate_ = {estimate_.x + moved.x, estimate_.y + moved.y, wrap_angle(estimate_.a + turn_measured)};
    last_ = me.pose;
    out.odometry = estimate_;
    const Vec2 v = rotate(me.velocity.linear(), -me.pose.a);
    out.velocity = {v.x * scale, v.y * scale, me.velocity.w};
  }

 private:
  double translation_noise_ = 0, rotation_noise_ = 0, drift_ = 0;
  bool started_ = false;
  Pose2 last_, estimate_;
};

}  // namespace
}  // namespace troupe::robocup::plugins

TROUPE_PLUGIN_EXPORT const TroupePluginInfo* troupe_plugin_v1() {
  using namespace troupe::robocup;
  return plugin_info<SensorPlugin, plugins::Odometry>(PluginKind::Sensor, "odometry");
}
