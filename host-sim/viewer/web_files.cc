#include "host-sim/viewer/web_files.h"

namespace troupe::viewer {

std::string web_file_name(std::string_view target) {
  if (const size_t q = target.find_first_of("?#"); q != std::string_view::npos) target = target.substr(0, q);
  if (target.empty() || target[0] != '/') return {};
  target.remove_prefix(1);
  if (target.empty()) return "index.html";
  // Names the build puts there: letters, digits, '-', '_', '.'; never a
  // leading dot (no "..", no hidden files), never a slash.
  if (target.size() > 64 || target[0] == '.') return {};
  for (char c : target) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
                    c == '_' || c == '.';
    if (!ok) return {};
  }
  return std::string(target);
}

std::string_view content_type(std::string_view name) {
  auto ends = [&](std::string_view ext) {
    return name.size() >= ext.size() && name.substr(name.size() - ext.size()) == ext;
  };
  if (ends(".html")) return "text/html; charset=utf-8";
  if (ends(".js")) return "text/javascript; charset=utf-8";
  if (ends(".css")) return "text/css; charset=utf-8";
  if (ends(".png")) return "image/png";
  if (ends(".svg")) return "image/svg+xml";
  if (ends(".map") || ends(".json")) return "application/json";
  return "application/octet-stream";
}

}  // namespace troupe::viewer
