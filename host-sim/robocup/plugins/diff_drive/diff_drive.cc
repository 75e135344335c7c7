// diff_drive: a differential drive (two driven wheels, like the Pioneer
// bases of the F2000 era). Forward and turn velocities follow the command
// within speed and acceleration limits; the wheels do not slide sideways,
// so any sideways velocity (from a collision) is taken out.
//
//   motion diff_drive max_speed=2 max_turn=6 accel=2 turn_accel=12
//
// max_speed m/s, max_turn rad/s, accel m/s^2, turn_accel rad/s^2.
#include "host-sim/robocup/api/plugin.h"
#include "host-sim/robocup/plugins/common/approach.h"

namespace troupe::robocup::plugins {
namespace {

class DiffDrive final : public MotionPlugin {
 public:
  bool configure(Options& o, std::string& error) override {
    max_speed_ = o.number("max_speed", 2, 0, 20);
    max_turn_ = o.number("max_turn", 6, 0, 100);
    accel_ = o.number("accel", 2, 1e-3, 1000);
    turn_accel_ = o.number("turn_accel", 12, 1e-3, 10000);
    return o.finish(error);
  }

  Twist drive(const MotionCommand& cmd, const Twist& now, double dt) override {
    const double v = std::clamp(cmd.vx, -max_speed_, max_speed_);
    const double w = std::clamp(cmd.w, -max_turn_, max_turn_);
    return {approach(now.vx, v, accel_ * dt), 0, approach(now.w, w, turn_accel_ * dt)};
  }

 private:
  double max_speed_ = 2, max_turn_ = 6, accel_ = 2, turn_accel_ = 12;
};

}  // namespace
}  // namespace troupe::robocup::plugins

TROUPE_PLUGIN_EXPORT const TroupePluginInfo* troupe_plugin_v1() {
  using namespace troupe::robocup;
  return plugin_info<MotionPlugin, plugins::DiffDrive>(PluginKind::Motion, "diff_drive");
}
