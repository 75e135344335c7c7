// omnivision: an omni-directional camera (a mirror above a camera) with
// iconic detections all around: field lines, goals, posts, ball, robots.
//
//   sensor omnivision range=5 min_range=0.1 range_noise=0 bearing_noise=0 miss=0
//                     ball=1 goals=1 posts=1 robots=1 lines=1 occlusion=1
#include "host-sim/robocup/plugins/common/vision.h"

namespace troupe::robocup::plugins {
namespace {

class OmniVision final : public SensorPlugin {
 public:
  OmniVision() {
    settings_.fov = 2 * kPi;
    settings_.lines = true;
  }
  bool configure(Options& o, std::string& error) override {
    read_vision(o, settings_);
    if (o.ok() && settings_.fov < 2 * kPi) o.fail("fov", "omni-vision sees all around; use camera for less");
    return o.finish(error);
  }
  void sense(const WorldView& world, const SensorContext& context, SensorReading& out) override {
    out.kind = ReadingKind::Detections;
    Vision(settings_, world, context, out).see_all();
  }

 private:
  VisionSettings settings_;
};

}  // namespace
}  // namespace troupe::robocup::plugins

TROUPE_PLUGIN_EXPORT const TroupePluginInfo* troupe_plugin_v1() {
  using namespace troupe::robocup;
  return plugin_info<SensorPlugin, plugins::OmniVision>(PluginKind::Sensor, "omnivision");
}
