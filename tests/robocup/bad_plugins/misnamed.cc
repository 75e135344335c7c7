// A library whose file name and declared plugin name disagree.
#include "host-sim/robocup/api/plugin.h"

namespace {
class Quiet final : public troupe::robocup::SensorPlugin {
 public:
  bool configure(troupe::robocup::Options& o, std::string& error) override { return o.finish(error); }
  void sense(const troupe::robocup::WorldView&, const troupe::robocup::SensorContext&,
             troupe::robocup::SensorReading&) override {}
};
}  // namespace

TROUPE_PLUGIN_EXPORT const TroupePluginInfo* troupe_plugin_v1() {
  using namespace troupe::robocup;
  return plugin_info<SensorPlugin, Quiet>(PluginKind::Sensor, "some_other_name");
}
