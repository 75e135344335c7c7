// A plugin built for another API version.
#include "host-sim/robocup/api/plugin.h"

TROUPE_ROBOCUP_EXPORT const troupe::robocup::PluginInfo* troupe_robocup_plugin_v1() {
  static const troupe::robocup::PluginInfo info{troupe::robocup::kPluginApiVersion + 1,
                                                troupe::robocup::PluginKind::Sensor, "old_api", nullptr,
                                                nullptr};
  return &info;
}
