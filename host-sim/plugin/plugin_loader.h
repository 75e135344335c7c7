// The one plugin loader (plugin_abi.h). One search rule, for every program
// that loads plugins:
//
//   1. folders the user names (a world's `plugin_path`, --plugin-path),
//   2. <folder of the running program>/../lib/troupe (the build tree's and
//      the installed tree's plugin folder: build/<preset>/lib/troupe,
//      <prefix>/lib/troupe),
//   3. the folders of $TROUPE_PLUGIN_PATH (colon-separated),
//   4. the world file's own folder.
//
// and one error format, "<kind> plugin 'NAME': why", for a plugin that is
// missing, is no Troupe plugin, was built for another ABI or interface
// version, or is of another kind.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "host-sim/plugin/plugin_abi.h"

namespace troupe::plugin {

inline constexpr const char* kPathVariable = "TROUPE_PLUGIN_PATH";

/// The search path: `first` (the user's folders), then the program's
/// ../lib/troupe, then $TROUPE_PLUGIN_PATH, then `world_dir` (if not empty).
std::vector<std::string> search_path(const std::vector<std::string>& first = {},
                                     const std::string& world_dir = "");

/// "controller", "sensor", "motion", "player".
const char* kind_name(uint32_t kind);

/// An instance made by a plugin: keeps its library loaded, and is destroyed
/// by the library that made it.
template <class T>
class Instance {
 public:
  Instance() = default;
  Instance(std::shared_ptr<void> library, T* object, void (*destroy)(void*))
      : library_(std::move(library)), object_(object), destroy_(destroy) {}
  Instance(Instance&& o) noexcept { *this = std::move(o); }
  Instance& operator=(Instance&& o) noexcept {
    if (this != &o) {
      reset();
      library_ = std::move(o.library_);
      object_ = o.object_;
      destroy_ = o.destroy_;
      o.object_ = nullptr;
    }
    return *this;
  }
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;
  ~Instance() { reset(); }

  void reset() {
    if (object_) destroy_(static_cast<void*>(object_));
    object_ = nullptr;
    library_.reset();  // after the object: its code lives there
  }
  T* get() const { return object_; }
  T* operator->() const { return object_; }
  T& operator*() const { return *object_; }
  explicit operator bool() const { return object_ != nullptr; }

 private:
  std::shared_ptr<void> library_;
  T* object_ = nullptr;
  void (*destroy_)(void*) = nullptr;
};

class Loader {
 public:
  explicit Loader(std::vector<std::string> path = search_path()) : path_(std::move(path)) {}

  /// Folders searched before the current ones.
  void prepend_path(const std::vector<std::string>& dirs);
  const std::vector<std::string>& path() const { return path_; }

  /// A new instance of plugin `name` of `kind`, whose interface must be
  /// `interface_version`, made from `args`. Empty with `error` ("<kind>
  /// plugin 'NAME': why") when it cannot be had.
  template <class T>
  Instance<T> make(std::string_view name, uint32_t kind, uint32_t interface_version, const char* args,
                   std::string& error) {
    std::shared_ptr<void> library;
    const TroupePluginInfo* info = open(name, kind, interface_version, library, error);
    if (!info) return {};
    void* object = info->create(args);
    if (!object) {
      error = label(name, kind) +
              (args && *args ? ": refused its arguments \"" + std::string(args) + "\"" : ": could not make an instance");
      return {};
    }
    return Instance<T>(std::move(library), static_cast<T*>(object), info->destroy);
  }

  /// True when NAME.so is on the path (or loaded already).
  bool has(std::string_view name) const;

  /// "<kind> plugin 'NAME'".
  static std::string label(std::string_view name, uint32_t kind);
  /// The library file of a plugin: NAME.so.
  static std::string file_name(std::string_view name);

 private:
  const TroupePluginInfo* open(std::string_view name, uint32_t kind, uint32_t interface_version,
                               std::shared_ptr<void>& library, std::string& error);

  std::vector<std::string> path_;
  std::map<std::string, std::shared_ptr<void>, std::less<>> libraries_;
};

}  // namespace troupe::plugin
