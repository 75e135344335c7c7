// learned_motion: a motion model fitted from a logged run (motion_model.h;
// train one with `troupe robocup-motion fit`). It predicts the next
// velocity from the current one and the command, one model cycle at a
// time.
//
//   motion learned_motion model="models/pioneer.motion"
//
// model: the file `fit` wrote, relative to the robot file.
#include "host-sim/robocup/plugins/learned_motion/motion_model.h"

namespace troupe::robocup::plugins {
namespace {

class LearnedMotion final : public MotionPlugin {
 public:
  bool configure(Options& o, std::string& error) override {
    const std::string file = o.path("model", "");
    if (file.empty()) o.fail("model", "name the model file: model=FILE");
    if (!o.finish(error)) return false;
    if (!MotionModel::load(file, model_, error)) {
      error = "option 'model': " + error;
      return false;
    }
    return true;
  }

  Twist drive(const MotionCommand& command, const Twist& now, double dt) override {
    // A simulation cycle that differs from the model's: step the model as
    // many of its cycles as fit, at least one.
    const int steps = std::max(1, int(std::lround(dt / model_.cycle_s())));
    Twist v = now;
    for (int i = 0; i < steps; ++i) v = model_.predict(v, command);
    return v;
  }

 private:
  MotionModel model_;
};

}  // namespace
}  // namespace troupe::robocup::plugins

TROUPE_PLUGIN_EXPORT const TroupePluginInfo* troupe_plugin_v1() {
  using namespace troupe::robocup;
  return plugin_info<MotionPlugin, plugins::LearnedMotion>(PluginKind::Motion, "learned_motion");
}
