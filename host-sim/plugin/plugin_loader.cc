#include "host-sim/plugin/plugin_loader.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>

namespace troupe::plugin {
namespace {

// A file name without folders, so a world cannot point outside the path.
bool good_name(std::string_view name) {
  if (name.empty() || name.size() > 64) return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                    c == '-';
    if (!ok) return false;
  }
  return true;
}

std::string program_folder() {
  char buf[4096];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return "";
  const std::string exe(buf, size_t(n));
  const size_t slash = exe.rfind('/');
  return slash == std::string::npos ? "" : exe.substr(0, slash);
}

}  // namespace

std::vector<std::string> search_path(const std::vector<std::string>& first, const std::string& world_dir) {
  std::vector<std::string> out = first;
  const std::string here = program_folder();
  if (!here.empty()) out.push_back(here + "/../lib/troupe");
  if (const char* env = std::getenv(kPathVariable)) {
    const std::string s(env);
    for (size_t at = 0; at <= s.size();) {
      size_t colon = s.find(':', at);
      if (colon == std::string::npos) colon = s.size();
      if (colon > at) out.push_back(s.substr(at, colon - at));
      at = colon + 1;
    }
  }
  if (!world_dir.empty()) out.push_back(world_dir);
  return out;
}

const char* kind_name(uint32_t kind) {
  switch (kind) {
    case TROUPE_PLUGIN_CONTROLLER:
      return "controller";
    case TROUPE_PLUGIN_SENSOR:
      return "sensor";
    case TROUPE_PLUGIN_MOTION:
      return "motion";
    case TROUPE_PLUGIN_PLAYER:
      return "player";
  }
  return "unknown";
}

void Loader::prepend_path(const std::vector<std::string>& dirs) {
  path_.insert(path_.begin(), dirs.begin(), dirs.end());
}

bool Loader::has(std::string_view name) const {
  if (libraries_.find(name) != libraries_.end()) return true;
  if (!good_name(name)) return false;
  for (const std::string& dir : path_) {
    if (access((dir + "/" + file_name(name)).c_str(), R_OK) == 0) return true;
  }
  return false;
}

std::string Loader::label(std::string_view name, uint32_t kind) {
  return std::string(kind_name(kind)) + " plugin '" + std::string(name) + "'";
}

std::string Loader::file_name(std::string_view name) {
  return std::string(name) + ".so";
}

const TroupePluginInfo* Loader::open(std::string_view name, uint32_t kind, uint32_t interface_version,
                                     std::shared_ptr<void>& library, std::string& error) {
  const std::string label = Loader::label(name, kind);
  if (!good_name(name)) {
    error = label + ": a plugin name holds only letters, digits, _ and -";
    return nullptr;
  }
  if (auto cached = libraries_.find(name); cached != libraries_.end()) {
    library = cached->second;
  } else {
    std::string file;
    for (const std::string& dir : path_) {
      const std::string candidate = dir + "/" + file_name(name);
      if (access(candidate.c_str(), R_OK) == 0) {
        file = candidate;
        break;
      }
    }
    if (file.empty()) {
      std::string dirs;
      for (const std::string& dir : path_) dirs += (dirs.empty() ? "" : ", ") + dir;
      error = label + ": not found (no " + file_name(name) + " in " + (dirs.empty() ? "an empty path" : dirs) +
              "; $" + kPathVariable + " adds folders)";
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
  auto entry = reinterpret_cast<const TroupePluginInfo* (*)()>(dlsym(library.get(), TROUPE_PLUGIN_ENTRY));
  if (!entry) {
    error = label + ": its library has no " + TROUPE_PLUGIN_ENTRY + " (not a Troupe plugin?)";
    return nullptr;
  }
  const TroupePluginInfo* info = entry();
  if (!info || info->abi_version != TROUPE_PLUGIN_ABI_VERSION) {
    error = label + ": built for plugin ABI v" + std::to_string(info ? info->abi_version : 0) +
            ", this program speaks v" + std::to_string(TROUPE_PLUGIN_ABI_VERSION);
    return nullptr;
  }
  if (info->kind != kind) {
    error = label + ": it is a " + kind_name(info->kind) + " plugin";
    return nullptr;
  }
  if (info->interface_version != interface_version) {
    error = label + ": built for " + kind_name(kind) + " interface v" + std::to_string(info->interface_version) +
            ", this program speaks v" + std::to_string(interface_version);
    return nullptr;
  }
  if (!info->name || name != info->name || !info->create || !info->destroy) {
    error = label + ": its library says it is '" + std::string(info->name ? info->name : "") + "'";
    return nullptr;
  }
  return info;
}

}  // namespace troupe::plugin
