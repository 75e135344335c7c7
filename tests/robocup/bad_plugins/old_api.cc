// A plugin built for another plugin ABI version.
#include "host-sim/plugin/plugin_abi.h"

TROUPE_PLUGIN_EXPORT const TroupePluginInfo* troupe_plugin_v1() {
  static const TroupePluginInfo info{TROUPE_PLUGIN_ABI_VERSION + 1, TROUPE_PLUGIN_SENSOR, 2, "old_api", nullptr,
                                     nullptr};
  return &info;
}
