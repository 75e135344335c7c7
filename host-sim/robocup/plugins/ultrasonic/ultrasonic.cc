// ultrasonic: a sonar transducer: the range to the nearest obstacle inside
// its cone (anything at its mount height, the ball included if tall
// enough), one value per reading.
//
//   sensor ultrasonic cone=0.5 range=3 min_range=0.05 noise=0 rays=9
//
// cone: full opening angle, rad; rays: beams traced across it.
#include "host-sim/robocup/plugins/common/noise.h"

namespace troupe::robocup::plugins {
namespace {

class Ultrasonic final : public SensorPlugin {
 public:
  bool configure(Options& o, std::string& error) override {
    cone_ = o.number("cone", 0.5, 0, kPi);
    range_ = o.number("range", 3, 0.01, 20);
    min_range_ = o.number("min_range", 0.05, 0, 20);
    noise_ = o.number("noise", 0, 0, 1);
    rays_ = int(o.integer("rays", 9, 1, 256));
    if (o.ok() && min_range_ >= range_) o.fail("min_range", "must be below range");
    return o.finish(error);
  }

  void sense(const WorldView& world, const SensorContext& c, SensorReading& out) override {
    const Pose2 sensor = world.robot(c.robot).pose.compose(c.mount);
    double nearest = range_;
    for (int i = 0; i < rays_; ++i) {
      const double a = rays_ > 1 ? -cone_ / 2 + cone_ * i / (rays_ - 1) : 0;
      RayResult hit;
      if (world.raycast(sensor.position(), sensor.a + a, range_, c.mount_z, c.robot, hit)) {
        nearest = std::min(nearest, hit.distance);
      }
    }
    if (nearest < range_) nearest = std::clamp(nearest + gaussian(*c.rng, noise_), min_range_, range_);
    out.kind = ReadingKind::Ranges;
    out.max_range = range_;
    out.angle_min = 0;
    out.angle_step = 0;
    out.ranges.assign(1, float(nearest));
  }

 private:
  double cone_ = 0.5, range_ = 3, min_range_ = 0.05, noise_ = 0;
  int rays_ = 9;
};

}  // namespace
}  // namespace troupe::robocup::plugins

TROUPE_PLUGIN_EXPORT const TroupePluginInfo* troupe_plugin_v1() {
  using namespace troupe::robocup;
  return plugin_info<SensorPlugin, plugins::Ultrasonic>(PluginKind::Sensor, "ultrasonic");
}
