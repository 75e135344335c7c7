#include "host-sim/robocup/game/plugin_loader.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>

namespace troupe::robocup {
namespace {

bool good_name(std::string_view name) {
  if (name.empty() || name.size() > 64) return false;
  for (char c : name) {
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')) return false;
  }
  return true;
}

bool exists(const std::string& path) {
  return access(path.c_str(), R_OK) == 0;
}

std::string program_folder() {
  char buf[4096];
  ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return "";
  std::string exe(buf, size_t(n));
  size_t slash = exe.rfind('/');
  return slash == std::string::npos ? "" : exe.substr(0, slash);
}

}  // namespace

PluginLoader::PluginLoader(std::vector<std::string> search_path) : path_(std::move(search_path)) {}

void PluginLoader::prepend_path(const std::vector<std::string>& dirs) {
  path_.insert(path_.begin(), dirs.begin(), dirs.end());
}

std::vector<std::string> PluginLoader::default_plugin_path() {
  std::vector<std::string> out;
  if (const char* env = std::getenv("TROUPE_ROBOCUP_PLUGIN_PATH")) {
    std::string s(env);
    size_t start = 0;
    while (start <= s.size()) {
      size_t colon = s.find(':', start);
      if (colon == std::string::npos) colon = s.size();
      if (colon > start) out.push_back(s.substr(start, colon - start));
      start = colon + 1;
    }
  }
  const std::string here = program_folder();
  if (!here.empty()) {
    out.push_back(here + "/plugins");
    out.push_back(here + "/../lib/troupe/robocup");
  }
  return out;
}

std::string PluginLoader::file_name(std::string_view name) {
  return "troupe_robocup_" + std::string(name) + ".so";
}

const PluginInfo* PluginLoader::open(std::string_view name, PluginKind kind, std::shared_ptr<void>& library,
                                     std::string& error) {
  const std::string label = std::string(plugin_kind_name(kind)) + " plugin '" + std::string(name) + "'";
  if (!good_name(name)) {
    error = label + ": a plugin name holds only a-z, 0-9 and _";
    return nullptr;
  }
  auto cached = libraries_.find(name);
  std::string file;
  if (cached != libraries_.end()) {
    library = cached->second;
  } else {
    for (const std::string& dir : path_) {
      if (exists(dir + "/" + file_name(name))) {
        file = dir + "/" + file_name(name);
        break;
      }
    }
    if (file.empty()) {
      std::string dirs;
      for (const std::string& dir : path_) dirs += (dirs.empty() ? "" : ", ") + dir;
      error = label + ": not found (no " + file_name(name) + " in " +
              (dirs.empty() ? "an empty path" : dirs) + ")";
      return nullptr;
    }
    dlerror();
    void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* why = dlerror();
      error = label + ": cannot load " + file + ": " + (why ? why : "unknown dlopen error");
      return nullptr;
    }
    library = std::shared_ptr<void>(handle, [](void* h) { dlclose(h); });
    libraries_.emplace(std::string(name), library);
  }
  dlerror();
  auto entry = reinterpret_cast<const PluginInfo* (*)()>(dlsym(library.get(), kPluginEntrySymbol));
  if (!entry) {
    error = label + ": its library has no " + kPluginEntrySymbol + " (not a Troupe RoboCup plugin?)";
    return nullptr;
  }
  const PluginInfo* info = entry();
  if (!info || info->api_version != kPluginApiVersion) {
    error = label + ": built for plugin API v" + std::to_string(info ? info->api_version : 0) +
            ", this simulator speaks v" + std::to_string(kPluginApiVersion);
    return nullptr;
  }
  if (info->kind != kind) {
    error = label + ": it is a " + plugin_kind_name(info->kind) + " plugin";
    return nullptr;
  }
  if (!info->name || name != info->name || !info->create || !info->destroy) {
    error = label + ": its library says it is '" + std::string(info->name ? info->name : "") + "'";
    return nullptr;
  }
  return info;
}

template <class T>
PluginInstance<T> PluginLoader::make(std::string_view name, PluginKind kind, std::string& error) {
  std::shared_ptr<void> library;
  const PluginInfo* info = open(name, kind, library, error);
  if (!info) return {};
  T* object = static_cast<T*>(info->create());
  if (!object) {
    error = std::string(plugin_kind_name(kind)) + " plugin '" + std::string(name) +
            "': could not make an instance";
    return {};
  }
  return PluginInstance<T>(std::move(library), object, info->destroy);
}

PluginInstance<SensorPlugin> PluginLoader::sensor(std::string_view name, std::string& error) {
  return make<SensorPlugin>(name, PluginKind::Sensor, error);
}

PluginInstance<MotionPlugin> PluginLoader::motion(std::string_view name, std::string& error) {
  return make<MotionPlugin>(name, PluginKind::Motion, error);
}

PluginInstance<PlayerPlugin> PluginLoader::player(std::string_view name, std::string& error) {
  return make<PlayerPlugin>(name, PluginKind::Player, error);
}

}  // namespace troupe::robocup
