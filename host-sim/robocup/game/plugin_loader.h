// The plugin factory: finds troupe_robocup_<name>.so on a search path,
// loads it (dlopen), checks its entry point, API version and kind, and
// makes instances. Every failure is an error message naming the plugin;
// nothing is half-loaded.
//
// Search path, first match wins: folders the world file names
// (`plugin_path`), then $TROUPE_ROBOCUP_PLUGIN_PATH (colon-separated), then
// <folder of the running program>/plugins and
// <folder of the running program>/../lib/troupe/robocup.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "host-sim/robocup/api/plugin.h"

namespace troupe::robocup {

/// An instance made by a plugin. It keeps its library loaded and is
/// destroyed by the library that made it.
template <class T>
class PluginInstance {
 public:
  PluginInstance() = default;
  PluginInstance(std::shared_ptr<void> library, T* object, void (*destroy)(void*))
      : library_(std::move(library)), object_(object), destroy_(destroy) {}
  PluginInstance(PluginInstance&& o) noexcept { *this = std::move(o); }
  PluginInstance& operator=(PluginInstance&& o) noexcept {
    if (this != &o) {
      reset();
      library_ = std::move(o.library_);
      object_ = o.object_;
      destroy_ = o.destroy_;
      o.object_ = nullptr;
    }
    return *this;
  }
  PluginInstance(const PluginInstance&) = delete;
  PluginInstance& operator=(const PluginInstance&) = delete;
  ~PluginInstance() { reset(); }

  void reset() {
    if (object_) destroy_(static_cast<void*>(object_));
    object_ = nullptr;
    library_.reset();  // after the object: its code lives there
  }
  T* get() const { return object_; }
  T* operator->() const { return object_; }
  explicit operator bool() const { return object_ != nullptr; }

 private:
  std::shared_ptr<void> library_;
  T* object_ = nullptr;
  void (*destroy_)(void*) = nullptr;
};

class PluginLoader {
 public:
  explicit PluginLoader(std::vector<std::string> search_path = default_plugin_path());

  /// Folders searched before the current ones.
  void prepend_path(const std::vector<std::string>& dirs);
  const std::vector<std::string>& search_path() const { return path_; }

  PluginInstance<SensorPlugin> sensor(std::string_view name, std::string& error);
  PluginInstance<MotionPlugin> motion(std::string_view name, std::string& error);
  PluginInstance<PlayerPlugin> player(std::string_view name, std::string& error);

  /// $TROUPE_ROBOCUP_PLUGIN_PATH, then the folders beside the program.
  static std::vector<std::string> default_plugin_path();
  /// The library file name of a plugin: troupe_robocup_<name>.so.
  static std::string file_name(std::string_view name);

 private:
  const PluginInfo* open(std::string_view name, PluginKind kind, std::shared_ptr<void>& library,
                         std::string& error);
  template <class T>
  PluginInstance<T> make(std::string_view name, PluginKind kind, std::string& error);

  std::vector<std::string> path_;
  std::map<std::string, std::shared_ptr<void>, std::less<>> libraries_;
};

}  // namespace troupe::robocup
