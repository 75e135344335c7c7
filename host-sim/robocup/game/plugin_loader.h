// RoboCup's typed face of the one plugin loader (host-sim/plugin): sensor,
// motion and player plugins by name, on the one search path (a world's
// `plugin_path` folders first). Every failure is an error message naming
// the plugin; nothing is half-loaded.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "host-sim/plugin/plugin_loader.h"
#include "host-sim/robocup/api/plugin.h"

namespace troupe::robocup {

template <class T>
using PluginInstance = plugin::Instance<T>;

class PluginLoader {
 public:
  explicit PluginLoader(std::vector<std::string> search_path = plugin::search_path()) : loader_(std::move(search_path)) {}

  /// Folders searched before the current ones.
  void prepend_path(const std::vector<std::string>& dirs) { loader_.prepend_path(dirs); }
  const std::vector<std::string>& search_path() const { return loader_.path(); }

  PluginInstance<SensorPlugin> sensor(std::string_view name, std::string& error) {
    return loader_.make<SensorPlugin>(name, TROUPE_PLUGIN_SENSOR, kPluginApiVersion, nullptr, error);
  }
  PluginInstance<MotionPlugin> motion(std::string_view name, std::string& error) {
    return loader_.make<MotionPlugin>(name, TROUPE_PLUGIN_MOTION, kPluginApiVersion, nullptr, error);
  }
  PluginInstance<PlayerPlugin> player(std::string_view name, std::string& error) {
    return loader_.make<PlayerPlugin>(name, TROUPE_PLUGIN_PLAYER, kPluginApiVersion, nullptr, error);
  }

 private:
  plugin::Loader loader_;
};

}  // namespace troupe::robocup
