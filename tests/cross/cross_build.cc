#include "tests/cross/cross_build.h"

#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <cstdio>

namespace troupe::cross {
namespace {

// board.json is flat and written by boards/CMakeLists.txt: "key": "value"
// pairs and one "drivers": ["a", "b"] list; no escapes in the values.
std::string json_value(const std::string& text, const std::string& key) {
  size_t at = text.find("\"" + key + "\":");
  if (at == std::string::npos) return "";
  size_t begin = text.find('"', at + key.size() + 3);
  size_t end = begin == std::string::npos ? begin : text.find('"', begin + 1);
  return end == std::string::npos ? "" : text.substr(begin + 1, end - begin - 1);
}

std::vector<std::string> json_list(const std::string& text, const std::string& key) {
  std::vector<std::string> items;
  size_t at = text.find("\"" + key + "\":");
  size_t open = at == std::string::npos ? at : text.find('[', at);
  size_t close = open == std::string::npos ? open : text.find(']', open);
  for (size_t i = open; i != std::string::npos && i < close;) {
    size_t begin = text.find('"', i + 1);
    if (begin == std::string::npos || begin > close) break;
    size_t end = text.find('"', begin + 1);
    items.push_back(text.substr(begin + 1, end - begin - 1));
    i = end;
  }
  return items;
}

}  // namespace

std::string read_text(const std::string& path) {
  std::string text;
  FILE* f = fopen(path.c_str(), "rb");
  if (f == nullptr) return text;
  char chunk[4096];
  size_t n = 0;
  while ((n = fread(chunk, 1, sizeof chunk, f)) > 0) text.append(chunk, n);
  fclose(f);
  return text;
}

bool load_cross_build(const std::string& name, CrossBuild& out, std::string& why) {
  out = CrossBuild{};
  out.name = name;
  out.dir = std::string(TROUPE_BINARY_DIR) + "/cross/" + name;
  std::string text = read_text(out.path("board.json"));
  if (text.empty()) {
    why = "cross build " + name + " is absent (" + out.dir +
          "/board.json): its set-up step was skipped, no cross compiler?";
    return false;
  }
  out.board = json_value(text, "board");
  out.drivers = json_list(text, "drivers");
  out.triple = json_value(text, "triple");
  out.deb_arch = json_value(text, "deb_arch");
  out.qemu = json_value(text, "qemu");
  out.loader_prefix = json_value(text, "loader_prefix");
  out.sysroot_lib = json_value(text, "sysroot_lib");
  out.node = json_value(text, "node");
  out.is_static = json_value(text, "static") == "ON";
  out.strip = json_value(text, "strip");
  out.nm = json_value(text, "nm");
  out.size = json_value(text, "size");
  out.readelf = json_value(text, "readelf");
  std::string found;
  if (run("command -v " + quote(out.qemu), found) != 0) {
    why = out.qemu + " is not installed (apt-get install qemu-user)";
    return false;
  }
  return true;
}

std::string quote(const std::string& text) {
  std::string q = "'";
  for (char c : text) {
    if (c == '\'') {
      q += "'\\''";
    } else {
      q += c;
    }
  }
  return q + "'";
}

int run(const std::string& command, std::string& out) {
  out.clear();
  FILE* p = popen(command.c_str(), "r");
  if (p == nullptr) return -1;
  char chunk[4096];
  size_t n = 0;
  while ((n = fread(chunk, 1, sizeof chunk, p)) > 0) out.append(chunk, n);
  int status = pclose(p);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string make_temp_dir(const std::string& tag) {
  std::string root = std::string(TROUPE_BINARY_DIR) + "/cross/tmp";
  mkdir((std::string(TROUPE_BINARY_DIR) + "/cross").c_str(), 0755);
  mkdir(root.c_str(), 0755);
  std::string pattern = root + "/" + tag + "-XXXXXX";
  char* made = mkdtemp(pattern.data());
  return made ? std::string(made) : std::string();
}

std::string test_name_of(std::string build_name) {
  for (char& c : build_name) c = c == '-' ? '_' : c;
  return build_name;
}

}  // namespace troupe::cross
