#include "drivers/ros2/names.h"

#include <cctype>

namespace troupe::drivers::ros2 {

bool valid_ros_token(const std::string& name) {
  if (name.empty() || std::isdigit(static_cast<unsigned char>(name[0]))) return false;
  for (size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
    if (c == '_' && i + 1 < name.size() && name[i + 1] == '_') return false;
  }
  return true;
}

bool valid_ros_path(const std::string& path) {
  size_t start = 0;
  while (true) {
    const size_t slash = path.find('/', start);
    if (!valid_ros_token(path.substr(start, slash - start))) return false;
    if (slash == std::string::npos) return true;
    start = slash + 1;
  }
}

std::string suffixed(const std::string& name, uint16_t index) {
  if (index == 0) return name;
  std::string out = name;
  out += '_';
  out += std::to_string(index);
  return out;
}

std::string in_ns(const std::string& ns, const std::string& name) {
  if (ns.empty()) return name;
  std::string out = ns;
  out += '/';
  out += name;
  return out;
}

std::string topic_in_ns(const std::string& ns, const std::string& name) {
  std::string out = "/";
  out += in_ns(ns, name);
  return out;
}

}  // namespace troupe::drivers::ros2
