// camera: a directed camera with iconic detections. Sees the ball, the
// goals, goal and corner posts and other robots inside its field of view
// and range, unless something stands in between.
//
//   sensor camera fov=1.0 range=5 min_range=0.1 range_noise=0 bearing_noise=0
//                 miss=0 ball=1 goals=1 posts=1 robots=1 lines=0 occlusion=1
//                 [x= y= a= z=  (mount) period=N]
#include "host-sim/robocup/plugins/common/vision.h"

namespace troupe::robocup::plugins {
namespace {

class Camera final : public SensorPlugin {
 public:
  bool configure(Options& o, std::string& error) override {
    read_vision(o, settings_);
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
  return plugin_info<SensorPlugin, plugins::Camera>(PluginKind::Sensor, "camera");
}
