// laser: a laser range finder in the plane of its mount height. Raw mode
// traces every beam against the world (robots, ball if the beam's height
// meets it, walls, goals, posts); iconic mode reports the objects (ball,
// robots, corner posts) the beams would hit, as detections.
//
//   sensor laser mode=raw beams=181 fov=3.14159 range=8 min_range=0.02 noise=0 z=0.3
//   sensor laser mode=iconic fov=3.14159 range=8 noise=0
//
// noise: standard deviation of each range, m.
#include "host-sim/robocup/plugins/common/noise.h"

namespace troupe::robocup::plugins {
namespace {

class Laser final : public SensorPlugin {
 public:
  bool configure(Options& o, std::string& error) override {
    iconic_ = o.choice("mode", "raw", {"raw", "iconic"}) == "iconic";
    beams_ = int(o.integer("beams", 181, 1, 4096));
    fov_ = o.number("fov", kPi, 1e-3, 2 * kPi);
    range_ = o.number("range", 8, 0.01, 100);
    min_range_ = o.number("min_range", 0.02, 0, 100);
    noise_ = o.number("noise", 0, 0, 10);
    if (o.ok() && min_range_ >= range_) o.fail("min_range", "must be below range");
    return o.finish(error);
  }

  void sense(const WorldView& world, const SensorContext& c, SensorReading& out) override {
    const Pose2 sensor = world.robot(c.robot).pose.compose(c.mount);
    if (iconic_) {
      iconic(world, c, sensor, out);
      return;
    }
    out.kind = ReadingKind::Ranges;
    out.max_range = range_;
    out.angle_min = beams_ > 1 ? -fov_ / 2 : 0;
    out.angle_step = beams_ > 1 ? fov_ / (beams_ - 1) : 0;
    out.ranges.resize(size_t(beams_));
    for (int i = 0; i < beams_; ++i) {
      RayResult hit;
      double r = range_;
      if (world.raycast(sensor.position(), sensor.a + out.angle_min + i * out.angle_step, range_, c.mount_z,
                        c.robot, hit)) {
        r = std::clamp(hit.distance + gaussian(*c.rng, noise_), min_range_, range_);
      }
      out.ranges[size_t(i)] = float(r);
    }
  }

 private:
  // An object is seen when a beam towards its centre first hits it.
  void iconic(const WorldView& world, const SensorContext& c, const Pose2& sensor, SensorReading& out) {
    out.kind = ReadingKind::Detections;
    auto look = [&](ObjectKind kind, int id, Vec2 at, double yaw, int team) {
      const Vec2 local = sensor.to_local(at);
      const double bearing = std::atan2(local.y, local.x), dist = length(local);
      if (std::fabs(bearing) > fov_ / 2 || dist > range_ || dist < min_range_) return;
      RayResult hit;
      if (!world.raycast(sensor.position(), sensor.a + bearing, range_, c.mount_z, c.robot, hit)) return;
      if (hit.kind != kind || (kind != ObjectKind::Ball && hit.id != id)) return;
      const double r = dist + gaussian(*c.rng, noise_);
      Detection d;
      d.kind = kind;
      d.id = id;
      d.x = r * std::cos(bearing);
      d.y = r * std::sin(bearing);
      d.yaw = wrap_angle(yaw - sensor.a);
      d.team = team;
      out.detections.push_back(d);
    };
    look(ObjectKind::Ball, 0, world.ball().position, 0, -1);
    for (int i = 0; i < world.robot_count(); ++i) {
      if (i == c.robot) continue;
      const RobotInfo r = world.robot(i);
      look(ObjectKind::Robot, i, r.pose.position(), r.pose.a, int(r.team));
    }
    for (const Landmark& l : world.field().landmarks) {
      if (l.kind == ObjectKind::CornerPost) look(l.kind, l.id, l.position, 0, -1);
    }
  }

  bool iconic_ = false;
  int beams_ = 181;
  double fov_ = kPi, range_ = 8, min_range_ = 0.02, noise_ = 0;
};

}  // namespace
}  // namespace troupe::robocup::plugins

TROUPE_PLUGIN_EXPORT const TroupePluginInfo* troupe_plugin_v1() {
  using namespace troupe::robocup;
  return plugin_info<SensorPlugin, plugins::Laser>(PluginKind::Sensor, "laser");
}
